//! The CLI's YAML arguments filled into a compiled type, then encoded.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_dynamic::fuzzing::yaml(data));
