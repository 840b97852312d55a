//! Typed graph changes recorded by the mutators of [`GraphCache`](crate::GraphCache), at the ROS
//! level: nodes, and each DDS reader or writer with the node it belongs to, the topic or service
//! it serves and its role there.
//!
//! # Node association
//!
//! DDS discovery reports readers and writers without their node; a ROS participant tells which
//! of its endpoints belong to which node in its `ros_discovery_info` message
//! (`ParticipantEntitiesInfo`), which may arrive before or after the endpoints it lists. As
//! rmw_dds_common's graph cache (jazzy `graph_cache.cpp`,
//! `__find_name_and_namespace_from_entity_gid`) the endpoint's node is looked up in the latest
//! message of the endpoint's own participant whenever an event is built:
//!
//! - an endpoint discovered after its node's message is reported with its node
//!   ([`GraphEndpoint::node`] is `Some`);
//! - an endpoint discovered first is reported with `node: None`, and once a message lists it a
//!   [`GraphEvent::EndpointNodeChanged`] reports it again with its node (and `previous: None`);
//! - a message that moves an endpoint to another node, or that no longer lists it, reports it
//!   the same way (`node: None` when no node lists it any more).
//!
//! Events keep this order, so that every node an event names is present at that point of the
//! sequence (as rmw_zenoh's graph cache, jazzy `rmw_zenoh_cpp/src/detail/graph_cache.hpp`, keys
//! every entity by its node): a message's [`NodeAdded`](GraphEvent::NodeAdded) events come first,
//! then its [`EndpointNodeChanged`](GraphEvent::EndpointNodeChanged), then its
//! [`NodeRemoved`](GraphEvent::NodeRemoved); a lost participant's endpoints are reported removed
//! (with their nodes) before its nodes.
//!
//! # Endpoints that are not ROS
//!
//! Every DDS reader and writer is reported, ROS or not, so that a consumer can see the whole
//! DDS graph: an endpoint on a topic that does not follow ROS's mangling (`ros_discovery_info`,
//! a bare DDS application's topic) has [`GraphEndpoint::ros`] `None` (and, no node listing it,
//! `node: None`). A consumer that shows the ROS graph skips those.

use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::{EndpointKind, Qos};

use crate::RosEndpoint;

/// A node by name and namespace, as its participant's `ros_discovery_info` lists it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeName {
    /// Node name.
    pub name: String,
    /// Node namespace.
    pub namespace: String,
}

/// One DDS reader or writer as the graph's events report it: what it is to ROS and what it
/// carries (the fields of rmw's `rmw_topic_endpoint_info_t`, plus its DDS identity).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GraphEndpoint {
    /// The node it belongs to; `None` while no node of its participant lists it (see the
    /// module's node association).
    pub node: Option<NodeName>,
    /// Its role and the ROS topic or service name it serves (demangled, e.g. `/chatter`,
    /// `/add_two_ints`); `None` for a DDS topic that is not ROS (e.g. `ros_discovery_info`).
    pub ros: Option<RosEndpoint>,
    /// Its GID (its DDS GUID).
    pub gid: Gid,
    /// Reader or writer.
    pub kind: EndpointKind,
    /// Its DDS topic name (e.g. `rt/chatter`, `rq/add_two_intsRequest`).
    pub dds_topic: String,
    /// Its DDS type name (e.g. `std_msgs::msg::dds_::String_`).
    pub dds_type: String,
    /// Its ROS type: for a publisher or subscription (or a non-ROS endpoint) the message type as
    /// [`TopicEndpointInfo::topic_type`](crate::TopicEndpointInfo::topic_type) gives it
    /// (`pkg/msg/Name`); for one of a service's endpoints the service type as
    /// [`ServiceEndpointInfo::service_type`](crate::ServiceEndpointInfo::service_type) gives it
    /// (`pkg/srv/Name`). A type that does not demangle as a service type is given as a message
    /// type would be, and one that does not demangle at all is its DDS type name.
    pub type_name: String,
    /// Its own type hash from USER_DATA ([`TypeHash::ZERO`] if absent): for a service's endpoint
    /// the hash of its request or response type.
    pub type_hash: TypeHash,
    /// Its QoS as discovered.
    pub qos: Qos,
}

/// One change of the graph (see the module documentation for node association and order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GraphEvent {
    /// A node appeared in a participant's `ros_discovery_info`.
    NodeAdded {
        /// Node name.
        name: String,
        /// Node namespace.
        namespace: String,
    },
    /// A node left its participant's `ros_discovery_info`, or its participant was lost.
    NodeRemoved {
        /// Node name.
        name: String,
        /// Node namespace.
        namespace: String,
    },
    /// A reader or writer was discovered (or what was known of its GID changed: reported as the
    /// old one removed, then this one added).
    EndpointAdded(GraphEndpoint),
    /// A reader or writer was lost (by itself or with its participant), as it last was.
    EndpointRemoved(GraphEndpoint),
    /// A known reader's or writer's node changed: a `ros_discovery_info` message listed it for
    /// the first time, moved it to another node, or no longer lists it.
    EndpointNodeChanged {
        /// The endpoint, with its new node.
        endpoint: GraphEndpoint,
        /// The node it was reported with before.
        previous: Option<NodeName>,
    },
}
