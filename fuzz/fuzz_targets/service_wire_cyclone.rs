//! rmw_cyclonedds' request/reply convention: 16-byte header in the body, then the message.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_services::fuzzing::cyclone(data));
