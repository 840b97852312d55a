//! A test backend that keeps everything in memory: it implements the backend contract
//! (`horus-ros-rmw-contract`, its only horus-ros dependency beside the messages) without any
//! middleware, to show that a context, its nodes, the graph cache and the services layer need
//! nothing beyond the contract, and that a backend outside horus-ros' own list plugs in with
//! `Context::builder().implementation(...)` and passes the conformance suite
//! (`tests/conformance.rs`) with no change to any other crate.
//!
//! One [`Bus`] per domain id, process-wide: every participant of that domain, its readers and
//! writers, and its latest `ros_discovery_info` message. Samples are delivered synchronously,
//! under the bus lock, to every matched reader's bounded queue; waits are condition variables
//! (no polling). Matching follows DDS on what the tests need: same topic and type name, a
//! RELIABLE reader only with a RELIABLE writer, a TRANSIENT_LOCAL reader only with a
//! TRANSIENT_LOCAL writer (which replays its last `depth` samples to it). Other policies,
//! discovery ranges and static peers are ignored: every participant of the domain sees every
//! other.
//!
//! GIDs keep the DDS layout the graph relies on: a 12-byte participant prefix (vendor
//! [`VENDOR`], the process id, a process-wide counter) + a 4-byte entity id (participant
//! `00 00 01 c1`; readers and writers a counter and the RTPS entity kind, `0x04`/`0x03`).

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Duration;

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use horus_ros_rmw_contract::push::{lock, FeedQueue, PushFeed, SampleQueue, WaitSet};
use horus_ros_rmw_contract::qos::{
    DdsDurability, DdsHistory, DdsQos, DdsReliability, EndpointKind,
};
use horus_ros_rmw_contract::{
    unix_time_ns, Capabilities, DdsError, DiscoveredEndpoint, DiscoveredParticipant,
    DiscoveryEvent, DiscoveryFeedError, FeedBackend, Gid, Implementation, LocalEvents,
    ParticipantBackend, ParticipantConfig, RawEndpointSpec, RawSample, ReaderBackend, SampleId,
    VendorId, WaitSetBackend, WaitSetError, Wake, WriterBackend,
};

/// The vendor id its participants announce: none of the DDS vendors, so the services layer
/// speaks the rmw_fastrtps convention (`related_sample_identity`) with them.
pub const VENDOR: VendorId = VendorId([0x01, 0xfe]);
/// Most samples a reader queues (fewer with a KEEP_LAST depth); the oldest go first.
const MAX_SAMPLES: usize = 1000;
/// Most events a feed queues before the oldest are dropped (a test reads its feeds promptly).
const MAX_FEED_EVENTS: usize = 100_000;

/// The in-memory backend; see the module documentation.
#[derive(Debug, Default)]
pub struct Memory;

/// The backend, for `Context::builder().implementation(...)`.
pub fn implementation() -> Arc<dyn Implementation> {
    Arc::new(Memory)
}

/// One domain: its participants and their endpoints.
#[derive(Default)]
struct Bus {
    state: Mutex<BusState>,
}

/// The bus of `domain`, made on first use and kept for the process.
fn bus(domain: u16) -> Arc<Bus> {
    static BUSES: OnceLock<Mutex<HashMap<u16, Arc<Bus>>>> = OnceLock::new();
    let buses = BUSES.get_or_init(Mutex::default);
    Arc::clone(lock(buses).entry(domain).or_default())
}

#[derive(Default)]
struct BusState {
    participants: BTreeMap<Gid, Peer>,
    endpoints: BTreeMap<Gid, Endpoint>,
}

/// A participant: its latest `ros_discovery_info` message and its open feed.
#[derive(Default)]
struct Peer {
    info: Option<ParticipantEntitiesInfo>,
    feed: Option<Arc<FeedQueue>>,
}

/// A reader or writer on the bus.
struct Endpoint {
    description: DiscoveredEndpoint,
    reliable: bool,
    transient_local: bool,
    /// How many samples it keeps (a reader's queue; a TRANSIENT_LOCAL writer's history).
    depth: usize,
    /// A reader's queue.
    reader: Option<Arc<ReaderQueue>>,
    /// A writer's last sequence number and, if TRANSIENT_LOCAL, its history.
    sequence_number: i64,
    history: VecDeque<RawSample>,
}

impl Endpoint {
    fn participant(&self) -> Gid {
        self.description.participant_gid
    }

    /// Whether data of one reaches the other (DDS' request-offered rules for what is modelled).
    fn matches(&self, other: &Endpoint) -> bool {
        let (w, r) = match (self.description.kind, other.description.kind) {
            (EndpointKind::Writer, EndpointKind::Reader) => (self, other),
            (EndpointKind::Reader, EndpointKind::Writer) => (other, self),
            _ => return false,
        };
        w.description.dds_topic_name == r.description.dds_topic_name
            && w.description.dds_type_name == r.description.dds_type_name
            && (w.reliable || !r.reliable)
            && (w.transient_local || !r.transient_local)
    }
}

impl BusState {
    /// Queues `event` on the open feed of `participant`, if any.
    fn send(&self, participant: Gid, event: DiscoveryEvent) {
        if let Some(feed) = self
            .participants
            .get(&participant)
            .and_then(|p| p.feed.as_ref())
        {
            feed.push(event);
        }
    }

    /// Queues `event` on every open feed but that of `participant`.
    fn send_to_others(&self, participant: Gid, event: &DiscoveryEvent) {
        for (gid, peer) in &self.participants {
            if let (true, Some(feed)) = (*gid != participant, &peer.feed) {
                feed.push(event.clone());
            }
        }
    }

    fn add_participant(&mut self, gid: Gid) {
        let event = DiscoveryEvent::ParticipantDiscovered(discovered(gid));
        self.send_to_others(gid, &event);
        self.participants.insert(gid, Peer::default());
    }

    fn remove_participant(&mut self, gid: Gid) {
        let own: Vec<Gid> = self
            .endpoints
            .iter()
            .filter(|(_, e)| e.participant() == gid)
            .map(|(g, _)| *g)
            .collect();
        for endpoint in own {
            self.remove_endpoint(endpoint);
        }
        self.participants.remove(&gid);
        self.send_to_others(gid, &DiscoveryEvent::ParticipantLost { gid });
    }

    /// Adds an endpoint: discovered by the others, then matched on both sides (a new
    /// TRANSIENT_LOCAL reader gets the history of the writers it matches).
    fn add_endpoint(&mut self, endpoint: Endpoint) {
        let gid = endpoint.description.gid;
        let participant = endpoint.participant();
        let event = DiscoveryEvent::EndpointDiscovered(endpoint.description.clone());
        self.send_to_others(participant, &event);
        for (other_gid, other) in &self.endpoints {
            if !endpoint.matches(other) {
                continue;
            }
            self.send(participant, matched(gid, *other_gid));
            self.send(other.participant(), matched(*other_gid, gid));
            if let (Some(queue), true) = (&endpoint.reader, endpoint.transient_local) {
                for sample in &other.history {
                    queue.deliver(sample.clone());
                }
            }
        }
        self.endpoints.insert(gid, endpoint);
    }

    fn remove_endpoint(&mut self, gid: Gid) {
        if let Some(e) = self.endpoints.remove(&gid) {
            let event = DiscoveryEvent::EndpointLost {
                gid,
                kind: e.description.kind,
            };
            self.send_to_others(e.participant(), &event);
        }
    }

    /// Everything a feed of `participant` opened now reports first.
    fn snapshot(&self, participant: Gid) -> VecDeque<DiscoveryEvent> {
        let others = self.participants.iter().filter(|(g, _)| **g != participant);
        let mut events: VecDeque<DiscoveryEvent> = others
            .clone()
            .map(|(gid, _)| DiscoveryEvent::ParticipantDiscovered(discovered(*gid)))
            .collect();
        for e in self.endpoints.values() {
            if e.participant() != participant {
                events.push_back(DiscoveryEvent::EndpointDiscovered(e.description.clone()));
            }
        }
        for info in others.filter_map(|(_, p)| p.info.clone()) {
            events.push_back(DiscoveryEvent::ParticipantEntities(info));
        }
        for (gid, e) in &self.endpoints {
            if e.participant() == participant {
                for (other_gid, other) in &self.endpoints {
                    if e.matches(other) {
                        events.push_back(matched(*gid, *other_gid));
                    }
                }
            }
        }
        events
    }
}

fn discovered(gid: Gid) -> DiscoveredParticipant {
    DiscoveredParticipant {
        gid,
        vendor_id: VENDOR,
        // Not announced: as a DDS backend that reads no participant USER_DATA.
        enclave: None,
    }
}

fn matched(local: Gid, remote: Gid) -> DiscoveryEvent {
    DiscoveryEvent::Matched { local, remote }
}

impl Implementation for Memory {
    fn name(&self) -> &'static str {
        "memory"
    }

    fn rmw_implementation(&self) -> &'static str {
        "rmw_memory_test"
    }

    fn vendor_id(&self) -> VendorId {
        VENDOR
    }

    fn capabilities(&self) -> Capabilities {
        Capabilities::NONE
            .with_sample_identity()
            .with_type_hashes_announced()
    }

    fn create_participant(
        &self,
        config: &ParticipantConfig<'_>,
    ) -> Result<Box<dyn ParticipantBackend>, DdsError> {
        static PARTICIPANTS: AtomicU64 = AtomicU64::new(1);
        let n = PARTICIPANTS.fetch_add(1, Ordering::Relaxed);
        let mut bytes = [0u8; 16];
        bytes[..2].copy_from_slice(&VENDOR.0);
        bytes[2..6].copy_from_slice(&std::process::id().to_be_bytes());
        bytes[6..12].copy_from_slice(&n.to_be_bytes()[2..]);
        bytes[12..].copy_from_slice(&[0x00, 0x00, 0x01, 0xc1]);
        let gid = Gid::from_bytes(bytes);
        let bus = bus(config.domain.get());
        lock(&bus.state).add_participant(gid);
        Ok(Box::new(MemoryParticipant {
            bus,
            gid,
            entities: AtomicU32::new(0),
            deleted: AtomicBool::new(false),
        }))
    }
}

/// A participant on its domain's bus.
struct MemoryParticipant {
    bus: Arc<Bus>,
    gid: Gid,
    entities: AtomicU32,
    deleted: AtomicBool,
}

impl MemoryParticipant {
    /// Puts a new endpoint of `kind` on the bus; its GID.
    fn add(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
        kind: EndpointKind,
        reader: Option<Arc<ReaderQueue>>,
    ) -> Result<Gid, DdsError> {
        let n = self.entities.fetch_add(1, Ordering::Relaxed) + 1;
        let mut bytes = *self.gid.as_bytes();
        bytes[12..15].copy_from_slice(&n.to_be_bytes()[1..]);
        // RTPS entity kinds: user writer / reader without key.
        bytes[15] = match kind {
            EndpointKind::Writer => 0x03,
            EndpointKind::Reader => 0x04,
        };
        let gid = Gid::from_bytes(bytes);
        let endpoint = Endpoint {
            description: DiscoveredEndpoint {
                gid,
                participant_gid: self.gid,
                kind,
                dds_topic_name: spec.dds_topic_name.clone(),
                dds_type_name: spec.dds_type_name.clone(),
                qos: spec.qos.effective(kind),
                type_hash: spec.type_hash,
                user_data: Vec::new(),
            },
            reliable: matches!(qos.reliability, DdsReliability::Reliable { .. }),
            transient_local: qos.durability != DdsDurability::Volatile,
            depth: depth(qos),
            reader,
            sequence_number: 0,
            history: VecDeque::new(),
        };
        // Checked under the bus lock: no endpoint outlives a deletion on the bus.
        let mut bus = lock(&self.bus.state);
        if self.deleted.load(Ordering::SeqCst) {
            return Err(DdsError::ParticipantDeleted);
        }
        bus.add_endpoint(endpoint);
        Ok(gid)
    }
}

/// How many samples an endpoint with `qos` keeps.
fn depth(qos: &DdsQos) -> usize {
    match qos.history {
        Some(DdsHistory::KeepLast(n)) => (n as usize).clamp(1, MAX_SAMPLES),
        Some(DdsHistory::KeepAll) | None => MAX_SAMPLES,
    }
}

impl ParticipantBackend for MemoryParticipant {
    fn gid(&self) -> Gid {
        self.gid
    }

    fn create_writer(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        let gid = self.add(spec, qos, EndpointKind::Writer, None)?;
        let bus = Arc::clone(&self.bus);
        Ok((Box::new(MemoryWriter { bus, gid }), gid))
    }

    /// Readers get every response: the servers address the reader a request names (`only_to`).
    fn create_reader(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
        _responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        let queue = Arc::new(ReaderQueue::new(depth(qos)));
        let gid = self.add(spec, qos, EndpointKind::Reader, Some(Arc::clone(&queue)))?;
        let bus = Arc::clone(&self.bus);
        Ok((Box::new(MemoryReader { bus, gid, queue }), gid))
    }

    fn publish_discovery_info(&self, message: &ParticipantEntitiesInfo) {
        let mut bus = lock(&self.bus.state);
        if let Some(peer) = bus.participants.get_mut(&self.gid) {
            peer.info = Some(message.clone());
            let event = DiscoveryEvent::ParticipantEntities(message.clone());
            bus.send_to_others(self.gid, &event);
        }
    }

    /// Delivered at once: every peer has it.
    fn wait_for_discovery_info_acks(&self, _limit: Duration) -> bool {
        true
    }

    fn delete(&self) {
        let mut bus = lock(&self.bus.state);
        if !self.deleted.swap(true, Ordering::SeqCst) {
            bus.remove_participant(self.gid);
        }
    }

    fn open_feed(&self, local: LocalEvents) -> Result<Box<dyn FeedBackend>, DiscoveryFeedError> {
        let mut bus = lock(&self.bus.state);
        let events = bus.snapshot(self.gid);
        let Some(peer) = bus.participants.get_mut(&self.gid) else {
            return Err(DiscoveryFeedError::Reader {
                cause: DdsError::ParticipantDeleted,
            });
        };
        let queue = Arc::new(FeedQueue::new(events, MAX_FEED_EVENTS));
        peer.feed = Some(Arc::clone(&queue));
        let closing = MemoryFeed {
            bus: Arc::clone(&self.bus),
            participant: self.gid,
            queue: Arc::clone(&queue),
        };
        Ok(Box::new(PushFeed::new(queue, local, closing)))
    }

    fn create_wait_set(&self) -> Result<Box<dyn WaitSetBackend>, WaitSetError> {
        Ok(Box::new(WaitSet {
            shared: Arc::default(),
        }))
    }
}

impl Drop for MemoryParticipant {
    fn drop(&mut self) {
        self.delete();
    }
}

/// A writer: delivers each sample, under the bus lock, to the queues of its matched readers.
struct MemoryWriter {
    bus: Arc<Bus>,
    gid: Gid,
}

impl WriterBackend for MemoryWriter {
    fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        let mut bus = lock(&self.bus.state);
        let bus = &mut *bus;
        let writer = bus
            .endpoints
            .get_mut(&self.gid)
            .ok_or(DdsError::ParticipantDeleted)?;
        writer.sequence_number += 1;
        let id = SampleId {
            writer: self.gid,
            sequence_number: writer.sequence_number,
        };
        let sample = RawSample {
            body,
            big_endian: false,
            id,
            related,
            publication_handle: None,
            source_timestamp: Some(unix_time_ns()),
            received_timestamp: 0,
        };
        if writer.transient_local {
            if writer.history.len() >= writer.depth {
                writer.history.pop_front();
            }
            writer.history.push_back(sample.clone());
        }
        let writer = &bus.endpoints[&self.gid];
        for (gid, reader) in &bus.endpoints {
            if only_to.is_some_and(|to| to != *gid) || !writer.matches(reader) {
                continue;
            }
            if let Some(queue) = &reader.reader {
                queue.deliver(sample.clone());
            }
        }
        Ok(id)
    }

    /// Delivered at once: nothing is left unacknowledged.
    fn wait_for_acknowledgments(&self, _timeout: Duration) -> bool {
        true
    }
}

impl Drop for MemoryWriter {
    fn drop(&mut self) {
        lock(&self.bus.state).remove_endpoint(self.gid);
    }
}

/// A reader's bounded queue and whom it wakes.
type ReaderQueue = SampleQueue<RawSample>;

struct MemoryReader {
    bus: Arc<Bus>,
    gid: Gid,
    queue: Arc<ReaderQueue>,
}

impl ReaderBackend for MemoryReader {
    fn take(&mut self) -> Result<Option<RawSample>, DdsError> {
        let sample = self.queue.pop();
        Ok(sample.map(|s| RawSample {
            received_timestamp: unix_time_ns(),
            ..s
        }))
    }

    fn wait(&mut self, timeout: Option<Duration>) -> bool {
        self.queue.wait(timeout)
    }

    fn waker(&self) -> Arc<dyn Wake> {
        self.queue.waker()
    }

    fn attach_to(&mut self, set: &dyn WaitSetBackend, key: usize) -> Result<(), WaitSetError> {
        self.queue.attach_to(set, key)
    }
}

impl Drop for MemoryReader {
    fn drop(&mut self) {
        lock(&self.bus.state).remove_endpoint(self.gid);
    }
}

/// What closes a participant's feed on the bus when the feed goes (a later one starts from a
/// new snapshot).
struct MemoryFeed {
    bus: Arc<Bus>,
    participant: Gid,
    queue: Arc<FeedQueue>,
}

impl Drop for MemoryFeed {
    /// Closes the feed on the bus (a later one starts from a new snapshot).
    fn drop(&mut self) {
        let mut bus = lock(&self.bus.state);
        if let Some(peer) = bus.participants.get_mut(&self.participant) {
            if peer
                .feed
                .as_ref()
                .is_some_and(|f| Arc::ptr_eq(f, &self.queue))
            {
                peer.feed = None;
            }
        }
    }
}
