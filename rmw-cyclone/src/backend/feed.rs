//! The Cyclone discovery feed: DCPSParticipant / DCPSPublication / DCPSSubscription (remote
//! USER_DATA included), other participants' `ros_discovery_info`, the matches of our own
//! endpoints, and the context's own changes, all waited on with one waitset in the caller's
//! thread (no code of ours runs on Cyclone's threads).

use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::{self as cyc, BuiltinSample, BuiltinTopic, StatusMask};
use horus_ros_msgs::rmw_dds_common::{Gid, ParticipantEntitiesInfo};
use horus_ros_msgs::user_data::parse_type_hash_from_user_data;
use horus_ros_msgs::TypeHash;

use super::{cyclone_error, gid, qos, CycloneParticipant, LocalEndpoints};
use horus_ros_dds_common::discovery_info::{TOPIC_NAME, TYPE_NAME};
use horus_ros_dds_common::late_joiner::{InfoReaderSource, LateJoiner, Taken};
use horus_ros_rmw_contract::discovery::{
    DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId,
};
use horus_ros_rmw_contract::qos::EndpointKind;
use horus_ros_rmw_contract::DiscoveryFeedError;
use horus_ros_rmw_contract::{FeedBackend, LocalEvents, Wake};

const GUARD: usize = 0;
const PARTICIPANTS: usize = 1;
const PUBLICATIONS: usize = 2;
const SUBSCRIPTIONS: usize = 3;
const INFO: usize = 4;
const LATE_JOINER: usize = 5;
/// Tokens of our own endpoints' matched statuses start here.
const FIRST_ENDPOINT_TOKEN: usize = 16;

/// Wakes the feed's waitset from the context's side.
struct GuardWake(cyc::GuardCondition);

impl Wake for GuardWake {
    fn wake(&self) {
        if let Err(e) = self.0.trigger() {
            tracing::debug!("could not wake the discovery feed: {e}");
        }
    }
}

/// The enclave a participant announces in USER_DATA (`enclave=…;`), as rmw_dds_common's
/// discovery reads it.
fn enclave(user_data: &[u8]) -> Option<String> {
    let kv = horus_ros_msgs::user_data::parse_key_value(user_data);
    kv.get("enclave")
        .map(|v| String::from_utf8_lossy(v).into_owned())
}

/// The status that changes when an endpoint of `kind` is matched or unmatched.
fn matched_status(kind: EndpointKind) -> StatusMask {
    match kind {
        EndpointKind::Writer => StatusMask::PUBLICATION_MATCHED,
        EndpointKind::Reader => StatusMask::SUBSCRIPTION_MATCHED,
    }
}

/// One of our endpoints whose matches are watched.
struct Watched {
    gid: Gid,
    entity: cyc::WeakEntity,
    kind: EndpointKind,
    matched: HashSet<Gid>,
}

/// The Cyclone side of a discovery feed.
pub(crate) struct CycloneDiscoveryFeed {
    waiter: cyc::Waiter,
    guard: Arc<GuardWake>,
    participants: cyc::BuiltinReader,
    publications: cyc::BuiltinReader,
    subscriptions: cyc::BuiltinReader,
    info: cyc::Reader,
    /// What creates the late-joiner `ros_discovery_info` reader.
    participant: cyc::Participant,
    late_topic: cyc::Topic,
    /// The extra reader announced after a peer's `ros_discovery_info` writer was discovered
    /// (see [`horus_ros_dds_common::late_joiner`]).
    late_joiner: LateJoiner<cyc::Reader>,
    local: LocalEvents,
    local_endpoints: Arc<LocalEndpoints>,
    watched: HashMap<usize, Watched>,
    token_of: HashMap<Gid, usize>,
    next_token: usize,
    own_gid: Gid,
    known_participants: HashSet<Gid>,
    known_endpoints: HashSet<Gid>,
    pending: VecDeque<DiscoveryEvent>,
}

impl CycloneDiscoveryFeed {
    /// Creates the built-in readers (which also deliver what was discovered before), the
    /// `ros_discovery_info` reader and the waitset.
    pub(crate) fn new(
        p: &CycloneParticipant,
        info_topic: &cyc::Topic,
        local: LocalEvents,
    ) -> Result<Self, DiscoveryFeedError> {
        let reader = |e| DiscoveryFeedError::Reader {
            cause: cyclone_error(e),
        };
        let poll = |e| DiscoveryFeedError::Poll {
            cause: cyclone_error(e),
        };
        let participants = p
            .participant
            .builtin_reader(BuiltinTopic::Participant)
            .map_err(reader)?;
        let publications = p
            .participant
            .builtin_reader(BuiltinTopic::Publication)
            .map_err(reader)?;
        let subscriptions = p
            .participant
            .builtin_reader(BuiltinTopic::Subscription)
            .map_err(reader)?;
        let info = p
            .participant
            .reader(
                info_topic,
                &qos::discovery_info(0),
                super::discovery_info::discovery_info_user_data().as_bytes(),
            )
            .map_err(reader)?;
        let late_topic = p
            .participant
            .blob_topic(TOPIC_NAME, TYPE_NAME)
            .map_err(reader)?;
        let guard = Arc::new(GuardWake(cyc::GuardCondition::new().map_err(poll)?));
        let waiter = cyc::Waiter::new().map_err(poll)?;
        waiter.attach_guard(&guard.0, GUARD).map_err(poll)?;
        waiter
            .attach_builtin(&participants, PARTICIPANTS)
            .map_err(poll)?;
        waiter
            .attach_builtin(&publications, PUBLICATIONS)
            .map_err(poll)?;
        waiter
            .attach_builtin(&subscriptions, SUBSCRIPTIONS)
            .map_err(poll)?;
        waiter.attach_reader(&info, INFO).map_err(poll)?;
        Ok(Self {
            waiter,
            guard,
            participants,
            publications,
            subscriptions,
            info,
            participant: p.participant.clone(),
            late_topic,
            late_joiner: LateJoiner::new(p.gid),
            local,
            local_endpoints: Arc::clone(&p.local_endpoints),
            watched: HashMap::new(),
            token_of: HashMap::new(),
            next_token: FIRST_ENDPOINT_TOKEN,
            own_gid: p.gid,
            known_participants: HashSet::new(),
            known_endpoints: HashSet::new(),
            pending: VecDeque::new(),
        })
    }

    /// Moves everything waiting into `pending`; `triggered` says which statuses fired (all
    /// watched endpoints are checked when unknown).
    fn drain(&mut self, triggered: Option<&[usize]>) {
        // The guard is reset only when a wait reported it: reset here otherwise, a wake that
        // came just before (a graph stopping) would be lost and the next wait never end.
        if triggered.is_some_and(|t| t.contains(&GUARD)) {
            if let Err(e) = self.guard.0.take() {
                tracing::debug!("could not reset the discovery feed's guard: {e}");
            }
        }
        // Our own changes first: they were made before anything discovery reports about them.
        while let Some(event) = self.local.try_next() {
            match &event {
                DiscoveryEvent::EndpointDiscovered(e) => self.watch(e.gid),
                DiscoveryEvent::EndpointLost { gid, .. } => self.unwatch(*gid),
                _ => {}
            }
            self.pending.push_back(event);
        }
        self.take_builtin(BuiltinTopic::Participant);
        self.take_builtin(BuiltinTopic::Publication);
        self.take_builtin(BuiltinTopic::Subscription);
        self.late_joiner
            .take_all::<LateReaders>(&mut self.info, &mut self.pending);
        let mut source = LateReaders {
            waiter: &self.waiter,
            participant: &self.participant,
            topic: &self.late_topic,
        };
        self.late_joiner
            .update(&mut source, &mut self.pending, Instant::now());
        let tokens: Vec<usize> = match triggered {
            Some(t) => t
                .iter()
                .copied()
                .filter(|t| *t >= FIRST_ENDPOINT_TOKEN)
                .collect(),
            None => self.watched.keys().copied().collect(),
        };
        for token in tokens {
            self.check_matches(token, false);
        }
    }

    /// Starts watching one of our endpoints' matches.
    fn watch(&mut self, gid: Gid) {
        if self.token_of.contains_key(&gid) {
            return;
        }
        let Some((entity, kind)) = self.local_endpoints.get(gid) else {
            return; // already gone again
        };
        let token = self.next_token;
        self.next_token += 1;
        if let Err(e) = self
            .waiter
            .attach_status(&entity, matched_status(kind), token)
        {
            tracing::warn!(endpoint = %gid, "cannot watch an endpoint's matches: {e}");
            return;
        }
        self.token_of.insert(gid, token);
        self.watched.insert(
            token,
            Watched {
                gid,
                entity: entity.downgrade(),
                kind,
                matched: HashSet::new(),
            },
        );
        // Matches made before the watch started.
        self.check_matches(token, true);
    }

    fn unwatch(&mut self, gid: Gid) {
        if let Some(token) = self.token_of.remove(&gid) {
            self.watched.remove(&token);
            if let Err(e) = self.waiter.detach(token) {
                tracing::debug!(endpoint = %gid, "detaching a watched endpoint: {e}");
            }
        }
    }

    /// Reports the endpoint's new matches (a match ends when either endpoint is lost). The
    /// matched list is read only when its matched status changed, unless `always`.
    fn check_matches(&mut self, token: usize, always: bool) {
        let Some(w) = self.watched.get_mut(&token) else {
            return;
        };
        let Some(entity) = w.entity.upgrade() else {
            return;
        };
        let mask = matched_status(w.kind);
        // Resets the status condition; the list below is the truth.
        let changed = entity
            .take_status(mask)
            .map_or(true, |set| set.contains(mask));
        if !changed && !always {
            return;
        }
        let matched = match w.kind {
            EndpointKind::Writer => entity.matched_subscriptions(),
            EndpointKind::Reader => entity.matched_publications(),
        };
        let matched = match matched {
            Ok(m) => m,
            Err(e) => {
                tracing::debug!(endpoint = %w.gid, "reading matches failed: {e}");
                return;
            }
        };
        let now: HashSet<Gid> = matched.iter().map(|m| gid(m.guid)).collect();
        for remote in &now {
            if !w.matched.contains(remote) {
                self.pending.push_back(DiscoveryEvent::Matched {
                    local: w.gid,
                    remote: *remote,
                });
            }
        }
        w.matched = now;
    }

    fn take_builtin(&mut self, topic: BuiltinTopic) {
        let reader = match topic {
            BuiltinTopic::Participant => &self.participants,
            BuiltinTopic::Publication => &self.publications,
            BuiltinTopic::Subscription => &self.subscriptions,
        };
        let samples = match reader.take() {
            Ok(s) => s,
            Err(e) => {
                tracing::warn!("reading a built-in discovery topic failed: {e}");
                return;
            }
        };
        for sample in samples {
            if let Some(event) = self.convert(sample) {
                self.late_joiner.observe(&event);
                self.pending.push_back(event);
            }
        }
    }

    fn convert(&mut self, sample: BuiltinSample) -> Option<DiscoveryEvent> {
        let own_prefix = self.own_gid.prefix();
        match sample {
            BuiltinSample::Participant(p) => {
                let g = gid(p.guid);
                // Our own participant is reported by the context itself.
                if g.prefix() == own_prefix {
                    return None;
                }
                if p.alive {
                    self.known_participants.insert(g).then(|| {
                        DiscoveryEvent::ParticipantDiscovered(DiscoveredParticipant {
                            gid: g,
                            vendor_id: VendorId(p.guid.vendor_hint()),
                            enclave: enclave(&p.user_data),
                        })
                    })
                } else {
                    self.known_participants
                        .remove(&g)
                        .then_some(DiscoveryEvent::ParticipantLost { gid: g })
                }
            }
            BuiltinSample::Publication(e) => self.endpoint(e, EndpointKind::Writer),
            BuiltinSample::Subscription(e) => self.endpoint(e, EndpointKind::Reader),
        }
    }

    fn endpoint(&mut self, e: cyc::EndpointInfo, kind: EndpointKind) -> Option<DiscoveryEvent> {
        let g = gid(e.guid);
        // Our own endpoints are reported by the context itself.
        if g.prefix() == self.own_gid.prefix() {
            return None;
        }
        if !e.alive {
            return self
                .known_endpoints
                .remove(&g)
                .then_some(DiscoveryEvent::EndpointLost { gid: g, kind });
        }
        if !self.known_endpoints.insert(g) {
            return None; // an update of one already reported
        }
        let type_hash = parse_type_hash_from_user_data(&e.user_data).unwrap_or_else(|err| {
            tracing::debug!(topic = %e.topic_name, "unusable type hash in USER_DATA: {err}");
            TypeHash::ZERO
        });
        let qos = match &e.qos {
            Some(q) => qos::discovered(q),
            None => horus_ros_rmw_contract::qos::Qos::unknown(),
        };
        Some(DiscoveryEvent::EndpointDiscovered(DiscoveredEndpoint {
            gid: g,
            participant_gid: gid(e.participant_guid),
            kind,
            dds_topic_name: e.topic_name,
            dds_type_name: e.type_name,
            qos,
            type_hash,
            user_data: e.user_data,
        }))
    }
}

/// The Cyclone calls for the feed's late-joiner `ros_discovery_info` reader.
struct LateReaders<'a> {
    waiter: &'a cyc::Waiter,
    participant: &'a cyc::Participant,
    topic: &'a cyc::Topic,
}

impl InfoReaderSource for LateReaders<'_> {
    type Reader = cyc::Reader;
    type CreateError = cyc::Error;
    type AttachError = cyc::Error;

    fn create(&mut self) -> Result<cyc::Reader, cyc::Error> {
        self.participant.reader(
            self.topic,
            &qos::discovery_info(0),
            super::discovery_info::discovery_info_user_data().as_bytes(),
        )
    }

    fn attach(&mut self, reader: &mut cyc::Reader) -> Result<(), cyc::Error> {
        self.waiter.attach_reader(reader, LATE_JOINER)
    }

    fn detach(&mut self, _reader: &mut cyc::Reader) {
        if let Err(e) = self.waiter.detach(LATE_JOINER) {
            tracing::debug!("detaching the late-joiner reader: {e}");
        }
    }

    fn take(reader: &mut cyc::Reader) -> Taken {
        match reader.take() {
            Ok(Some(sample)) => {
                match horus_ros_msgs::cdr::from_cdr::<ParticipantEntitiesInfo>(&sample.cdr) {
                    Ok(info) => Taken::Sample(info),
                    Err(e) => {
                        tracing::warn!("dropped a malformed ros_discovery_info sample: {e}");
                        Taken::Skipped
                    }
                }
            }
            Ok(None) => Taken::End,
            Err(e) => {
                tracing::warn!("reading ros_discovery_info failed: {e}");
                Taken::End
            }
        }
    }
}

impl FeedBackend for CycloneDiscoveryFeed {
    fn try_next(&mut self) -> Option<DiscoveryEvent> {
        if self.pending.is_empty() {
            self.drain(None);
        }
        self.pending.pop_front()
    }

    fn wait(&mut self, limit: Option<Duration>) -> std::io::Result<bool> {
        // The late-joiner reader's retry is due at most then (see `horus_ros_dds_common::late_joiner`).
        let limit = self.late_joiner.wait_limit(limit, Instant::now());
        let triggered = self.waiter.wait_for(limit).map_err(std::io::Error::other)?;
        self.drain(Some(&triggered));
        Ok(!triggered.is_empty())
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::clone(&self.guard) as Arc<dyn Wake>
    }
}
