//! Fully-qualified ROS 2 service names.
//!
//! rmw validates service names with the topic rules
//! (`rmw_validate_full_topic_name`, called from rmw_fastrtps_cpp
//! `rmw_service.cpp`/`rmw_client.cpp` and rmw_cyclonedds_cpp `rmw_node.cpp`,
//! jazzy), so the error type is shared with [`TopicName`](super::TopicName).

use super::macros::impl_validated_name;
use super::topic_name::{validate_full_topic_name, TopicNameError};

/// Why a string is not a valid service name: the topic-name rules apply.
pub type ServiceNameError = TopicNameError;

/// A fully-qualified service name valid per `rmw_validate_full_topic_name`,
/// e.g. `/add_two_ints`. Distinct from [`TopicName`](super::TopicName) so the
/// two cannot be mixed up.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ServiceName(pub(super) String);

impl ServiceName {
    /// Validates `name` (already fully qualified) and wraps it.
    pub fn new(name: &str) -> Result<Self, ServiceNameError> {
        validate_full_topic_name(name)?;
        Ok(Self(name.to_owned()))
    }

    /// Whether the name is hidden: any `/`-token starts with `_`.
    pub fn is_hidden(&self) -> bool {
        super::hidden::is_hidden_name(&self.0)
    }
}

impl_validated_name!(ServiceName, ServiceNameError);
