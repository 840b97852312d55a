//! ROS names to DDS topic names.
//!
//! Prefixes from rmw_fastrtps_shared_cpp `src/namespace_prefix.cpp` and
//! rmw_cyclonedds_cpp `src/namespace_prefix.hpp`; joined as rmw_fastrtps_shared_cpp
//! `names.hpp` `_create_topic_name` and rmw_cyclonedds_cpp `rmw_node.cpp`
//! `make_fqtopic` do (jazzy): `avoid_ros_namespace_conventions` drops the
//! prefix but keeps the suffix.

use super::service_name::ServiceName;
use super::topic_name::TopicName;

/// Prefix of DDS topics carrying ROS topics (`ros_topic_prefix`).
pub const ROS_TOPIC_PREFIX: &str = "rt";
/// Prefix of DDS topics carrying service requests (`ros_service_requester_prefix`).
pub const ROS_SERVICE_REQUESTER_PREFIX: &str = "rq";
/// Prefix of DDS topics carrying service replies (`ros_service_response_prefix`).
pub const ROS_SERVICE_RESPONSE_PREFIX: &str = "rr";
/// Suffix of service request topics.
pub const SERVICE_REQUEST_SUFFIX: &str = "Request";
/// Suffix of service reply topics.
pub const SERVICE_REPLY_SUFFIX: &str = "Reply";

/// `prefix + name + suffix`, or `name + suffix` when avoiding ROS conventions.
fn make_fqtopic(prefix: &str, name: &str, suffix: &str, avoid_ros_conventions: bool) -> String {
    if avoid_ros_conventions {
        format!("{name}{suffix}")
    } else {
        format!("{prefix}{name}{suffix}")
    }
}

impl TopicName {
    /// The DDS topic name: `rt/<name>`, or `<name>` when
    /// `avoid_ros_namespace_conventions` is set.
    pub fn to_dds_topic_name(&self, avoid_ros_namespace_conventions: bool) -> String {
        make_fqtopic(
            ROS_TOPIC_PREFIX,
            self.as_str(),
            "",
            avoid_ros_namespace_conventions,
        )
    }
}

impl ServiceName {
    /// The DDS request topic: `rq/<name>Request` (`<name>Request` when
    /// `avoid_ros_namespace_conventions` is set).
    pub fn to_dds_request_topic_name(&self, avoid_ros_namespace_conventions: bool) -> String {
        make_fqtopic(
            ROS_SERVICE_REQUESTER_PREFIX,
            self.as_str(),
            SERVICE_REQUEST_SUFFIX,
            avoid_ros_namespace_conventions,
        )
    }

    /// The DDS reply topic: `rr/<name>Reply` (`<name>Reply` when
    /// `avoid_ros_namespace_conventions` is set).
    pub fn to_dds_reply_topic_name(&self, avoid_ros_namespace_conventions: bool) -> String {
        make_fqtopic(
            ROS_SERVICE_RESPONSE_PREFIX,
            self.as_str(),
            SERVICE_REPLY_SUFFIX,
            avoid_ros_namespace_conventions,
        )
    }
}
