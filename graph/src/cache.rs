//! [`GraphCache`]: the state and its mutators (rmw_dds_common jazzy `graph_cache.cpp`:
//! `add_entity`, `remove_entity`, `add_participant`, `remove_participant`,
//! `update_participant_entities`), and the indexes the mutators keep up to date so that
//! queries need not scan every endpoint.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::names::{is_hidden_name, DemangledTopic};
use horus_ros_rmw::qos::EndpointKind;

use serde::{Deserialize, Serialize};

use crate::endpoint::{participant_gid_from_prefix, EndpointEntry, GuidPrefix};
use crate::event::{GraphEndpoint, GraphEvent, NodeName};
use crate::query::{demangle_service_type, demangle_type};
use crate::RosEndpoint;

/// `e` as events report it, its node looked up in `participant` (its own participant, if known).
fn graph_endpoint(e: &EndpointEntry, participant: Option<&Participant>) -> GraphEndpoint {
    let ros = RosEndpoint::of(&e.dds_topic_name, e.kind);
    let type_name = match &ros {
        Some(r) if r.role.is_service() => demangle_service_type(&e.dds_type_name)
            .unwrap_or_else(|| demangle_type(&e.dds_type_name)),
        _ => demangle_type(&e.dds_type_name),
    };
    GraphEndpoint {
        node: participant.and_then(|p| p.node_name_listing(e)),
        ros,
        gid: e.gid,
        kind: e.kind,
        dds_topic: e.dds_topic_name.clone(),
        dds_type: e.dds_type_name.clone(),
        type_name,
        type_hash: e.type_hash,
        qos: e.qos,
    }
}

/// What is known about one participant.
#[derive(Debug, Clone, Default)]
pub(crate) struct Participant {
    /// Its enclave, when its USER_DATA told it.
    pub(crate) enclave: Option<String>,
    /// Whether its USER_DATA was read and holds no `enclave=` where every ROS participant of its
    /// DDS puts one: it is not a ROS participant (see [`GraphCache::mark_not_ros`]).
    pub(crate) not_ros: bool,
    /// Its nodes, as its latest `ros_discovery_info` message lists them.
    pub(crate) nodes: Vec<NodeEntitiesInfo>,
    /// Endpoint GID → (kind, index into `nodes`) of the first node listing it.
    pub(crate) owner: BTreeMap<Gid, (EndpointKind, usize)>,
    /// Whether a `ros_discovery_info` message of it has arrived.
    pub(crate) announced: bool,
}

impl Participant {
    /// The node listing `e` (of the same kind) in its latest message, the first if several do
    /// (rmw_dds_common `__find_name_and_namespace_from_entity_gid`).
    pub(crate) fn node_listing(&self, e: &EndpointEntry) -> Option<&NodeEntitiesInfo> {
        match self.owner.get(&e.gid) {
            Some((kind, index)) if *kind == e.kind => self.nodes.get(*index),
            _ => None,
        }
    }

    /// The name and namespace of [`node_listing`](Self::node_listing).
    fn node_name_listing(&self, e: &EndpointEntry) -> Option<NodeName> {
        self.node_listing(e).map(|n| NodeName {
            name: n.node_name.clone(),
            namespace: n.node_namespace.clone(),
        })
    }

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

/// The demangled forms of one DDS type name used on one topic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct TypeUse {
    /// How many endpoints of the topic have this type.
    pub(crate) endpoints: usize,
    /// `_demangle_if_ros_type` of the DDS type name (`pkg/msg/Name`, else unchanged).
    pub(crate) message_type: String,
    /// `_demangle_service_type_only` of the DDS type name (`pkg/srv/Name`).
    pub(crate) service_type: Option<String>,
}

/// Everything known about one DDS topic name: its endpoints and their types.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct TopicEntry {
    /// The DDS topic name classified and demangled once.
    pub(crate) demangled: DemangledTopic,
    /// Whether the demangled ROS name is hidden (false for non-ROS topics).
    pub(crate) hidden: bool,
    /// Readers on the topic, in GID order.
    pub(crate) readers: BTreeSet<Gid>,
    /// Writers on the topic, in GID order.
    pub(crate) writers: BTreeSet<Gid>,
    /// The DDS type names of its endpoints, with their demangled forms.
    pub(crate) types: BTreeMap<String, TypeUse>,
}

impl TopicEntry {
    fn new(dds_topic: &str) -> Self {
        let demangled = DemangledTopic::from_dds_topic_name(dds_topic);
        let hidden = match &demangled {
            DemangledTopic::Topic(t) => is_hidden_name(t.as_str()),
            DemangledTopic::ServiceRequest(s) | DemangledTopic::ServiceReply(s) => {
                is_hidden_name(s.as_str())
            }
            DemangledTopic::NotRos => false,
        };
        Self {
            demangled,
            hidden,
            readers: BTreeSet::new(),
            writers: BTreeSet::new(),
            types: BTreeMap::new(),
        }
    }

    /// The endpoints of `kind` on the topic, in GID order.
    pub(crate) fn gids(&self, kind: EndpointKind) -> &BTreeSet<Gid> {
        match kind {
            EndpointKind::Reader => &self.readers,
            EndpointKind::Writer => &self.writers,
        }
    }

    fn gids_mut(&mut self, kind: EndpointKind) -> &mut BTreeSet<Gid> {
        match kind {
            EndpointKind::Reader => &mut self.readers,
            EndpointKind::Writer => &mut self.writers,
        }
    }
}

/// Nodes by namespace then name: each (participant, index into its `nodes`) listing it.
type NodeIndex = BTreeMap<String, BTreeMap<String, BTreeSet<(GuidPrefix, usize)>>>;

/// Indexes derived from `GraphCache::endpoints` and `GraphCache::participants`, kept in step
/// by every mutator (and rebuilt from scratch by the tests to check that).
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub(crate) struct Indexes {
    /// DDS topic name → its endpoints and types. Topics with no endpoint are dropped.
    pub(crate) topics: BTreeMap<String, TopicEntry>,
    /// Participant GUID prefix → GIDs of its endpoints (participant known or not).
    pub(crate) by_participant: BTreeMap<GuidPrefix, BTreeSet<Gid>>,
    /// Node namespace → name → (participant, node index), in participant then node order.
    pub(crate) nodes: NodeIndex,
    /// Number of nodes of all participants, duplicates counted.
    pub(crate) node_count: usize,
}

impl Indexes {
    fn add_endpoint(&mut self, e: &EndpointEntry) {
        let topic = match self.topics.get_mut(e.dds_topic_name.as_str()) {
            Some(topic) => topic,
            None => self
                .topics
                .entry(e.dds_topic_name.clone())
                .or_insert_with(|| TopicEntry::new(&e.dds_topic_name)),
        };
        topic.gids_mut(e.kind).insert(e.gid);
        match topic.types.get_mut(e.dds_type_name.as_str()) {
            Some(used) => used.endpoints += 1,
            None => {
                topic.types.insert(
                    e.dds_type_name.clone(),
                    TypeUse {
                        endpoints: 1,
                        message_type: demangle_type(&e.dds_type_name),
                        service_type: demangle_service_type(&e.dds_type_name),
                    },
                );
            }
        }
        self.by_participant
            .entry(e.participant_prefix())
            .or_default()
            .insert(e.gid);
    }

    fn remove_endpoint(&mut self, e: &EndpointEntry) {
        if let Some(topic) = self.topics.get_mut(e.dds_topic_name.as_str()) {
            topic.gids_mut(e.kind).remove(&e.gid);
            if let Some(used) = topic.types.get_mut(e.dds_type_name.as_str()) {
                used.endpoints -= 1;
                if used.endpoints == 0 {
                    topic.types.remove(e.dds_type_name.as_str());
                }
            }
            if topic.readers.is_empty() && topic.writers.is_empty() {
                self.topics.remove(e.dds_topic_name.as_str());
            }
        }
        let prefix = e.participant_prefix();
        if let Some(gids) = self.by_participant.get_mut(&prefix) {
            gids.remove(&e.gid);
            if gids.is_empty() {
                self.by_participant.remove(&prefix);
            }
        }
    }

    fn add_nodes(&mut self, prefix: GuidPrefix, nodes: &[NodeEntitiesInfo]) {
        for (index, node) in nodes.iter().enumerate() {
            let names = match self.nodes.get_mut(node.node_namespace.as_str()) {
                Some(names) => names,
                None => self.nodes.entry(node.node_namespace.clone()).or_default(),
            };
            let places = match names.get_mut(node.node_name.as_str()) {
                Some(places) => places,
                None => names.entry(node.node_name.clone()).or_default(),
            };
            places.insert((prefix, index));
        }
        self.node_count += nodes.len();
    }

    fn remove_nodes(&mut self, prefix: GuidPrefix, nodes: &[NodeEntitiesInfo]) {
        for (index, node) in nodes.iter().enumerate() {
            let Some(names) = self.nodes.get_mut(node.node_namespace.as_str()) else {
                continue;
            };
            if let Some(places) = names.get_mut(node.node_name.as_str()) {
                places.remove(&(prefix, index));
                if places.is_empty() {
                    names.remove(node.node_name.as_str());
                }
            }
            if names.is_empty() {
                self.nodes.remove(node.node_namespace.as_str());
            }
        }
        self.node_count -= nodes.len();
    }
}

/// The DDS topic every ROS participant announces its nodes on (rmw_dds_common).
const DISCOVERY_INFO_TOPIC: &str = "ros_discovery_info";

/// Whether a participant is a ROS participant — one that announces its nodes on
/// `ros_discovery_info` — as far as what is known tells (see [`GraphCache::participant_kind`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParticipantKind {
    /// A ROS participant: its USER_DATA names its enclave, or its `ros_discovery_info` writer
    /// or message was seen.
    Ros,
    /// Not a ROS participant (a bare DDS application): it never announces nodes.
    NotRos,
    /// Not known yet: nothing of it but its SPDP announcement (or readers) without USER_DATA
    /// that would tell.
    Undecided,
}

/// Why a [`GraphCache`] is not consistent yet (see [`GraphCache::unsettled`]).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Unsettled {
    /// ROS participants (their GIDs, in order) whose `ros_discovery_info` has not arrived, among
    /// those known from DDS discovery or from their endpoints.
    pub unannounced: Vec<Gid>,
    /// Participants (their GIDs, in order) not known yet to be ROS participants or not.
    pub undecided: Vec<Gid>,
    /// Announced participants (their GIDs, in order) that list endpoints DDS discovery has not
    /// reported yet.
    pub incomplete: Vec<Gid>,
    /// How many endpoints the `incomplete` participants list that are not discovered yet.
    pub missing_endpoints: usize,
}

impl Unsettled {
    /// Whether nothing is outstanding.
    pub fn is_empty(&self) -> bool {
        self.unannounced.is_empty() && self.undecided.is_empty() && self.incomplete.is_empty()
    }

    /// Whether something is outstanding of a participant known to be a ROS participant (the
    /// undecided ones aside).
    pub fn ros_outstanding(&self) -> bool {
        !self.unannounced.is_empty() || !self.incomplete.is_empty()
    }

    /// Every participant with something outstanding, in GID order, each once.
    pub fn participants(&self) -> Vec<Gid> {
        let mut all: Vec<Gid> = self
            .unannounced
            .iter()
            .chain(&self.undecided)
            .chain(&self.incomplete)
            .copied()
            .collect();
        all.sort();
        all.dedup();
        all
    }
}

/// The ROS 2 graph as seen so far: participants, their nodes, and every reader and writer.
///
/// A plain data structure fed by discovery events; no I/O, no locking (wrap it in a mutex to
/// share it). Endpoints are indexed by DDS topic and by participant (GID-ordered sets) and
/// nodes by namespace and name, so every query is deterministic and a query about one topic,
/// service or node costs about as much as what it returns, not a scan of the whole graph.
#[derive(Debug, Default)]
pub struct GraphCache {
    /// Participants by GUID prefix.
    pub(crate) participants: BTreeMap<GuidPrefix, Participant>,
    /// Readers and writers by GID (hashed: GID order comes from the indexes' sets).
    pub(crate) endpoints: HashMap<Gid, EndpointEntry>,
    /// Indexes over `participants` and `endpoints`.
    pub(crate) index: Indexes,
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

    /// Whether events are being recorded (so building one is worth it).
    fn recording(&self) -> bool {
        self.events.is_some()
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
    /// removed. Events: the endpoints removed (in GID order, each with its node), then the
    /// nodes.
    pub fn remove_participant(&mut self, participant_gid: Gid) -> bool {
        let prefix = participant_gid.prefix();
        let mut changed = false;
        // In GID order; removed while the participant still names their nodes.
        let lost = self
            .index
            .by_participant
            .get(&prefix)
            .cloned()
            .unwrap_or_default();
        for gid in lost {
            changed |= self.remove_entity(gid);
        }
        self.index.by_participant.remove(&prefix);
        if let Some(participant) = self.participants.remove(&prefix) {
            changed = true;
            self.index.remove_nodes(prefix, &participant.nodes);
            for node in participant.nodes {
                self.emit(GraphEvent::NodeRemoved {
                    name: node.node_name,
                    namespace: node.node_namespace,
                });
            }
        }
        changed
    }

    /// `e` as events report it, with its node as known now.
    pub(crate) fn graph_endpoint(&self, e: &EndpointEntry) -> GraphEndpoint {
        graph_endpoint(e, self.participants.get(&e.participant_prefix()))
    }

    /// Adds a reader or writer, or replaces what was known about its GID. Returns whether
    /// anything changed. Its participant need not be known yet.
    pub fn add_entity(&mut self, entry: EndpointEntry) -> bool {
        if self.endpoints.get(&entry.gid) == Some(&entry) {
            return false;
        }
        let added = self.recording().then(|| self.graph_endpoint(&entry));
        let removed = match self.endpoints.get(&entry.gid) {
            Some(old) => {
                let event = self.recording().then(|| self.graph_endpoint(old));
                self.index.remove_endpoint(old);
                event
            }
            None => None,
        };
        self.index.add_endpoint(&entry);
        self.endpoints.insert(entry.gid, entry);
        if let Some(old) = removed {
            self.emit(GraphEvent::EndpointRemoved(old));
        }
        if let Some(new) = added {
            self.emit(GraphEvent::EndpointAdded(new));
        }
        true
    }

    /// Removes a reader or writer. Returns whether it was known.
    pub fn remove_entity(&mut self, gid: Gid) -> bool {
        let Some(old) = self.endpoints.remove(&gid) else {
            return false;
        };
        self.index.remove_endpoint(&old);
        if self.recording() {
            let event = GraphEvent::EndpointRemoved(self.graph_endpoint(&old));
            self.emit(event);
        }
        true
    }

    /// Applies a participant's `ros_discovery_info` message: its node list replaces the
    /// previous one (a node missing from it is gone), as rmw_dds_common does. Creates the
    /// participant if unknown. Returns whether its node list changed.
    ///
    /// Events: the nodes added, then (in GID order) every discovered endpoint of the
    /// participant whose node changed ([`GraphEvent::EndpointNodeChanged`]: first listed, moved,
    /// or no longer listed), then the nodes removed.
    pub fn update_participant_entities(&mut self, msg: ParticipantEntitiesInfo) -> bool {
        let prefix = msg.gid.prefix();
        let participant = self.participants.entry(prefix).or_default();
        let first = !participant.announced;
        participant.announced = true;
        if participant.nodes == msg.node_entities_info_seq {
            return first;
        }
        let old = Participant {
            nodes: std::mem::take(&mut participant.nodes),
            owner: std::mem::take(&mut participant.owner),
            ..Participant::default()
        };
        participant.set_nodes(msg.node_entities_info_seq);
        self.index.remove_nodes(prefix, &old.nodes);
        self.index.add_nodes(prefix, &participant.nodes);
        if self.events.is_none() {
            return true;
        }
        // The endpoints either message lists, in GID order.
        let listed: BTreeSet<Gid> = old
            .owner
            .keys()
            .chain(participant.owner.keys())
            .copied()
            .collect();
        let moved: Vec<GraphEvent> = listed
            .iter()
            .filter_map(|gid| self.endpoints.get(gid))
            .filter(|e| e.participant_prefix() == prefix)
            .filter_map(|e| {
                let previous = old.node_name_listing(e);
                let endpoint = graph_endpoint(e, Some(&*participant));
                (endpoint.node != previous)
                    .then_some(GraphEvent::EndpointNodeChanged { endpoint, previous })
            })
            .collect();
        let new: Vec<(String, String)> = participant
            .nodes
            .iter()
            .map(|n| (n.node_name.clone(), n.node_namespace.clone()))
            .collect();
        let old: Vec<(String, String)> = old
            .nodes
            .into_iter()
            .map(|n| (n.node_name, n.node_namespace))
            .collect();
        for (name, namespace) in multiset_minus(&new, &old) {
            self.emit(GraphEvent::NodeAdded { name, namespace });
        }
        for event in moved {
            self.emit(event);
        }
        for (name, namespace) in multiset_minus(&old, &new) {
            self.emit(GraphEvent::NodeRemoved { name, namespace });
        }
        true
    }

    /// Marks the participant `participant_gid` (added with [`add_participant`](Self::add_participant))
    /// as not a ROS participant: its USER_DATA was read, holds no `enclave=`, and its DDS is one
    /// whose ROS participants always put it there (rmw_fastrtps `participant.cpp` and
    /// rmw_cyclonedds `rmw_context_impl_s::init` write `enclave=<enclave>;` into every
    /// participant's USER_DATA). Returns whether anything changed.
    pub fn mark_not_ros(&mut self, participant_gid: Gid) -> bool {
        match self.participants.get_mut(&participant_gid.prefix()) {
            Some(p) if !p.not_ros => {
                p.not_ros = true;
                true
            }
            _ => false,
        }
    }

    /// Whether the participant of `prefix` is a ROS participant, as far as known:
    ///
    /// - [`Ros`](ParticipantKind::Ros) when it has announced its nodes, its USER_DATA names its
    ///   enclave, or one of its writers is on `ros_discovery_info`;
    /// - [`NotRos`](ParticipantKind::NotRos) otherwise when its USER_DATA said so
    ///   ([`mark_not_ros`](Self::mark_not_ros)), or when one of its writers is known: every rmw
    ///   creates its `ros_discovery_info` writer before any other (rmw_fastrtps
    ///   `init_rmw_context_impl.cpp`, rmw_cyclonedds `rmw_context_impl_s::init`, ours at context
    ///   creation), and SEDP delivers a participant's writers in the order they were announced,
    ///   so a ROS participant's first writer discovered is that one;
    /// - [`Undecided`](ParticipantKind::Undecided) otherwise (only its SPDP announcement, or
    ///   readers, without USER_DATA that tells: the rustdds backend reads none).
    pub fn participant_kind(&self, prefix: GuidPrefix) -> ParticipantKind {
        let participant = self.participants.get(&prefix);
        if participant.is_some_and(|p| p.announced || p.enclave.is_some()) {
            return ParticipantKind::Ros;
        }
        let mut any_writer = false;
        for gid in self.index.by_participant.get(&prefix).into_iter().flatten() {
            let Some(e) = self.endpoints.get(gid) else {
                continue;
            };
            if e.kind == EndpointKind::Writer {
                if e.dds_topic_name == DISCOVERY_INFO_TOPIC {
                    return ParticipantKind::Ros;
                }
                any_writer = true;
            }
        }
        if any_writer || participant.is_some_and(|p| p.not_ros) {
            ParticipantKind::NotRos
        } else {
            ParticipantKind::Undecided
        }
    }

    /// Whether what is known is consistent: every ROS participant, known from DDS discovery or
    /// only from its endpoints, has sent its `ros_discovery_info`, every endpoint its nodes
    /// list has been discovered, and no participant is left whose kind is
    /// [undecided](ParticipantKind::Undecided). Participants that are not ROS participants
    /// ([`participant_kind`](Self::participant_kind)) never announce nodes and do not count.
    /// A discovery wait can stop once this holds.
    pub fn is_consistent(&self) -> bool {
        self.unsettled().is_empty()
    }

    /// What keeps the cache from being [consistent](Self::is_consistent): the ROS participants
    /// not announced yet, the participants not known to be ROS participants or not, and the
    /// announced ones that list endpoints not discovered yet (and how many).
    pub fn unsettled(&self) -> Unsettled {
        let mut unsettled = Unsettled::default();
        // Endpoints can be discovered before their participant is reported (DDS delivers the
        // two in any order): such a participant has not announced its nodes either.
        let unannounced = self
            .participants
            .iter()
            .filter(|(_, p)| !p.announced)
            .map(|(prefix, _)| *prefix)
            .chain(
                self.index
                    .by_participant
                    .keys()
                    .filter(|prefix| !self.participants.contains_key(*prefix))
                    .copied(),
            );
        for prefix in unannounced {
            match self.participant_kind(prefix) {
                ParticipantKind::Ros => unsettled
                    .unannounced
                    .push(participant_gid_from_prefix(prefix)),
                ParticipantKind::Undecided => unsettled
                    .undecided
                    .push(participant_gid_from_prefix(prefix)),
                ParticipantKind::NotRos => {}
            }
        }
        unsettled.unannounced.sort();
        unsettled.undecided.sort();
        for (prefix, p) in self.participants.iter().filter(|(_, p)| p.announced) {
            let missing = p
                .owner
                .keys()
                .filter(|gid| !self.endpoints.contains_key(gid))
                .count();
            if missing > 0 {
                unsettled
                    .incomplete
                    .push(participant_gid_from_prefix(*prefix));
                unsettled.missing_endpoints += missing;
            }
        }
        unsettled
    }

    /// Records the hash of a service type (e.g. `example_interfaces/srv/AddTwoInts`) for
    /// [`ServiceEndpointInfo::service_type_hash`](crate::ServiceEndpointInfo::service_type_hash):
    /// Jazzy peers do not send it.
    pub fn set_service_type_hash(&mut self, service_type: &str, hash: TypeHash) {
        self.service_type_hashes
            .insert(service_type.to_owned(), hash);
    }
}

#[cfg(test)]
impl GraphCache {
    /// The indexes rebuilt from scratch from the participants and endpoints.
    pub(crate) fn rebuilt_indexes(&self) -> Indexes {
        let mut index = Indexes::default();
        for e in self.endpoints.values() {
            index.add_endpoint(e);
        }
        for (prefix, participant) in &self.participants {
            index.add_nodes(*prefix, &participant.nodes);
        }
        index
    }

    /// Panics unless the maintained indexes equal the rebuilt ones.
    pub(crate) fn assert_indexes_consistent(&self) {
        assert_eq!(self.index, self.rebuilt_indexes(), "indexes out of step");
    }
}

/// The items of `a` not matched one-for-one by items of `b` (multiset difference, `a`'s order).
fn multiset_minus<T: Clone + Eq + std::hash::Hash>(a: &[T], b: &[T]) -> Vec<T> {
    // Counted once (O(n + m)): a node announced twice and withdrawn once is still there once.
    let mut left: HashMap<&T, usize> = HashMap::with_capacity(b.len());
    for item in b {
        *left.entry(item).or_default() += 1;
    }
    a.iter()
        .filter(|item| match left.get_mut(item) {
            Some(n) if *n > 0 => {
                *n -= 1;
                false
            }
            _ => true,
        })
        .cloned()
        .collect()
}
