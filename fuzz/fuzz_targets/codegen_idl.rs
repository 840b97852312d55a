//! An `.idl` file's text, parsed into the interface model.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_codegen::fuzzing::idl(data));
