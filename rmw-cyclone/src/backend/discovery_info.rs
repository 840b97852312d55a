//! The `ros_discovery_info` topic on Cyclone DDS: its endpoints' USER_DATA (the QoS is
//! `qos::discovery_info`, the names [`horus_ros_dds_common::discovery_info`]).

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;

/// The USER_DATA of the `ros_discovery_info` reader and writer: rmw_cyclonedds creates them as
/// ordinary endpoints (`create_publisher` / `create_subscription`), so they carry the type hash.
pub(crate) fn discovery_info_user_data() -> String {
    use horus_ros_msgs::Message;
    ParticipantEntitiesInfo::type_hash().to_user_data()
}
