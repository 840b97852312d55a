//! Typed graph changes recorded by the mutators of [`GraphCache`](crate::GraphCache).

use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::EndpointKind;

use crate::RosEndpoint;

/// One change of the graph.
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
    /// A reader or writer was discovered.
    EndpointAdded {
        /// Its GID.
        gid: Gid,
        /// Reader or writer.
        kind: EndpointKind,
        /// Its DDS topic name (e.g. `rt/chatter`).
        topic: String,
        /// What it is to ROS, and the ROS name it serves (`None`: not a ROS topic, e.g.
        /// `ros_discovery_info`).
        ros: Option<RosEndpoint>,
        /// Its type as the graph's queries give it (`pkg/msg/Name` demangled from the DDS type
        /// name, as [`TopicEndpointInfo::topic_type`](crate::TopicEndpointInfo::topic_type)).
        type_name: String,
        /// Its type hash from USER_DATA ([`TypeHash::ZERO`] if absent).
        type_hash: TypeHash,
    },
    /// A reader or writer was lost (by itself or with its participant).
    EndpointRemoved {
        /// Its GID.
        gid: Gid,
        /// Reader or writer.
        kind: EndpointKind,
        /// Its DDS topic name.
        topic: String,
        /// What it was to ROS, and the ROS name it served.
        ros: Option<RosEndpoint>,
        /// Its type as the graph's queries gave it.
        type_name: String,
        /// Its type hash from USER_DATA ([`TypeHash::ZERO`] if absent).
        type_hash: TypeHash,
    },
}
