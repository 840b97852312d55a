//! rmw_fastrtps' request/reply convention: plain bodies, horus-ros error replies.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_services::fuzzing::fastrtps(data));
