//! The shared DDS layer: what both DDS backends (horus-ros-rmw-rustdds, horus-ros-rmw-cyclone)
//! and the context above them do the same way, written once — the way rmw_dds_common is shared
//! by rmw_fastrtps and rmw_cyclonedds.
//!
//! - [`discovery_info`]: the `ros_discovery_info` topic's name, type and QoS facts.
//! - [`entities`]: a participant's nodes and the endpoints listed under each, as
//!   rmw_dds_common's `GraphCache` keeps them for the local participant; every change gives the
//!   whole `ParticipantEntitiesInfo` to publish.
//! - [`late_joiner`]: when a feed renews its extra `ros_discovery_info` reader, for peers whose
//!   TRANSIENT_LOCAL sample never reached us, and the reader handling both feeds share (each
//!   backend gives only its DDS calls, as an `InfoReaderSource`).
//!
//! Topic mangling (`rt/`, `rq/`, `rr/`) lives in the contract's `names`, the two request/reply
//! conventions in horus-ros-rmw's `service`: both are written against the backend contract's raw
//! readers and writers, so any backend speaks them.

pub mod discovery_info;
pub mod entities;
pub mod late_joiner;

use horus_ros_rmw_contract::{discovery, qos, Gid, VendorId};
