//! The CLI's dynamic CDR codec on a compiled type's description, and its printers.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_dynamic::fuzzing::cdr(data));
