//! The rustdds backend: everything that touches rustdds lives below this module, so the rest of
//! horus-ros sees only our own types (a second backend can sit beside it).

pub(crate) mod discovery_feed;
pub(crate) mod discovery_info;
pub(crate) mod participant;
pub(crate) mod raw;

use horus_ros_msgs::rmw_dds_common::Gid;
use rustdds::GUID;

/// The GID of a DDS entity: its 16-byte GUID (12-byte prefix + 4-byte entity id), as rmw_dds_common
/// `convert_gid_to_message` / rmw_cyclonedds `convert_guid_to_gid` fill Jazzy's 16-byte GID.
pub(crate) fn gid_from_guid(guid: GUID) -> Gid {
    Gid::from_bytes(guid.to_bytes())
}

/// The DDS GUID a GID stands for.
pub(crate) fn guid_from_gid(gid: Gid) -> rustdds::GUID {
    rustdds::GUID::from_bytes(*gid.as_bytes())
}
