//! ROS 2 QoS profiles (`rmw_qos_profile_t`) and their mapping to and from DDS QoS ([`DdsQos`]).
//!
//! Follows ROS 2 Jazzy:
//! - profile layout and policy enums: rmw `include/rmw/types.h`, `include/rmw/time.h`;
//! - standard profiles: rmw `include/rmw/qos_profiles.h`, rcl `logging_rosout.h`,
//!   rcl_action `default_qos.h`;
//! - compatibility check and BEST_AVAILABLE resolution: rmw_dds_common `src/qos.cpp`
//!   (the implementation behind `rmw_qos_profile_check_compatible`);
//! - DDS mapping: rmw_cyclonedds_cpp `rmw_node.cpp` (`create_readwrite_qos`, `dds_qos_to_rmw_qos`)
//!   and rmw_fastrtps_shared_cpp `qos.cpp` / `qos.hpp`;
//! - printed form: rclpy `topic_endpoint_info.py` (`TopicEndpointInfo.__str__`), `qos.py`,
//!   `duration.py`.

mod best_available;
mod cli_format;
mod compatibility;
mod dds;
mod duration;
mod error;
mod policy;
mod profile;
mod profiles;

pub use compatibility::{check_compatible, incompatible_policies, QosCompatibility};
#[doc(hidden)]
pub use dds::{assert_dds_defaults_per_kind, unusual_profile};
pub use dds::{
    DdsDurability, DdsHistory, DdsLiveliness, DdsQos, DdsReliability, EndpointKind,
    MAX_DDS_DURATION, RELIABLE_MAX_BLOCKING_TIME,
};
pub use duration::QosDuration;
pub use error::QosError;
pub use policy::{DurabilityPolicy, HistoryPolicy, LivelinessPolicy, ReliabilityPolicy};
pub use profile::Qos;
