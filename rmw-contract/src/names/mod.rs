//! ROS 2 names: validated node names, namespaces, topic and service names,
//! rcl-style expansion, hidden names, and the DDS mangling of names and types
//! that Jazzy's RMW implementations use on the wire.
//!
//! Each rule is ported from the ROS 2 Jazzy sources cited in its file (rmw
//! `validate_*.c`, rcl `expand_topic_name.c` / `validate_topic_name.c`,
//! rmw_fastrtps_shared_cpp `namespace_prefix.cpp` / `demangle.cpp`,
//! rmw_cyclonedds_cpp `rmw_node.cpp`).
//!
//! ```
//! use horus_ros_rmw_contract::names::{Namespace, NodeName, TopicName};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let node = NodeName::new("talker")?;
//! let ns = Namespace::new("/robot1")?;
//! let topic = TopicName::expand("~/status", &node, &ns)?;
//! assert_eq!(topic.as_str(), "/robot1/talker/status");
//! assert_eq!(topic.to_dds_topic_name(false), "rt/robot1/talker/status");
//! # Ok(())
//! # }
//! ```

mod macros;

mod dds_type_name;
mod demangle;
mod expand;
mod fq_node_name;
mod hidden;
mod mangle;
mod namespace;
mod node_name;
mod service_name;
mod topic_name;
mod type_name;
mod unexpanded;

#[cfg(test)]
mod tests;

pub use dds_type_name::{DdsTypeNameError, ServiceTypeRole};
pub use demangle::DemangledTopic;
pub use expand::{expand_name, ExpandError};
pub use fq_node_name::{FqNodeNameError, FullyQualifiedNodeName};
pub use hidden::{is_hidden_name, HIDDEN_PREFIX};
pub use mangle::{
    ROS_SERVICE_REQUESTER_PREFIX, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX, SERVICE_REQUEST_SUFFIX,
};
pub use namespace::{validate_namespace, Namespace, NamespaceError, NAMESPACE_MAX_LENGTH};
pub use node_name::{validate_node_name, NodeName, NodeNameError, NODE_NAME_MAX_LENGTH};
pub use service_name::{ServiceName, ServiceNameError};
pub use topic_name::{
    validate_full_topic_name, TopicName, TopicNameError, DDS_TOPIC_NAME_MAX_LENGTH,
    TOPIC_NAME_MAX_LENGTH,
};
pub use type_name::{InterfaceKind, RosTypeName, RosTypeNameError};
pub use unexpanded::{validate_unexpanded_name, UnexpandedNameError};
