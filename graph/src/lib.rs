//! horus-ros graph cache: everything known about the ROS 2 graph, as one plain data structure.
//!
//! [`GraphCache`] follows rmw_dds_common's `GraphCache` (jazzy `include/rmw_dds_common/graph_cache.hpp`,
//! `src/graph_cache.cpp`): it is fed by events (participants and readers/writers from DDS
//! discovery, node ↔ endpoint maps from `ros_discovery_info`) and does no I/O. Mutators return
//! whether anything changed and can record typed [`GraphEvent`]s for the caller to drain.
//!
//! Queries use rcl's names with Rust types: node names, topic and service names and types,
//! names and types by node, counts, and endpoint information by topic and by service
//! ([`TopicEndpointInfo`], [`ServiceEndpointInfo`], whose `Display` matches rclpy's `__str__`).
//!
//! [`Graph`] keeps a cache up to date from a context's discovery in the background and offers
//! change notification and service readiness. [`GraphSnapshot`] carries a cache's content to
//! another process, which rebuilds an equal cache from it.

mod action_query;
mod cache;
mod endpoint;
mod endpoint_query;
mod endpoint_role;
mod error;
mod event;
mod info;
mod live;
mod query;
mod snapshot;
#[cfg(feature = "tokio")]
pub mod stream;
mod subscription;

#[cfg(test)]
mod tests;

pub use action_query::{
    filter_action_names, ActionEndpoints, ActionUser, ACTION_FEEDBACK_SUFFIX,
    ACTION_FEEDBACK_TYPE_SUFFIX,
};
pub use cache::{GraphCache, ParticipantKind, Unsettled};
pub use endpoint::{participant_gid_from_prefix, EndpointEntry, GuidPrefix};
pub use endpoint_role::{EndpointRole, RosEndpoint};
pub use error::GraphError;
pub use event::{GraphEndpoint, GraphEvent, NodeName};
pub use horus_ros_msgs::rmw_dds_common::Gid;
pub use info::{ServiceEndpointInfo, ServiceEndpointType, TopicEndpointInfo, TopicEndpointType};
pub use live::{apply_discovery_event, Graph, GraphStartError, GraphView, GraphWatcher};
pub use query::{NamesAndTypes, NodeInfo};
pub use snapshot::{GraphSnapshot, ParticipantSnapshot};
#[cfg(feature = "tokio")]
pub use stream::{GraphEvents, Lagged};
pub use subscription::{
    GraphSubscription, RecvError, SubscriptionInterrupter, SUBSCRIPTION_CAPACITY,
};

/// Node name reported for an endpoint whose participant is unknown (rmw_dds_common
/// `graph_cache.cpp`, `EndpointCreator::BARE_DDS_PARTICIPANT`); also used as its namespace.
pub const CREATED_BY_BARE_DDS_APP: &str = "_CREATED_BY_BARE_DDS_APP_";
/// Node name reported for an endpoint of a known participant that no node of it lists
/// (rmw_dds_common `EndpointCreator::UNDISCOVERED_ROS_NODE`).
pub const NODE_NAME_UNKNOWN: &str = "_NODE_NAME_UNKNOWN_";
/// Node namespace reported with [`NODE_NAME_UNKNOWN`].
pub const NODE_NAMESPACE_UNKNOWN: &str = "_NODE_NAMESPACE_UNKNOWN_";
