//! What DDS discovery and `ros_discovery_info` report, in our own types: the input of the graph
//! cache. Obtained from `Context::discovery_feed`.

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use horus_ros_msgs::TypeHash;

use crate::qos::{EndpointKind, Qos};
use crate::Gid;

/// The RTPS vendor id of a participant (who implemented its DDS stack).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VendorId(pub [u8; 2]);

impl VendorId {
    /// eProsima Fast DDS (rmw_fastrtps).
    pub const FAST_DDS: Self = Self([0x01, 0x0f]);
    /// Eclipse Cyclone DDS (rmw_cyclonedds).
    pub const CYCLONE_DDS: Self = Self([0x01, 0x10]);
    /// RustDDS (horus-ros, ros2-client).
    pub const RUSTDDS: Self = Self([0x01, 0x12]);
    /// Not an RTPS vendor: the participants of the Zenoh backend's graph (one per Zenoh
    /// session, `ZN`), so that nothing takes them for a DDS implementation's.
    pub const ZENOH: Self = Self([0x5a, 0x4e]);
}

/// A participant found by SPDP.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DiscoveredParticipant {
    /// Its GID (GUID prefix + entity id `00 00 01 c1`).
    pub gid: Gid,
    /// Who implemented its DDS stack.
    pub vendor_id: VendorId,
    /// Its security enclave, from its USER_DATA `enclave=…;` (rmw_cyclonedds and rmw_fastrtps
    /// announce it); `None` when not told (the rustdds backend cannot read participant USER_DATA).
    pub enclave: Option<String>,
}

/// A reader or writer found by SEDP (or created locally).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DiscoveredEndpoint {
    /// The endpoint's GID (its GUID).
    pub gid: Gid,
    /// The GID of the participant it belongs to.
    pub participant_gid: Gid,
    /// Reader or writer.
    pub kind: EndpointKind,
    /// The DDS topic name (mangled: `rt/…`, `rq/…Request`, `rr/…Reply`, or a plain DDS name).
    pub dds_topic_name: String,
    /// The DDS type name (`pkg::msg::dds_::Name_`, …).
    pub dds_type_name: String,
    /// Its QoS as discovery tells it (history UNKNOWN: depth is not carried by discovery).
    pub qos: Qos,
    /// The RIHS01 type hash from its USER_DATA (`typehash=…;`), or [`TypeHash::ZERO`].
    pub type_hash: TypeHash,
    /// Its raw USER_DATA.
    pub user_data: Vec<u8>,
}

/// One thing discovery learnt.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DiscoveryEvent {
    /// A participant appeared.
    ParticipantDiscovered(DiscoveredParticipant),
    /// A participant left or its lease expired; its endpoints are gone with it.
    ParticipantLost {
        /// Its GID.
        gid: Gid,
    },
    /// A reader or writer appeared.
    EndpointDiscovered(DiscoveredEndpoint),
    /// A reader or writer went away.
    EndpointLost {
        /// Its GID.
        gid: Gid,
        /// Reader or writer.
        kind: EndpointKind,
    },
    /// Another participant's `ros_discovery_info` message (its nodes and their endpoints).
    ParticipantEntities(ParticipantEntitiesInfo),
    /// One of our endpoints was matched with another (remote or of this participant): data
    /// written by the writer of the pair now reaches the reader. The match ends when either
    /// endpoint is lost.
    Matched {
        /// Our endpoint.
        local: Gid,
        /// The endpoint it was matched with.
        remote: Gid,
    },
}
