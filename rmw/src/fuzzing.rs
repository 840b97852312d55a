//! Fuzzing entry points for what rmw reads from discovery data: each takes arbitrary bytes and
//! panics only on a bug (called by the `fuzz/` targets and `tests/fuzz_discovery_data.rs`).

use horus_ros_msgs::user_data::{parse_key_value, parse_type_hash_from_user_data};

use crate::names::{DemangledTopic, RosTypeName, ServiceTypeRole};
use horus_ros_rmw_rustdds::user_data_octets;

/// An endpoint's or participant's USER_DATA as rustdds reports it (the raw PID_USER_DATA value,
/// or bare octets): the octets are extracted as the discovery feed does, then read for a type
/// hash and an enclave as both backends' feeds do.
///
/// The octets, written back as a `sequence<octet>` parameter value (length, octets, padding),
/// must be extracted unchanged.
pub fn user_data(data: &[u8]) {
    let octets = user_data_octets(data);
    let mut parameter = Vec::with_capacity(octets.len() + 8);
    let len = u32::try_from(octets.len()).expect("fuzz inputs are shorter than 4 GiB");
    parameter.extend_from_slice(&len.to_le_bytes());
    parameter.extend_from_slice(octets);
    parameter.resize(parameter.len().next_multiple_of(4), 0);
    assert_eq!(user_data_octets(&parameter), octets);
    let _ = parse_type_hash_from_user_data(octets);
    let kv = parse_key_value(octets);
    let _ = kv
        .get("enclave")
        .map(|v| String::from_utf8_lossy(v).into_owned());
}

/// A DDS topic name and a DDS type name from SEDP (the input split at its first NUL; not UTF-8 →
/// nothing to do, as rustdds hands over Rust strings): demangled as the discovery feed and graph
/// do; every ROS name found must mangle back to the input, every type name to a DDS name that
/// demangles to it.
pub fn dds_names(data: &[u8]) {
    let (topic, type_name) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, data),
    };
    if let Ok(topic) = std::str::from_utf8(topic) {
        match DemangledTopic::from_dds_topic_name(topic) {
            DemangledTopic::Topic(t) => assert_eq!(t.to_dds_topic_name(false), topic),
            DemangledTopic::ServiceRequest(s) => {
                assert_eq!(s.to_dds_request_topic_name(false), topic);
            }
            DemangledTopic::ServiceReply(s) => assert_eq!(s.to_dds_reply_topic_name(false), topic),
            DemangledTopic::NotRos => {}
        }
    }
    if let Ok(type_name) = std::str::from_utf8(type_name) {
        if let Ok(t) = RosTypeName::from_dds_type_name(type_name) {
            assert_eq!(
                RosTypeName::from_dds_type_name(&t.to_dds_type_name()),
                Ok(t)
            );
        }
        if let Ok((t, role)) = RosTypeName::from_dds_service_type_name(type_name) {
            assert_eq!(
                RosTypeName::from_dds_service_type_name(&t.to_dds_service_type_name(role)),
                Ok((t.clone(), role))
            );
            let other = match role {
                ServiceTypeRole::Request => ServiceTypeRole::Response,
                ServiceTypeRole::Response => ServiceTypeRole::Request,
            };
            assert_eq!(
                RosTypeName::from_dds_service_type_name(&t.to_dds_service_type_name(other)),
                Ok((t, other))
            );
        }
        let _ = horus_ros_msgs::ros_type_name_from_dds(type_name);
    }
}
