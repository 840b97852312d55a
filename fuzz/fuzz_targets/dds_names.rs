//! DDS topic and type names from SEDP, demangled.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_rmw::fuzzing::dds_names(data));
