//! [`GraphSnapshot`]: everything a [`GraphCache`] holds, as plain serializable data, and the
//! cache rebuilt from it — how one process hands its graph to another (the CLI's daemon).

use std::collections::BTreeMap;

use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::TypeHash;
use serde::{Deserialize, Serialize};

use crate::endpoint::participant_gid_from_prefix;
use crate::{EndpointEntry, GraphCache};

/// One participant of a [`GraphSnapshot`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ParticipantSnapshot {
    /// The participant's GID.
    pub gid: Gid,
    /// Its enclave, when its USER_DATA told it.
    pub enclave: Option<String>,
    /// Whether its USER_DATA said it is not a ROS participant
    /// ([`GraphCache::mark_not_ros`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub not_ros: bool,
    /// Its nodes as its latest `ros_discovery_info` listed them; `None` while it has not sent
    /// one.
    pub nodes: Option<Vec<NodeEntitiesInfo>>,
}

/// The whole content of a [`GraphCache`] (participants in GUID order, endpoints in GID order,
/// the service type hashes it was given), from which [`GraphCache::from_snapshot`] rebuilds an
/// equal cache: every query answers the same on both.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct GraphSnapshot {
    /// Every participant known.
    pub participants: Vec<ParticipantSnapshot>,
    /// Every reader and writer known.
    pub endpoints: Vec<EndpointEntry>,
    /// Service type hashes by demangled service type (set ones only).
    pub service_type_hashes: BTreeMap<String, TypeHash>,
}

impl GraphCache {
    /// The cache's content as plain data.
    pub fn snapshot(&self) -> GraphSnapshot {
        let participants = self
            .participants
            .iter()
            .map(|(prefix, p)| ParticipantSnapshot {
                gid: participant_gid_from_prefix(*prefix),
                enclave: p.enclave.clone(),
                not_ros: p.not_ros,
                nodes: p.announced.then(|| p.nodes.clone()),
            })
            .collect();
        let mut endpoints: Vec<EndpointEntry> = self.endpoints.values().cloned().collect();
        endpoints.sort_by_key(|e| e.gid);
        let service_type_hashes = self
            .service_type_hashes
            .iter()
            .filter(|(_, hash)| hash.is_set())
            .map(|(ty, hash)| (ty.clone(), *hash))
            .collect();
        GraphSnapshot {
            participants,
            endpoints,
            service_type_hashes,
        }
    }

    /// A cache holding what `snapshot` holds, built through the mutators (so its indexes are
    /// those the live cache had). Records no events.
    pub fn from_snapshot(snapshot: GraphSnapshot) -> Self {
        let mut cache = Self::new();
        for p in snapshot.participants {
            cache.add_participant(p.gid, p.enclave);
            if p.not_ros {
                cache.mark_not_ros(p.gid);
            }
            if let Some(nodes) = p.nodes {
                cache.update_participant_entities(ParticipantEntitiesInfo {
                    gid: p.gid,
                    node_entities_info_seq: nodes,
                });
            }
        }
        for e in snapshot.endpoints {
            cache.add_entity(e);
        }
        for (ty, hash) in snapshot.service_type_hashes {
            cache.set_service_type_hash(&ty, hash);
        }
        cache
    }
}

/// `EndpointEntry::type_hash` in a snapshot: the RIHS string, or `null` when unset
/// ([`TypeHash`]'s own form is the RIHS string, which has no unset value).
pub(crate) mod optional_type_hash {
    use horus_ros_msgs::TypeHash;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(crate) fn serialize<S: Serializer>(hash: &TypeHash, s: S) -> Result<S::Ok, S::Error> {
        hash.is_set().then_some(hash).serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<TypeHash, D::Error> {
        Ok(Option::<TypeHash>::deserialize(d)?.unwrap_or(TypeHash::ZERO))
    }
}
