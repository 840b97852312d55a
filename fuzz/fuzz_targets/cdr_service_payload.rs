//! A service request or response payload of a compiled type (selector byte, CDR with header).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_msgs::fuzzing::service_payload(data));
