//! A `~/get_type_description` response, a bare TypeDescription, a request (CDR with header).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_msgs::fuzzing::type_description(data));
