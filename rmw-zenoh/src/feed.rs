//! The graph of a Zenoh ROS 2 system, from rmw_zenoh's liveliness tokens, turned into the
//! [`DiscoveryEvent`]s the DDS-shaped graph cache is fed with (rmw_zenoh_cpp 0.2.10 builds its
//! own `GraphCache` from the same tokens: `src/detail/graph_cache.cpp`, `parse_put`/`parse_del`).
//!
//! The mapping, so that every graph query answers unchanged:
//!
//! - each Zenoh session (zid) is one participant, whose GID is the first 12 bytes of the
//!   XXH3-128 of the zid's text followed by the DDS participant entity id `00 00 01 c1`;
//! - `MP`/`MS` are a writer/reader on `rt/<topic>` with the token's type, hash and QoS, and the
//!   token's GID (what rmw_zenoh reports for the entity);
//! - `SS` is a server's two DDS endpoints: the request reader on `rq/<service>Request` (type
//!   `…_Request_`) with the token's GID and the reply writer on `rr/<service>Reply` (type
//!   `…_Response_`) with the GID of the token key followed by `#reply`; `SC` the reverse: the
//!   request writer has the token's GID (the one a client's requests carry in their attachment),
//!   the reply reader the GID of `<key>#reply`;
//! - `NN` tokens and the entity tokens under them make a synthesized `ros_discovery_info`
//!   message (`ParticipantEntitiesInfo`) per session, nodes in id order, each listing its
//!   endpoints' GIDs.
//!
//! A token's DELETE removes what it announced, once confirmed (no one answers for the token:
//! [`DeleteConfirmer`]); a session whose last token went is a lost
//! participant. A malformed token is logged once per session and dropped. The maps are bounded
//! ([`MAX_TOKENS`]), and so is the feed's queue ([`MAX_FEED_EVENTS`]).

use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use zenoh::Wait;

use horus_ros_msgs::rmw_dds_common::{NodeEntitiesInfo, ParticipantEntitiesInfo};

use super::liveliness::{gid_of_key, EntityKind, Token};
use horus_ros_rmw_contract::discovery::{
    DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId,
};
use horus_ros_rmw_contract::names::{
    ROS_SERVICE_REQUESTER_PREFIX, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX, SERVICE_REQUEST_SUFFIX,
};
use horus_ros_rmw_contract::push::{lock, FeedQueue, PushFeed};
use horus_ros_rmw_contract::qos::EndpointKind;
use horus_ros_rmw_contract::Gid;
use horus_ros_rmw_contract::LocalEvents;

/// Most tokens kept from all peers together; more are dropped (with one warning).
pub(crate) const MAX_TOKENS: usize = 100_000;
/// Most events a feed queues before its oldest are dropped.
pub(crate) const MAX_FEED_EVENTS: usize = 100_000;
/// Most sessions remembered as having sent a malformed token (each is warned about once).
const MAX_WARNED: usize = 1024;

/// The participant GID of a Zenoh session, from its zid as tokens write it.
pub(crate) fn participant_gid(zid: &str) -> Gid {
    let mut bytes = *gid_of_key(zid).as_bytes();
    bytes[12..].copy_from_slice(&[0x00, 0x00, 0x01, 0xc1]);
    Gid::from_bytes(bytes)
}

/// The DDS endpoints a token stands for, with their GIDs.
pub(crate) fn endpoints_of(token: &Token, key: &str, participant: Gid) -> Vec<DiscoveredEndpoint> {
    let Some(topic) = &token.topic else {
        return Vec::new();
    };
    let gid = gid_of_key(key);
    let reply_gid = || gid_of_key(&format!("{key}#reply"));
    let endpoint = |gid, kind, dds_topic_name: String, dds_type_name: String| DiscoveredEndpoint {
        gid,
        participant_gid: participant,
        kind,
        dds_topic_name,
        dds_type_name,
        qos: topic.qos,
        type_hash: topic.type_hash,
        user_data: Vec::new(),
    };
    let name = topic.name.trim_start_matches('/');
    let base = topic
        .type_name
        .strip_suffix('_')
        .unwrap_or(&topic.type_name);
    let request = || {
        (
            format!("{ROS_SERVICE_REQUESTER_PREFIX}/{name}{SERVICE_REQUEST_SUFFIX}"),
            format!("{base}_Request_"),
        )
    };
    let reply = || {
        (
            format!("{ROS_SERVICE_RESPONSE_PREFIX}/{name}{SERVICE_REPLY_SUFFIX}"),
            format!("{base}_Response_"),
        )
    };
    let topic_name = || format!("{ROS_TOPIC_PREFIX}/{name}");
    match token.kind {
        EntityKind::Node => Vec::new(),
        EntityKind::Publisher => vec![endpoint(
            gid,
            EndpointKind::Writer,
            topic_name(),
            topic.type_name.clone(),
        )],
        EntityKind::Subscription => vec![endpoint(
            gid,
            EndpointKind::Reader,
            topic_name(),
            topic.type_name.clone(),
        )],
        EntityKind::Service => {
            let ((rq, rq_type), (rr, rr_type)) = (request(), reply());
            vec![
                endpoint(gid, EndpointKind::Reader, rq, rq_type),
                endpoint(reply_gid(), EndpointKind::Writer, rr, rr_type),
            ]
        }
        EntityKind::Client => {
            let ((rq, rq_type), (rr, rr_type)) = (request(), reply());
            vec![
                endpoint(gid, EndpointKind::Writer, rq, rq_type),
                endpoint(reply_gid(), EndpointKind::Reader, rr, rr_type),
            ]
        }
    }
}

/// One remote session's tokens.
struct Session {
    gid: Gid,
    /// Its context's enclave, which every token names (rmw_zenoh's graph cache takes a node's
    /// from whichever of its tokens comes first: `GraphCache::make_graph_node`).
    enclave: String,
    /// Node tokens by node id.
    nodes: BTreeMap<u64, Token>,
    /// Entity tokens by key, with the endpoints they stand for.
    entities: BTreeMap<String, (Token, Vec<DiscoveredEndpoint>)>,
}

impl Session {
    fn is_empty(&self) -> bool {
        self.nodes.is_empty() && self.entities.is_empty()
    }

    /// The synthesized `ros_discovery_info` message.
    fn entities_info(&self) -> ParticipantEntitiesInfo {
        let mut nodes: Vec<NodeEntitiesInfo> = Vec::new();
        for (id, node) in &self.nodes {
            let mut info = NodeEntitiesInfo {
                node_namespace: node.namespace.clone(),
                node_name: node.node_name.clone(),
                reader_gid_seq: Vec::new(),
                writer_gid_seq: Vec::new(),
            };
            // Entity keys sort as strings; list them in entity id order, as they were made.
            let mut under: Vec<&(Token, Vec<DiscoveredEndpoint>)> = self
                .entities
                .values()
                .filter(|(t, _)| t.node_id == *id)
                .collect();
            under.sort_by_key(|(t, _)| t.entity_id);
            for (_, endpoints) in under {
                for e in endpoints {
                    match e.kind {
                        EndpointKind::Reader => info.reader_gid_seq.push(e.gid),
                        EndpointKind::Writer => info.writer_gid_seq.push(e.gid),
                    }
                }
            }
            nodes.push(info);
        }
        ParticipantEntitiesInfo {
            gid: self.gid,
            node_entities_info_seq: nodes,
        }
    }
}

/// One of this context's own endpoints, for matching.
#[derive(Clone)]
struct LocalEndpoint {
    kind: EndpointKind,
    topic: String,
    type_name: String,
}

/// Whether data of one reaches the other.
fn matches(a_kind: EndpointKind, a: (&str, &str), b_kind: EndpointKind, b: (&str, &str)) -> bool {
    a_kind != b_kind && a == b
}

/// The graph a context's session sees: remote sessions' tokens, its own endpoints (to report
/// matches) and its open feed.
pub(crate) struct Graph {
    own_zid: String,
    domain: u32,
    state: Mutex<GraphState>,
}

#[derive(Default)]
struct GraphState {
    sessions: BTreeMap<String, Session>,
    tokens: usize,
    /// Known tokens whose DELETE waits for its confirmation, with its ticket (see
    /// [`Graph::token`]); at most one per known token.
    pending_deletes: HashMap<String, u64>,
    next_ticket: u64,
    local: BTreeMap<Gid, LocalEndpoint>,
    feed: Option<Arc<FeedQueue>>,
    warned: BTreeSet<String>,
    warned_full: bool,
}

impl GraphState {
    /// Whether the token `key` is in the graph.
    fn knows(&self, token: &Token, key: &str) -> bool {
        self.sessions.get(&token.zid).is_some_and(|s| {
            if token.kind == EntityKind::Node {
                s.nodes.get(&token.node_id).is_some_and(|t| t.key() == key)
            } else {
                s.entities.contains_key(key)
            }
        })
    }

    fn send(&self, event: DiscoveryEvent) {
        if let Some(feed) = &self.feed {
            feed.push(event);
        }
    }

    /// Logs a peer's bad input once per session.
    fn warn_once(&mut self, zid: &str, what: &str) {
        if self.warned.len() < MAX_WARNED && self.warned.insert(zid.to_owned()) {
            tracing::warn!(zenoh_id = zid, "zenoh: dropped a malformed liveliness token: {what} (further ones of this peer are dropped silently)");
        }
    }

    /// `(local, remote)` pairs of matching endpoints, for a remote `e`.
    fn local_matches(&self, e: &DiscoveredEndpoint) -> Vec<DiscoveryEvent> {
        self.local
            .iter()
            .filter(|(_, l)| {
                matches(
                    l.kind,
                    (&l.topic, &l.type_name),
                    e.kind,
                    (&e.dds_topic_name, &e.dds_type_name),
                )
            })
            .map(|(gid, _)| DiscoveryEvent::Matched {
                local: *gid,
                remote: e.gid,
            })
            .collect()
    }

    /// Everything a feed opened now reports first.
    fn snapshot(&self) -> VecDeque<DiscoveryEvent> {
        let mut events = VecDeque::new();
        for s in self.sessions.values() {
            events.push_back(DiscoveryEvent::ParticipantDiscovered(
                DiscoveredParticipant {
                    gid: s.gid,
                    vendor_id: VendorId::ZENOH,
                    enclave: Some(s.enclave.clone()),
                },
            ));
            for (_, endpoints) in s.entities.values() {
                for e in endpoints {
                    events.push_back(DiscoveryEvent::EndpointDiscovered(e.clone()));
                    events.extend(self.local_matches(e));
                }
            }
            events.push_back(DiscoveryEvent::ParticipantEntities(s.entities_info()));
        }
        for (gid, l) in &self.local {
            for (other_gid, o) in &self.local {
                if matches(
                    l.kind,
                    (&l.topic, &l.type_name),
                    o.kind,
                    (&o.topic, &o.type_name),
                ) {
                    events.push_back(DiscoveryEvent::Matched {
                        local: *gid,
                        remote: *other_gid,
                    });
                }
            }
        }
        events
    }
}

/// Most DELETEs waiting for their confirmation to be asked; beyond, one is applied at once.
const MAX_UNCONFIRMED: usize = 1024;

/// How long a DELETE's confirmation may take (a liveliness `get` answered by the routing tables
/// of the sessions and routers on the way): then the DELETE is applied.
const CONFIRM_TIMEOUT: Duration = Duration::from_secs(5);

/// Asks, on a thread of its own (not from zenoh's callback), whether each token of a pending
/// DELETE is still alive, and tells the graph ([`Graph::confirm_delete`]). The thread ends with
/// the last sender (the liveliness subscriber's callback, undeclared when the session closes).
pub(crate) struct DeleteConfirmer {
    requests: mpsc::SyncSender<(String, u64)>,
    graph: Arc<Graph>,
}

impl DeleteConfirmer {
    /// Starts the thread that asks through `session`.
    pub(crate) fn start(session: zenoh::Session, graph: Arc<Graph>) -> std::io::Result<Self> {
        let (requests, pending) = mpsc::sync_channel::<(String, u64)>(MAX_UNCONFIRMED);
        let asking = Arc::clone(&graph);
        std::thread::Builder::new()
            .name("zenoh-graph".into())
            .spawn(move || {
                for (key, ticket) in pending {
                    ask(&session, &asking, key, ticket);
                }
            })?;
        Ok(Self { requests, graph })
    }

    /// Has the DELETE of `key` (`ticket`) confirmed; applied at once if too many wait.
    pub(crate) fn confirm(&self, key: &str, ticket: u64) {
        if let Err(
            mpsc::TrySendError::Full((key, ticket))
            | mpsc::TrySendError::Disconnected((key, ticket)),
        ) = self.requests.try_send((key.to_owned(), ticket))
        {
            self.graph.confirm_delete(&key, ticket, true);
        }
    }
}

/// A liveliness `get` of `key`: the DELETE is refuted if anyone answers for the token, applied
/// when the query ends without an answer (its callback dropped).
fn ask(session: &zenoh::Session, graph: &Arc<Graph>, key: String, ticket: u64) {
    /// Applies or refutes the DELETE when dropped, with the query's callback.
    struct Answer {
        graph: Arc<Graph>,
        key: String,
        ticket: u64,
        alive: AtomicBool,
    }
    impl Drop for Answer {
        fn drop(&mut self) {
            let gone = !self.alive.load(Ordering::SeqCst);
            self.graph.confirm_delete(&self.key, self.ticket, gone);
        }
    }
    let answer = Arc::new(Answer {
        graph: Arc::clone(graph),
        key: key.clone(),
        ticket,
        alive: AtomicBool::new(false),
    });
    let on_reply = move |reply: zenoh::query::Reply| {
        if reply.result().is_ok() {
            answer.alive.store(true, Ordering::SeqCst);
        }
    };
    // On an error the callback (and with it the answer) is dropped: the DELETE is applied.
    if let Err(e) = session
        .liveliness()
        .get(key.as_str())
        .timeout(CONFIRM_TIMEOUT)
        .callback(on_reply)
        .wait()
    {
        tracing::debug!("zenoh: confirming the DELETE of {key}: {e}");
    }
}

impl Graph {
    /// An empty graph of `domain`, seen by the session `own_zid`.
    pub(crate) fn new(own_zid: String, domain: u32) -> Self {
        Self {
            own_zid,
            domain,
            state: Mutex::default(),
        }
    }

    /// A token appeared (`put`) or went (`!put`); keys of this session, of another domain, or
    /// not under `@ros2_lv` are ignored.
    ///
    /// A DELETE of a known token is not applied at once: its ticket is returned, and the caller
    /// asks whether the token is still alive (a liveliness `get` of its key) and then calls
    /// [`confirm_delete`](Self::confirm_delete). Zenoh 1.8 delivers a DELETE when the link a token
    /// came over closes even while the token lives on over another — as when two peers' direct
    /// link (gossip) replaces the path through the router — and puts it again a moment later;
    /// applied at once, the entity would leave the graph and come back (a call in flight to a
    /// server ended with `ServerGone`). A PUT meanwhile cancels the pending DELETE.
    pub(crate) fn token(&self, key: &str, put: bool) -> Option<u64> {
        let mut state = lock(&self.state);
        let token = match Token::parse(key) {
            Ok(t) => t,
            Err(e) => {
                // The zid chunk, if any, names the peer.
                let zid = key.split('/').nth(2).unwrap_or("?").to_owned();
                if zid != self.own_zid {
                    state.warn_once(&zid, &format!("{key}: {e}"));
                }
                return None;
            }
        };
        if token.zid == self.own_zid || token.domain != self.domain {
            return None;
        }
        if put {
            state.pending_deletes.remove(key);
            self.put(&mut state, token, key);
            None
        } else if state.knows(&token, key) {
            state.next_ticket += 1;
            let ticket = state.next_ticket;
            state.pending_deletes.insert(key.to_owned(), ticket);
            Some(ticket)
        } else {
            None
        }
    }

    /// The DELETE of `key` with `ticket` ([`token`](Self::token)) is confirmed (`gone`: no one
    /// answered for the token) or refuted: applied if no PUT came since.
    pub(crate) fn confirm_delete(&self, key: &str, ticket: u64, gone: bool) {
        let mut state = lock(&self.state);
        if state.pending_deletes.get(key) != Some(&ticket) {
            return;
        }
        state.pending_deletes.remove(key);
        if !gone {
            return;
        }
        if let Ok(token) = Token::parse(key) {
            Self::delete(&mut state, &token, key);
        }
    }

    fn put(&self, state: &mut GraphState, token: Token, key: &str) {
        if state.tokens >= MAX_TOKENS {
            if !std::mem::replace(&mut state.warned_full, true) {
                tracing::warn!(
                    "zenoh: {MAX_TOKENS} liveliness tokens known, further ones are dropped"
                );
            }
            return;
        }
        let zid = token.zid.clone();
        let mut events = Vec::new();
        let session = state
            .sessions
            .entry(zid.clone())
            .or_insert_with(|| Session {
                gid: participant_gid(&zid),
                enclave: token.enclave.clone(),
                nodes: BTreeMap::new(),
                entities: BTreeMap::new(),
            });
        let new_session = session.is_empty();
        let gid = session.gid;
        if token.kind == EntityKind::Node {
            if session
                .nodes
                .get(&token.node_id)
                .is_some_and(|t| t.key() == key)
            {
                return;
            }
            session.nodes.insert(token.node_id, token);
        } else {
            if session.entities.contains_key(key) {
                return;
            }
            let endpoints = endpoints_of(&token, key, gid);
            session
                .entities
                .insert(key.to_owned(), (token, endpoints.clone()));
            events.extend(
                endpoints
                    .into_iter()
                    .map(DiscoveryEvent::EndpointDiscovered),
            );
        }
        let info = session.entities_info();
        let enclave = Some(session.enclave.clone());
        state.tokens += 1;
        if new_session {
            state.send(DiscoveryEvent::ParticipantDiscovered(
                DiscoveredParticipant {
                    gid,
                    vendor_id: VendorId::ZENOH,
                    enclave,
                },
            ));
        }
        for event in events {
            let matched = match &event {
                DiscoveryEvent::EndpointDiscovered(e) => state.local_matches(e),
                _ => Vec::new(),
            };
            state.send(event);
            for m in matched {
                state.send(m);
            }
        }
        state.send(DiscoveryEvent::ParticipantEntities(info));
    }

    fn delete(state: &mut GraphState, token: &Token, key: &str) {
        let Some(session) = state.sessions.get_mut(&token.zid) else {
            return;
        };
        let mut events = Vec::new();
        if token.kind == EntityKind::Node {
            if session.nodes.remove(&token.node_id).is_none() {
                return;
            }
        } else {
            let Some((_, endpoints)) = session.entities.remove(key) else {
                return;
            };
            events.extend(endpoints.into_iter().map(|e| DiscoveryEvent::EndpointLost {
                gid: e.gid,
                kind: e.kind,
            }));
        }
        state.tokens = state.tokens.saturating_sub(1);
        let info = session.entities_info();
        let gone = session.is_empty().then_some(session.gid);
        for event in events {
            state.send(event);
        }
        state.send(DiscoveryEvent::ParticipantEntities(info));
        if let Some(gid) = gone {
            state.sessions.remove(&token.zid);
            state.send(DiscoveryEvent::ParticipantLost { gid });
        }
    }

    /// One of this context's endpoints was made: it is matched with what it reaches.
    pub(crate) fn add_local(&self, gid: Gid, kind: EndpointKind, topic: &str, type_name: &str) {
        let mut state = lock(&self.state);
        let local = LocalEndpoint {
            kind,
            topic: topic.to_owned(),
            type_name: type_name.to_owned(),
        };
        let mut events = Vec::new();
        for s in state.sessions.values() {
            for (_, endpoints) in s.entities.values() {
                for e in endpoints {
                    if matches(
                        kind,
                        (topic, type_name),
                        e.kind,
                        (&e.dds_topic_name, &e.dds_type_name),
                    ) {
                        events.push(DiscoveryEvent::Matched {
                            local: gid,
                            remote: e.gid,
                        });
                    }
                }
            }
        }
        for (other_gid, o) in &state.local {
            if matches(kind, (topic, type_name), o.kind, (&o.topic, &o.type_name)) {
                events.push(DiscoveryEvent::Matched {
                    local: gid,
                    remote: *other_gid,
                });
                events.push(DiscoveryEvent::Matched {
                    local: *other_gid,
                    remote: gid,
                });
            }
        }
        state.local.insert(gid, local);
        for event in events {
            state.send(event);
        }
    }

    /// Whether another session has a subscription on `topic` of `type_name` (a token seen).
    pub(crate) fn has_remote_reader(&self, topic: &str, type_name: &str) -> bool {
        lock(&self.state).sessions.values().any(|s| {
            s.entities.values().any(|(_, endpoints)| {
                endpoints.iter().any(|e| {
                    matches(
                        EndpointKind::Writer,
                        (topic, type_name),
                        e.kind,
                        (&e.dds_topic_name, &e.dds_type_name),
                    )
                })
            })
        })
    }

    /// One of this context's endpoints went.
    pub(crate) fn remove_local(&self, gid: Gid) {
        lock(&self.state).local.remove(&gid);
    }

    /// Opens the feed (replacing a previous one): it reports `local` first, then the current
    /// graph, then every change.
    pub(crate) fn open_feed(self: &Arc<Self>, local: LocalEvents) -> PushFeed {
        let mut state = lock(&self.state);
        let queue = Arc::new(FeedQueue::new(state.snapshot(), MAX_FEED_EVENTS));
        state.feed = Some(Arc::clone(&queue));
        let closing = ZenohFeed {
            graph: Arc::clone(self),
            queue: Arc::clone(&queue),
        };
        PushFeed::new(queue, local, closing)
    }
}

/// What closes the context's feed on the graph when the feed goes (a later one starts from a
/// new snapshot).
pub(crate) struct ZenohFeed {
    graph: Arc<Graph>,
    queue: Arc<FeedQueue>,
}

impl Drop for ZenohFeed {
    fn drop(&mut self) {
        let mut state = lock(&self.graph.state);
        if state
            .feed
            .as_ref()
            .is_some_and(|f| Arc::ptr_eq(f, &self.queue))
        {
            state.feed = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_rmw_contract::FeedBackend;

    const NODE: &str = "@ros2_lv/0/f60efce6758d919f6932f83718eeed34/0/0/NN/%/%/talker";
    const TALKER_MP: &str = "@ros2_lv/0/f60efce6758d919f6932f83718eeed34/0/10/MP/%/%/talker/%chatter/std_msgs::msg::dds_::String_/RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18/::,10:,:,:,,";
    const SERVER: &str = "@ros2_lv/0/f60efce6758d919f6932f83718eeed34/0/11/SS/%/%/talker/%add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a/::,10:,:,:,,";

    fn drain(feed: &mut PushFeed) -> Vec<DiscoveryEvent> {
        std::iter::from_fn(|| feed.try_next()).collect()
    }

    #[test]
    fn tokens_become_a_participant_its_node_and_endpoints_and_go_again() {
        let graph = Arc::new(Graph::new("1".to_owned(), 0));
        let (_sink, local) = horus_ros_rmw_contract::local_sink::LocalSink::new();
        let mut feed = graph.open_feed(local);
        graph.token(NODE, true);
        graph.token(TALKER_MP, true);
        graph.token(TALKER_MP, true); // a repeat (history and get) is ignored
        graph.token(SERVER, true);
        let events = drain(&mut feed);
        let participant = participant_gid("f60efce6758d919f6932f83718eeed34");
        assert!(
            matches!(&events[0], DiscoveryEvent::ParticipantDiscovered(p)
            if p.gid == participant && p.enclave.as_deref() == Some("/"))
        );
        let endpoints: Vec<&DiscoveredEndpoint> = events
            .iter()
            .filter_map(|e| match e {
                DiscoveryEvent::EndpointDiscovered(e) => Some(e),
                _ => None,
            })
            .collect();
        assert_eq!(endpoints.len(), 3);
        assert_eq!(endpoints[0].dds_topic_name, "rt/chatter");
        assert_eq!(endpoints[0].gid, gid_of_key(TALKER_MP));
        assert_eq!(endpoints[1].dds_topic_name, "rq/add_two_intsRequest");
        assert_eq!(
            endpoints[1].dds_type_name,
            "example_interfaces::srv::dds_::AddTwoInts_Request_"
        );
        assert_eq!(endpoints[1].gid, gid_of_key(SERVER));
        assert_eq!(endpoints[2].dds_topic_name, "rr/add_two_intsReply");
        assert_eq!(endpoints[2].kind, EndpointKind::Writer);
        let Some(DiscoveryEvent::ParticipantEntities(info)) = events.last() else {
            panic!("{events:?}")
        };
        assert_eq!(info.node_entities_info_seq.len(), 1);
        let node = &info.node_entities_info_seq[0];
        assert_eq!(
            (node.node_namespace.as_str(), node.node_name.as_str()),
            ("/", "talker")
        );
        assert_eq!(
            node.writer_gid_seq,
            vec![gid_of_key(TALKER_MP), endpoints[2].gid]
        );
        assert_eq!(node.reader_gid_seq, vec![gid_of_key(SERVER)]);

        // A DELETE waits for its confirmation: refuted (the token still answers), or cancelled
        // by a PUT, nothing changes; confirmed, the entity goes.
        let ticket = graph
            .token(TALKER_MP, false)
            .expect("a known token's DELETE");
        graph.confirm_delete(TALKER_MP, ticket, false);
        let ticket = graph.token(SERVER, false).expect("a known token's DELETE");
        graph.token(SERVER, true);
        graph.confirm_delete(SERVER, ticket, true);
        assert!(drain(&mut feed).is_empty());
        assert_eq!(
            graph.token("@ros2_lv/0/unknown/0/9/NN/%/%/nobody", false),
            None
        );
        for key in [TALKER_MP, SERVER, NODE] {
            let ticket = graph.token(key, false).expect("a known token's DELETE");
            graph.confirm_delete(key, ticket, true);
        }
        let events = drain(&mut feed);
        assert_eq!(
            events
                .iter()
                .filter(|e| matches!(e, DiscoveryEvent::EndpointLost { .. }))
                .count(),
            3
        );
        assert_eq!(
            events.last(),
            Some(&DiscoveryEvent::ParticipantLost { gid: participant })
        );
        assert_eq!(lock(&graph.state).tokens, 0);
    }

    #[test]
    fn a_sessions_enclave_comes_with_whichever_token_comes_first() {
        // Tokens come in no particular order (the subscriber's history and the liveliness
        // query's replies): here an entity's before its node's, both in the enclave /robot.
        let graph = Arc::new(Graph::new("1".to_owned(), 0));
        let (_sink, local) = horus_ros_rmw_contract::local_sink::LocalSink::new();
        let mut feed = graph.open_feed(local);
        graph.token(&TALKER_MP.replace("/MP/%/%/", "/MP/%robot/%/"), true);
        graph.token(&NODE.replace("/NN/%/%/", "/NN/%robot/%/"), true);
        let participant = participant_gid("f60efce6758d919f6932f83718eeed34");
        let discovered: Vec<DiscoveredParticipant> = drain(&mut feed)
            .into_iter()
            .filter_map(|e| match e {
                DiscoveryEvent::ParticipantDiscovered(p) => Some(p),
                _ => None,
            })
            .collect();
        assert_eq!(discovered.len(), 1, "{discovered:?}");
        assert_eq!(discovered[0].gid, participant);
        assert_eq!(discovered[0].enclave.as_deref(), Some("/robot"));
        // A feed opened later reports it too.
        let (_sink, local) = horus_ros_rmw_contract::local_sink::LocalSink::new();
        let mut late = graph.open_feed(local);
        assert!(matches!(
            drain(&mut late).first(),
            Some(DiscoveryEvent::ParticipantDiscovered(p)) if p.enclave.as_deref() == Some("/robot")
        ));
    }

    #[test]
    fn own_other_domain_and_malformed_tokens_are_dropped() {
        let graph = Arc::new(Graph::new("f60efce6758d919f6932f83718eeed34".to_owned(), 0));
        let (_sink, local) = horus_ros_rmw_contract::local_sink::LocalSink::new();
        let mut feed = graph.open_feed(local);
        graph.token(TALKER_MP, true);
        graph.token(&TALKER_MP.replace("@ros2_lv/0/f60", "@ros2_lv/1/a60"), true);
        graph.token("@ros2_lv/0/abc/0/0/XX", true);
        graph.token("@ros2_lv/0/abc/0/0/YY", true);
        assert!(drain(&mut feed).is_empty());
        assert_eq!(lock(&graph.state).warned.len(), 1);
    }

    #[test]
    fn a_late_feed_gets_the_graph_and_local_endpoints_are_matched() {
        let graph = Arc::new(Graph::new("1".to_owned(), 0));
        graph.token(NODE, true);
        graph.token(TALKER_MP, true);
        let ours = Gid::from_bytes([7; 16]);
        graph.add_local(
            ours,
            EndpointKind::Reader,
            "rt/chatter",
            "std_msgs::msg::dds_::String_",
        );
        let (_sink, local) = horus_ros_rmw_contract::local_sink::LocalSink::new();
        let mut feed = graph.open_feed(local);
        let events = drain(&mut feed);
        assert!(events.contains(&DiscoveryEvent::Matched {
            local: ours,
            remote: gid_of_key(TALKER_MP)
        }));
        assert!(matches!(
            events[0],
            DiscoveryEvent::ParticipantDiscovered(_)
        ));
    }
}
