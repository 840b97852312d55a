//! [`GraphCache`]: the state and its mutators (rmw_dds_common jazzy `graph_cache.cpp`:
//! `add_entity`, `remove_entity`, `add_participant`, `remove_participant`,
//! `update_participant_entities`).

use std::collections::BTreeMap;

use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::EndpointKind;

use crate::endpoint::{EndpointEntry, GuidPrefix};
use crate::event::GraphEvent;

/// What is known about one participant.
#[derive(Debug, Clone, Default)]
pub(crate) struct Participant {
    /// Its enclave, when its USER_DATA told it.
    pub(crate) enclave: Option<String>,
    /// Its nodes, as its latest `ros_discovery_info` message lists them.
    pub(crate) nodes: Vec<NodeEntitiesInfo>,
    /// Endpoint GID → (kind, index into `nodes`) of the first node listing it.
    pub(crate) owner: BTreeMap<Gid, (EndpointKind, usize)>,
}

impl Participant {
    /// Replaces the node list and rebuilds the GID → node index.
    fn set_nodes(&mut self, nodes: Vec<NodeEntitiesInfo>) {
        let mut owner = BTreeMap::new();
        for (index, node) in nodes.iter().enumerate() {
            for gid in &node.reader_gid_seq {
                owner.entry(*gid).or_insert((EndpointKind::Reader, index));
            }
            for gid in &node.writer_gid_seq {
                owner.entry(*gid).or_insert((EndpointKind::Writer, index));
            }
        }
        self.nodes = nodes;
        self.owner = owner;
    }
}

/// The ROS 2 graph as seen so far: participants, their nodes, and every reader and writer.
///
/// A plain data structure fed by discovery events; no I/O, no locking (wrap it in a mutex to
/// share it). Maps are keyed by GID in `BTreeMap`s, so every query is deterministic.
#[derive(Debug, Default)]
pub struct GraphCache {
    /// Participants by GUID prefix.
    pub(crate) participants: BTreeMap<GuidPrefix, Participant>,
    /// Readers and writers by GID.
    pub(crate) endpoints: BTreeMap<Gid, EndpointEntry>,
    /// Service type hashes known to the caller, by demangled service type.
    pub(crate) service_type_hashes: BTreeMap<String, TypeHash>,
    /// Recorded events, when enabled.
    events: Option<Vec<GraphEvent>>,
}

impl GraphCache {
    /// An empty cache that records no events.
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts (`true`) or stops (`false`, dropping pending ones) recording [`GraphEvent`]s.
    pub fn record_events(&mut self, enabled: bool) {
        match (enabled, self.events.is_some()) {
            (true, false) => self.events = Some(Vec::new()),
            (false, true) => self.events = None,
            _ => {}
        }
    }

    /// Takes the events recorded since the last call, oldest first.
    pub fn drain_events(&mut self) -> Vec<GraphEvent> {
        self.events.as_mut().map(std::mem::take).unwrap_or_default()
    }

    fn emit(&mut self, event: GraphEvent) {
        if let Some(events) = self.events.as_mut() {
            events.push(event);
        }
    }

    /// Adds or updates a participant (seen in SPDP) and its enclave. Returns whether anything
    /// changed. A participant first known through `ros_discovery_info` has no enclave.
    pub fn add_participant(&mut self, participant_gid: Gid, enclave: Option<String>) -> bool {
        match self.participants.get_mut(&participant_gid.prefix()) {
            Some(p) if p.enclave == enclave => false,
            Some(p) => {
                p.enclave = enclave;
                true
            }
            None => {
                self.participants.insert(
                    participant_gid.prefix(),
                    Participant {
                        enclave,
                        ..Participant::default()
                    },
                );
                true
            }
        }
    }

    /// Removes a participant, its nodes, and every endpoint whose `participant_gid` has its
    /// GUID prefix (DDS reports only the participant's loss). Returns whether anything was
    /// removed.
    pub fn remove_participant(&mut self, participant_gid: Gid) -> bool {
        let prefix = participant_gid.prefix();
        let mut changed = false;
        if let Some(participant) = self.participants.remove(&prefix) {
            changed = true;
            for node in participant.nodes {
                self.emit(GraphEvent::NodeRemoved {
                    name: node.node_name,
                    namespace: node.node_namespace,
                });
            }
        }
        let lost: Vec<Gid> = self
            .endpoints
            .iter()
            .filter(|(_, e)| e.participant_prefix() == prefix)
            .map(|(gid, _)| *gid)
            .collect();
        for gid in lost {
            changed |= self.remove_entity(gid);
        }
        changed
    }

    /// Adds a reader or writer, or replaces what was known about its GID. Returns whether
    /// anything changed. Its participant need not be known yet.
    pub fn add_entity(&mut self, entry: EndpointEntry) -> bool {
        if self.endpoints.get(&entry.gid) == Some(&entry) {
            return false;
        }
        let event = GraphEvent::EndpointAdded {
            gid: entry.gid,
            kind: entry.kind,
            topic: entry.dds_topic_name.clone(),
        };
        if let Some(old) = self.endpoints.insert(entry.gid, entry) {
            self.emit(GraphEvent::EndpointRemoved {
                gid: old.gid,
                kind: old.kind,
                topic: old.dds_topic_name,
            });
        }
        self.emit(event);
        true
    }

    /// Removes a reader or writer. Returns whether it was known.
    pub fn remove_entity(&mut self, gid: Gid) -> bool {
        match self.endpoints.remove(&gid) {
            Some(old) => {
                self.emit(GraphEvent::EndpointRemoved {
                    gid: old.gid,
                    kind: old.kind,
                    topic: old.dds_topic_name,
                });
                true
            }
            None => false,
        }
    }

    /// Applies a participant's `ros_discovery_info` message: its node list replaces the
    /// previous one (a node missing from it is gone), as rmw_dds_common does. Creates the
    /// participant if unknown. Returns whether its node list changed.
    pub fn update_participant_entities(&mut self, msg: ParticipantEntitiesInfo) -> bool {
        let participant = self.participants.entry(msg.gid.prefix()).or_default();
        if participant.nodes == msg.node_entities_info_seq {
            return false;
        }
        let old = std::mem::take(&mut participant.nodes);
        participant.set_nodes(msg.node_entities_info_seq);
        let new: Vec<(String, String)> = participant
            .nodes
            .iter()
            .map(|n| (n.node_name.clone(), n.node_namespace.clone()))
            .collect();
        let old: Vec<(String, String)> = old
            .into_iter()
            .map(|n| (n.node_name, n.node_namespace))
            .collect();
        for (name, namespace) in multiset_minus(&old, &new) {
            self.emit(GraphEvent::NodeRemoved { name, namespace });
        }
        for (name, namespace) in multiset_minus(&new, &old) {
            self.emit(GraphEvent::NodeAdded { name, namespace });
        }
        true
    }

    /// Records the hash of a service type (e.g. `example_interfaces/srv/AddTwoInts`) for
    /// [`ServiceEndpointInfo::service_type_hash`](crate::ServiceEndpointInfo::service_type_hash):
    /// Jazzy peers do not send it.
    pub fn set_service_type_hash(&mut self, service_type: &str, hash: TypeHash) {
        self.service_type_hashes
            .insert(service_type.to_owned(), hash);
    }
}

/// The items of `a` not matched one-for-one by items of `b` (multiset difference, `a`'s order).
fn multiset_minus<T: Clone + PartialEq>(a: &[T], b: &[T]) -> Vec<T> {
    let mut used = vec![false; b.len()];
    a.iter()
        .filter(|item| {
            match b
                .iter()
                .enumerate()
                .position(|(i, other)| !used[i] && other == *item)
            {
                Some(i) => {
                    used[i] = true;
                    false
                }
                None => true,
            }
        })
        .cloned()
        .collect()
}
