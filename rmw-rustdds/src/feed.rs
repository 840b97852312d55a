//! Turns rustdds discovery status events and our `ros_discovery_info` reader into
//! [`DiscoveryEvent`]s.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use std::sync::{Arc, Mutex, MutexGuard};

use rustdds::mio1 as mio;

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use horus_ros_msgs::user_data::parse_type_hash_from_user_data;
use horus_ros_msgs::TypeHash;
use rustdds::{
    no_key, CDRDeserializerAdapter, DomainParticipantStatusEvent, DomainParticipantStatusListener,
    EndpointDescription, StatusEvented,
};

use super::gid_from_guid;
use crate::contract::{FeedBackend, LocalEvents, Wake};
use crate::dds::late_joiner::{InfoReaderSource, LateJoiner, Taken};
use crate::discovery::{DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId};
use horus_ros_rmw_contract::qos::{EndpointKind, Qos};
use horus_ros_rmw_contract::Gid;

const STATUS: mio::Token = mio::Token(0);
const INFO: mio::Token = mio::Token(1);
const LOCAL: mio::Token = mio::Token(2);
const LATE_JOINER: mio::Token = mio::Token(3);

type InfoReader =
    no_key::DataReader<ParticipantEntitiesInfo, CDRDeserializerAdapter<ParticipantEntitiesInfo>>;

/// Wakes the feed's poll from the context's side.
struct MioWake(mio::Waker);

impl Wake for MioWake {
    fn wake(&self) {
        // A failed wake only delays the event until the feed's next wake-up.
        let _ = self.0.wake();
    }
}

/// The participant's status-event listener, shared by the participant (which drops it when it
/// deletes itself: a listener keeps rustdds' participant alive) and the [`StatusPoll`]; `None`
/// once the participant is deleted.
pub(crate) type SharedListener = Arc<Mutex<Option<DomainParticipantStatusListener>>>;

/// The participant's status-event listener registered with a poll instance (and the poll's one
/// waker). rustdds lets a listener be registered only once, so this outlives each feed and is
/// handed back when a feed closes.
pub(crate) struct StatusPoll {
    poll: mio::Poll,
    waker: Arc<MioWake>,
    listener: SharedListener,
}

impl StatusPoll {
    /// Registers `listener` with a new poll instance.
    pub(crate) fn new(listener: SharedListener) -> std::io::Result<Self> {
        let poll = mio::Poll::new()?;
        if let Some(l) = lock(&listener).as_mut() {
            poll.registry()
                .register(l, STATUS, mio::Interest::READABLE)?;
        }
        let waker = Arc::new(MioWake(mio::Waker::new(poll.registry(), LOCAL)?));
        Ok(Self {
            poll,
            waker,
            listener,
        })
    }

    /// The next status event, if any (none once the participant is deleted).
    fn try_recv(&self) -> Option<DomainParticipantStatusEvent> {
        lock(&self.listener).as_ref()?.try_recv_status()
    }
}

/// Locks a mutex whose data stays consistent even if a holder panicked.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// What creates `ros_discovery_info` readers: the late-joiner reader is created as the feed goes.
pub(crate) struct InfoReaderFactory {
    /// The participant's subscriber.
    pub(crate) subscriber: rustdds::Subscriber,
    /// The `ros_discovery_info` topic.
    pub(crate) topic: rustdds::Topic,
}

/// The rustdds calls for the feed's late-joiner `ros_discovery_info` reader.
struct LateReaders<'a> {
    factory: &'a InfoReaderFactory,
    status: &'a Mutex<StatusPoll>,
}

impl InfoReaderSource for LateReaders<'_> {
    type Reader = InfoReader;
    type CreateError = rustdds::dds::CreateError;
    type AttachError = std::io::Error;

    fn create(&mut self) -> Result<InfoReader, rustdds::dds::CreateError> {
        self.factory.subscriber.create_datareader_no_key(
            &self.factory.topic,
            Some(super::discovery_info::reader_qos()),
        )
    }

    fn attach(&mut self, reader: &mut InfoReader) -> std::io::Result<()> {
        lock(self.status)
            .poll
            .registry()
            .register(reader, LATE_JOINER, mio::Interest::READABLE)
    }

    fn detach(&mut self, reader: &mut InfoReader) {
        let _ = lock(self.status).poll.registry().deregister(reader);
    }

    fn take(reader: &mut InfoReader) -> Taken {
        match reader.take_next_sample() {
            Ok(Some(sample)) => Taken::Sample(sample.into_value()),
            Ok(None) => Taken::End,
            // Malformed CDR from the wire: that sample is dropped, the feed goes on.
            Err(e) => {
                tracing::warn!("dropped a malformed ros_discovery_info sample: {e}");
                Taken::Skipped
            }
        }
    }
}

/// The rustdds side of a discovery feed.
pub(crate) struct DdsDiscoveryFeed {
    /// The participant's, kept between feeds (only the open feed locks it).
    status: Arc<Mutex<StatusPoll>>,
    waker: Arc<MioWake>,
    reader: InfoReader,
    factory: InfoReaderFactory,
    /// The extra reader announced after a peer's `ros_discovery_info` writer was discovered
    /// (see [`crate::dds::late_joiner`]).
    late_joiner: LateJoiner<InfoReader>,
    local: LocalEvents,
    own_gid: Gid,
    pending: VecDeque<DiscoveryEvent>,
    /// What the last poll reported (only whether anything did matters: all is drained).
    events: mio::Events,
}

impl DdsDiscoveryFeed {
    /// A feed over the participant's status events and the `ros_discovery_info` reader,
    /// starting with `initial` (what was discovered before).
    pub(crate) fn new(
        status: Arc<Mutex<StatusPoll>>,
        mut reader: InfoReader,
        factory: InfoReaderFactory,
        own_gid: Gid,
        initial: Vec<DiscoveryEvent>,
        local: LocalEvents,
    ) -> std::io::Result<Self> {
        let waker = {
            let status = lock(&status);
            status
                .poll
                .registry()
                .register(&mut reader, INFO, mio::Interest::READABLE)?;
            Arc::clone(&status.waker)
        };
        let mut late_joiner = LateJoiner::new(own_gid);
        for event in &initial {
            late_joiner.observe(event);
        }
        Ok(Self {
            status,
            waker,
            reader,
            factory,
            late_joiner,
            local,
            own_gid,
            pending: initial.into(),
            events: mio::Events::with_capacity(8),
        })
    }

    /// Moves everything waiting into `pending` (wake-ups are edge-triggered: all is drained).
    fn drain(&mut self) {
        // Our own changes first: they were made before anything discovery reports about them.
        while let Some(event) = self.local.try_next() {
            self.pending.push_back(event);
        }
        while let Some(status) = lock(&self.status).try_recv() {
            if let Some(event) = self.convert(status) {
                self.late_joiner.observe(&event);
                self.pending.push_back(event);
            }
        }
        self.late_joiner
            .take_all::<LateReaders>(&mut self.reader, &mut self.pending);
        let mut source = LateReaders {
            factory: &self.factory,
            status: &self.status,
        };
        self.late_joiner
            .update(&mut source, &mut self.pending, Instant::now());
    }

    fn convert(&self, status: DomainParticipantStatusEvent) -> Option<DiscoveryEvent> {
        let event = match status {
            DomainParticipantStatusEvent::ParticipantDiscovered { dpd } => Some(
                DiscoveryEvent::ParticipantDiscovered(DiscoveredParticipant {
                    gid: gid_from_guid(dpd.guid),
                    vendor_id: VendorId(dpd.vendor_id.vendor_id),
                    // rustdds 0.15 does not expose participant USER_DATA.
                    enclave: None,
                }),
            ),
            DomainParticipantStatusEvent::ParticipantLost { id, .. } => {
                Some(DiscoveryEvent::ParticipantLost {
                    gid: participant_gid(id.as_ref()),
                })
            }
            DomainParticipantStatusEvent::ReaderDetected { reader } => Some(
                DiscoveryEvent::EndpointDiscovered(endpoint(reader, EndpointKind::Reader)),
            ),
            DomainParticipantStatusEvent::WriterDetected { writer } => Some(
                DiscoveryEvent::EndpointDiscovered(endpoint(writer, EndpointKind::Writer)),
            ),
            DomainParticipantStatusEvent::ReaderLost { guid, .. } => {
                Some(DiscoveryEvent::EndpointLost {
                    gid: gid_from_guid(guid),
                    kind: EndpointKind::Reader,
                })
            }
            DomainParticipantStatusEvent::WriterLost { guid, .. } => {
                Some(DiscoveryEvent::EndpointLost {
                    gid: gid_from_guid(guid),
                    kind: EndpointKind::Writer,
                })
            }
            DomainParticipantStatusEvent::RemoteReaderMatched {
                local_writer,
                remote_reader,
            } => {
                return Some(DiscoveryEvent::Matched {
                    local: gid_from_guid(local_writer),
                    remote: gid_from_guid(remote_reader),
                });
            }
            DomainParticipantStatusEvent::RemoteWriterMatched {
                local_reader,
                remote_writer,
            } => {
                return Some(DiscoveryEvent::Matched {
                    local: gid_from_guid(local_reader),
                    remote: gid_from_guid(remote_writer),
                });
            }
            _ => None,
        }?;
        // Our own participant and endpoints are reported by the context itself.
        let gid = match &event {
            DiscoveryEvent::ParticipantDiscovered(p) => p.gid,
            DiscoveryEvent::ParticipantLost { gid } | DiscoveryEvent::EndpointLost { gid, .. } => {
                *gid
            }
            DiscoveryEvent::EndpointDiscovered(e) => e.gid,
            DiscoveryEvent::ParticipantEntities(_) | DiscoveryEvent::Matched { .. } => {
                return Some(event)
            }
        };
        (gid.prefix() != self.own_gid.prefix()).then_some(event)
    }
}

impl Drop for DdsDiscoveryFeed {
    /// Leaves the participant's status poll to the next feed, without this feed's readers.
    fn drop(&mut self) {
        let status = lock(&self.status);
        // Deregistering fails only for what was never registered; nothing to undo then.
        let _ = status.poll.registry().deregister(&mut self.reader);
        if let Some(late) = self.late_joiner.reader_mut() {
            let _ = status.poll.registry().deregister(late);
        }
    }
}

impl FeedBackend for DdsDiscoveryFeed {
    fn try_next(&mut self) -> Option<DiscoveryEvent> {
        if self.pending.is_empty() {
            self.drain();
        }
        self.pending.pop_front()
    }

    fn wait(&mut self, limit: Option<Duration>) -> std::io::Result<bool> {
        // The late-joiner reader's retry is due at most then (see `crate::dds::late_joiner`).
        let limit = self.late_joiner.wait_limit(limit, Instant::now());
        self.events.clear();
        lock(&self.status).poll.poll(&mut self.events, limit)?;
        Ok(!self.events.is_empty())
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::clone(&self.waker) as Arc<dyn Wake>
    }
}

/// The participant GID for a GUID prefix: the prefix + `ENTITYID_PARTICIPANT` (`00 00 01 c1`).
fn participant_gid(prefix: &[u8]) -> Gid {
    let mut bytes = [0u8; 16];
    for (b, p) in bytes[..12].iter_mut().zip(prefix) {
        *b = *p;
    }
    bytes[12..].copy_from_slice(&[0x00, 0x00, 0x01, 0xc1]);
    Gid::from_bytes(bytes)
}

/// The octets of a USER_DATA policy as rustdds 0.15 reports it for remote endpoints.
///
/// rustdds hands over the raw PID_USER_DATA parameter value: the CDR `sequence<octet>` length
/// (4 bytes, little-endian in every RTPS stack seen here) followed by the octets and up to 3 bytes
/// of padding. When the bytes have that shape, the octets are returned; anything else is taken as
/// already bare octets.
pub fn user_data_octets(raw: &[u8]) -> &[u8] {
    if let Some((len, rest)) = raw.split_first_chunk::<4>() {
        let n = u32::from_le_bytes(*len) as usize;
        if n <= rest.len() && rest.len() - n < 4 {
            return &rest[..n];
        }
    }
    raw
}

fn endpoint(d: EndpointDescription, kind: EndpointKind) -> DiscoveredEndpoint {
    endpoint_from_parts(
        d.guid,
        d.topic_name,
        d.type_name,
        &d.qos,
        &d.user_data,
        kind,
    )
}

fn endpoint_from_parts(
    guid: rustdds::GUID,
    topic_name: String,
    type_name: String,
    qos: &rustdds::QosPolicies,
    raw_user_data: &[u8],
    kind: EndpointKind,
) -> DiscoveredEndpoint {
    let user_data = user_data_octets(raw_user_data).to_vec();
    let type_hash = parse_type_hash_from_user_data(&user_data).unwrap_or_else(|e| {
        tracing::debug!(topic = %topic_name, "unusable type hash in USER_DATA: {e}");
        TypeHash::ZERO
    });
    DiscoveredEndpoint {
        gid: gid_from_guid(guid),
        participant_gid: participant_gid(guid.prefix.as_ref()),
        kind,
        dds_topic_name: topic_name,
        dds_type_name: type_name,
        qos: Qos::from_dds(&super::qos::from_rustdds(qos, kind)),
        type_hash,
        user_data,
    }
}

/// Every remote reader and writer the participant knows now, as discovery events: a feed opened
/// late starts from these (rustdds keeps no list of participants, only of endpoints).
pub(crate) fn endpoint_snapshot(
    participant: &rustdds::DomainParticipant,
    own_gid: Gid,
) -> Vec<DiscoveryEvent> {
    let readers = participant.discovered_readers().into_iter().map(|r| {
        let t = &r.subscription_topic_data;
        endpoint_from_parts(
            r.reader_proxy.remote_reader_guid,
            t.topic_name().clone(),
            t.type_name().clone(),
            &t.qos(),
            &r.user_data,
            EndpointKind::Reader,
        )
    });
    let writers = participant.discovered_writers().into_iter().map(|w| {
        let t = &w.publication_topic_data;
        endpoint_from_parts(
            w.writer_proxy.remote_writer_guid,
            t.topic_name().clone(),
            t.type_name.clone(),
            &t.qos(),
            &w.user_data,
            EndpointKind::Writer,
        )
    });
    readers
        .chain(writers)
        .filter(|e| e.gid.prefix() != own_gid.prefix())
        .map(DiscoveryEvent::EndpointDiscovered)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::user_data_octets;

    #[test]
    fn user_data_length_prefix_and_padding_are_removed() {
        let mut raw = vec![5, 0, 0, 0];
        raw.extend_from_slice(b"abcde\0\0\0");
        assert_eq!(user_data_octets(&raw), b"abcde");
        assert_eq!(user_data_octets(&[0, 0, 0, 0]), b"");
        assert_eq!(
            user_data_octets(b"typehash=x;"),
            b"typehash=x;",
            "bare octets stay as they are"
        );
        assert_eq!(user_data_octets(&[]), b"");
        assert_eq!(
            user_data_octets(&[200, 0, 0, 0, 1]),
            &[200, 0, 0, 0, 1],
            "length past the end"
        );
    }
}
