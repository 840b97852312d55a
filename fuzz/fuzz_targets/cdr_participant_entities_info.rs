//! A `ros_discovery_info` sample (ParticipantEntitiesInfo, CDR with header).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| horus_ros_msgs::fuzzing::participant_entities_info(data));
