//! `rmw_dds_common` (Jazzy): the node ↔ endpoint map every participant publishes on
//! `ros_discovery_info`.
//!
//! Layouts from rmw_dds_common (jazzy) `msg/Gid.msg`, `msg/NodeEntitiesInfo.msg`,
//! `msg/ParticipantEntitiesInfo.msg`. Jazzy's `Gid` is `char[16]` (Humble had 24 bytes).

use serde::{Deserialize, Serialize};
use std::fmt;

/// Length of a Jazzy GID in bytes (`RMW_GID_STORAGE_SIZE` = 16 in Jazzy).
pub const GID_LENGTH: usize = 16;

/// `rmw_dds_common/msg/Gid`: a 16-byte global identifier (a DDS GUID: 12-byte prefix + 4-byte entity id).
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize)]
pub struct Gid {
    /// The raw bytes.
    pub data: [u8; GID_LENGTH],
}

impl Gid {
    /// A GID from its 16 raw bytes.
    pub const fn from_bytes(data: [u8; GID_LENGTH]) -> Self {
        Self { data }
    }

    /// The raw bytes.
    pub const fn as_bytes(&self) -> &[u8; GID_LENGTH] {
        &self.data
    }

    /// The 12-byte GUID prefix (the participant part).
    pub fn prefix(&self) -> [u8; 12] {
        let mut p = [0u8; 12];
        p.copy_from_slice(&self.data[..12]);
        p
    }
}

/// Prints the GID as ros2cli does: dotted lower-case hex, `01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04`.
impl fmt::Display for Gid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, b) in self.data.iter().enumerate() {
            if i > 0 {
                f.write_str(".")?;
            }
            write!(f, "{b:02x}")?;
        }
        Ok(())
    }
}

impl fmt::Debug for Gid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Gid({self})")
    }
}

/// `rmw_dds_common/msg/NodeEntitiesInfo`: one node and the GIDs of its readers and writers.
#[derive(Clone, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct NodeEntitiesInfo {
    /// `string<=256 node_namespace`.
    pub node_namespace: String,
    /// `string<=256 node_name`.
    pub node_name: String,
    /// GIDs of the node's data readers.
    pub reader_gid_seq: Vec<Gid>,
    /// GIDs of the node's data writers.
    pub writer_gid_seq: Vec<Gid>,
}

/// `rmw_dds_common/msg/ParticipantEntitiesInfo`: what one participant publishes on `ros_discovery_info`.
#[derive(Clone, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct ParticipantEntitiesInfo {
    /// The participant's GID (GUID prefix + entity id `00 00 01 c1`).
    pub gid: Gid,
    /// Every node of the participant.
    pub node_entities_info_seq: Vec<NodeEntitiesInfo>,
}

impl crate::Message for Gid {
    const TYPE_NAME: &'static str = "rmw_dds_common/msg/Gid";

    /// `char[16] data`: rosidl maps `.msg` `char` to `uint8`, so `UINT8_ARRAY` of 16.
    fn type_description() -> crate::TypeDescription {
        crate::DescriptionBuilder::new(Self::TYPE_NAME)
            .field::<[u8; GID_LENGTH]>("data")
            .build()
    }
}

impl crate::Message for NodeEntitiesInfo {
    const TYPE_NAME: &'static str = "rmw_dds_common/msg/NodeEntitiesInfo";

    fn type_description() -> crate::TypeDescription {
        crate::DescriptionBuilder::new(Self::TYPE_NAME)
            .field_with::<String>("node_namespace", |t| t.bounded_string(256))
            .field_with::<String>("node_name", |t| t.bounded_string(256))
            .field::<Vec<Gid>>("reader_gid_seq")
            .field::<Vec<Gid>>("writer_gid_seq")
            .build()
    }
}

impl crate::Message for ParticipantEntitiesInfo {
    const TYPE_NAME: &'static str = "rmw_dds_common/msg/ParticipantEntitiesInfo";

    fn type_description() -> crate::TypeDescription {
        crate::DescriptionBuilder::new(Self::TYPE_NAME)
            .field::<Gid>("gid")
            .field::<Vec<NodeEntitiesInfo>>("node_entities_info_seq")
            .build()
    }
}

/// Every interface of this package: ROS type name and type description.
pub const TYPES: &[(&str, crate::DescribeFn)] = &[
    (
        "rmw_dds_common/msg/Gid",
        <Gid as crate::Message>::type_description,
    ),
    (
        "rmw_dds_common/msg/NodeEntitiesInfo",
        <NodeEntitiesInfo as crate::Message>::type_description,
    ),
    (
        "rmw_dds_common/msg/ParticipantEntitiesInfo",
        <ParticipantEntitiesInfo as crate::Message>::type_description,
    ),
];
