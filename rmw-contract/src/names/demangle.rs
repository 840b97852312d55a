//! DDS topic names back to ROS names.
//!
//! Follows rmw_fastrtps_shared_cpp `src/demangle.cpp` (`_demangle_if_ros_topic`,
//! `_demangle_service_from_topic`, `_demangle_service_request_from_topic`,
//! `_demangle_service_reply_from_topic`) and `src/namespace_prefix.cpp`
//! (`_resolve_prefix`), jazzy. Unlike those, the result must also be a valid
//! fully-qualified name, or the topic counts as not ROS.

use super::mangle::{
    ROS_SERVICE_REQUESTER_PREFIX, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX, SERVICE_REQUEST_SUFFIX,
};
use super::service_name::ServiceName;
use super::topic_name::TopicName;

/// What a DDS topic name carries, by its ROS prefix.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum DemangledTopic {
    /// `rt/<topic>`: a ROS topic.
    Topic(TopicName),
    /// `rq/<service>Request`: requests of a ROS service.
    ServiceRequest(ServiceName),
    /// `rr/<service>Reply`: replies of a ROS service.
    ServiceReply(ServiceName),
    /// No ROS prefix, a service topic without its suffix, or an invalid name
    /// (e.g. `ros_discovery_info`).
    NotRos,
}

impl DemangledTopic {
    /// Classifies and demangles a DDS topic name.
    pub fn from_dds_topic_name(dds_topic: &str) -> Self {
        if let Some(name) = strip_ros_prefix(dds_topic, ROS_TOPIC_PREFIX) {
            return TopicName::new(name).map_or(Self::NotRos, Self::Topic);
        }
        if let Some(name) =
            service_from_topic(dds_topic, ROS_SERVICE_RESPONSE_PREFIX, SERVICE_REPLY_SUFFIX)
        {
            return ServiceName::new(name).map_or(Self::NotRos, Self::ServiceReply);
        }
        if let Some(name) = service_from_topic(
            dds_topic,
            ROS_SERVICE_REQUESTER_PREFIX,
            SERVICE_REQUEST_SUFFIX,
        ) {
            return ServiceName::new(name).map_or(Self::NotRos, Self::ServiceRequest);
        }
        Self::NotRos
    }

    /// The service name of a request or reply topic.
    pub fn service_name(&self) -> Option<&ServiceName> {
        match self {
            Self::ServiceRequest(name) | Self::ServiceReply(name) => Some(name),
            Self::Topic(_) | Self::NotRos => None,
        }
    }

    /// The topic name of an `rt/` topic.
    pub fn topic_name(&self) -> Option<&TopicName> {
        match self {
            Self::Topic(name) => Some(name),
            _ => None,
        }
    }
}

/// `_resolve_prefix`: `name` without `prefix` when it starts with `prefix/`
/// (the `/` is kept, as it begins the ROS name).
fn strip_ros_prefix<'a>(name: &'a str, prefix: &str) -> Option<&'a str> {
    let rest = name.strip_prefix(prefix)?;
    rest.starts_with('/').then_some(rest)
}

/// `_demangle_service_from_topic`: prefix stripped and `suffix` at the very end.
fn service_from_topic<'a>(name: &'a str, prefix: &str, suffix: &str) -> Option<&'a str> {
    strip_ros_prefix(name, prefix)?.strip_suffix(suffix)
}
