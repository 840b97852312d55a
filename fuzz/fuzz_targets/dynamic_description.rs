//! A peer's type description turned into a schema, then a body decoded with it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_dynamic::fuzzing::description(data));
