//! What DDS discovery tells about one reader or writer.

use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::{EndpointKind, Qos};

/// The 12-byte GUID prefix shared by a participant and all its entities.
pub type GuidPrefix = [u8; 12];

/// Entity id of a DDS participant (`ENTITYID_PARTICIPANT` = `00 00 01 c1`, DDSI-RTPS 9.3.1.2).
const ENTITYID_PARTICIPANT: [u8; 4] = [0x00, 0x00, 0x01, 0xc1];

/// The participant GID (as carried by `ParticipantEntitiesInfo.gid`) of a GUID prefix.
pub fn participant_gid_from_prefix(prefix: GuidPrefix) -> Gid {
    let mut data = [0u8; 16];
    data[..12].copy_from_slice(&prefix);
    data[12..].copy_from_slice(&ENTITYID_PARTICIPANT);
    Gid::from_bytes(data)
}

/// One discovered (or local) DDS reader or writer, as given to
/// [`GraphCache::add_entity`](crate::GraphCache::add_entity).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct EndpointEntry {
    /// The endpoint's GID (its DDS GUID).
    pub gid: Gid,
    /// The GID of its participant; only its GUID prefix is used to find the participant.
    pub participant_gid: Gid,
    /// The DDS topic name, e.g. `rt/chatter` or `rq/add_two_intsRequest`.
    pub dds_topic_name: String,
    /// The DDS type name, e.g. `std_msgs::msg::dds_::String_`.
    pub dds_type_name: String,
    /// The endpoint's QoS as discovered.
    pub qos: Qos,
    /// The type hash from USER_DATA, [`TypeHash::ZERO`] if absent.
    #[serde(with = "crate::snapshot::optional_type_hash")]
    pub type_hash: TypeHash,
    /// Reader or writer.
    pub kind: EndpointKind,
}

impl EndpointEntry {
    /// The GUID prefix of the endpoint's participant.
    pub fn participant_prefix(&self) -> GuidPrefix {
        self.participant_gid.prefix()
    }
}
