//! USER_DATA as rustdds reports it (PID value or bare octets), enclave and type hash.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_rmw::fuzzing::user_data(data));
