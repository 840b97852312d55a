//! The `ros_discovery_info` topic: where each participant tells which nodes own which endpoints.
//!
//! Topic and QoS as rmw_cyclonedds_cpp `rmw_node.cpp` (`rmw_context_impl_s::init`, jazzy) and
//! rmw_fastrtps_shared_cpp `participant.cpp` create them: no `rt/` prefix
//! (avoid_ros_namespace_conventions), type `rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_`;
//! the writer RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1, readers RELIABLE, TRANSIENT_LOCAL,
//! KEEP_ALL, ignoring their own participant. Each backend creates them with its own DDS calls
//! (`rustdds/discovery_info.rs`, `cyclone/qos.rs`).

/// The DDS topic name.
pub const TOPIC_NAME: &str = "ros_discovery_info";
/// The DDS type name.
pub const TYPE_NAME: &str = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";
