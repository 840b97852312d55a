//! ROS 2 interface types for horus-ros.

pub mod rmw_dds_common;
