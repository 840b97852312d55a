//! [`Gid`]: the 16-byte global id of a participant or endpoint (Jazzy's `rmw_gid_t` payload).
//!
//! On DDS a GID is the entity's GUID: 12-byte prefix + 4-byte entity id. It prints as ros2cli
//! prints GIDs: `01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04`.

pub use horus_ros_msgs::rmw_dds_common::{Gid, GID_LENGTH};
