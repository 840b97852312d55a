//! USER_DATA `key=value;` octets and the `typehash=` entry.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_msgs::fuzzing::user_data(data));
