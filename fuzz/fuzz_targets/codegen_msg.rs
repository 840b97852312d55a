//! A kind byte (`m`, `s`, `a`) then a `.msg`/`.srv`/`.action` file's text, parsed.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_codegen::fuzzing::msg(data));
