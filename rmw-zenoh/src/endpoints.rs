//! Publishers and subscriptions on Zenoh, as rmw_zenoh_cpp 0.2.10 makes them
//! (`src/detail/rmw_publisher_data.cpp`, `src/detail/rmw_subscription_data.cpp`; wire facts
//! §3–4): a Zenoh publisher on the data key, every sample the CDR payload (4-byte encapsulation
//! header included) with the 33-byte attachment (sequence number from 1, source timestamp,
//! GID); a Zenoh subscriber whose samples go to a bounded queue that wakes the reader (or its
//! wait set). Each entity holds its liveliness token for its whole life.
//!
//! A VOLATILE publisher holds its samples while the graph knows a subscription of its topic
//! that this session has no route to yet ([`route`](super::route)), at most its depth of them;
//! TRANSIENT_LOCAL publishers need none of this: their late joiners query the cache.
//!
//! With shared memory on ([`shm`](super::shm)), a message at or above the threshold is copied
//! once, encapsulation header and body, into a buffer of the context's shared-memory pool and
//! put from there; a subscriber on the same host then maps that buffer instead of receiving
//! its bytes (zenoh passes a reference on the link). What is zero-copy is the crossing: the
//! payload is neither copied into a heap buffer, nor onto the socket, nor out of it. The
//! subscription keeps the received payload (a `ZBytes` over the mapped buffer, as rmw_zenoh's
//! `SubscriptionData` keeps its `zenoh::Bytes`) until it is taken; a take copies the body out
//! once into the [`RawSample`], as rmw_zenoh's `rmw_take` deserializes out of the payload.

use std::any::Any;

use std::sync::atomic::{AtomicBool, AtomicI64, AtomicU64, Ordering};
use std::sync::{Arc, Weak};
use std::time::Duration;

use zenoh::bytes::ZBytes;
use zenoh::liveliness::LivelinessToken;
use zenoh::matching::{MatchingListener, MatchingStatus};
use zenoh::pubsub::{Publisher, Subscriber};
use zenoh::shm::ZShmMut;
use zenoh::Wait;

use super::attachment::{now_ns, Attachment};
use super::feed::Graph;
use super::route::RouteWait;
use super::shm::ShmContext;
use horus_ros_rmw_contract::dds_error::{boxed, DdsError};
use horus_ros_rmw_contract::push::SampleQueue;
use horus_ros_rmw_contract::Gid;
use horus_ros_rmw_contract::RawSample;
use horus_ros_rmw_contract::{
    LentBody, LoanedBuffer, LoanedSample, ReaderBackend, SampleId, WaitSetBackend, WaitSetError,
    Wake, WriteLoan, WriterBackend,
};

/// CDR little-endian encapsulation (`00 01 00 00`), what rmw_zenoh writes.
pub(crate) const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Most samples a reader queues (KEEP_ALL, or a larger depth): the oldest go first.
pub(crate) const MAX_SAMPLES: usize = 10_000;

/// A message Zenoh gave as an error.
#[derive(Debug, thiserror::Error)]
#[error("zenoh: {0}")]
pub(crate) struct ZenohError(pub(crate) String);

/// A Zenoh error as the contract's error.
pub(crate) fn zenoh_error(
    make: fn(horus_ros_rmw_contract::BackendCause) -> DdsError,
    e: impl std::fmt::Display,
) -> DdsError {
    make(boxed(ZenohError(e.to_string())))
}

/// A Zenoh publisher: a plain one (VOLATILE) or zenoh-ext's advanced one (TRANSIENT_LOCAL,
/// with the cache late joiners query), as rmw_zenoh declares them (`rmw_publisher_data.cpp`).
pub(crate) enum Publication {
    /// A plain publisher.
    Plain(Publisher<'static>),
    /// An advanced publisher with a cache of the last `depth` samples.
    Advanced(zenoh_ext::AdvancedPublisher<'static>),
}

impl Publication {
    fn put(&self, payload: ZBytes, attachment: Vec<u8>) -> Result<(), DdsError> {
        match self {
            Publication::Plain(p) => p.put(payload).attachment(attachment).wait(),
            Publication::Advanced(p) => p.put(payload).attachment(attachment).wait(),
        }
        .map_err(|e| zenoh_error(DdsError::Write, e))
    }
}

/// A publisher and the samples (payload, attachment) it holds for a route.
pub(crate) struct Delivery {
    publisher: Publication,
    held: RouteWait<(ZBytes, Vec<u8>)>,
    topic: String,
    type_name: String,
}

impl Delivery {
    /// `publisher` of `topic`/`type_name`, holding at most `depth` samples; for a plain
    /// (VOLATILE) one, `probe` is a publisher of the same key restricted to remote subscribers,
    /// whose matching listener reports the routes what is held waits for: the publisher's own
    /// status counts a subscriber of this session as a match (zenoh `Session::matching_status`,
    /// `Locality::Any`), which would release samples held for a remote one.
    pub(crate) fn new(
        publisher: Publication,
        probe: Option<Publisher<'static>>,
        depth: usize,
        (topic, type_name): (&str, &str),
    ) -> Result<(Arc<Self>, Option<RouteListener>), DdsError> {
        let delivery = Arc::new(Self {
            publisher,
            held: RouteWait::new(depth, "sample"),
            topic: topic.to_owned(),
            type_name: type_name.to_owned(),
        });
        let Some(probe) = probe else {
            return Ok((delivery, None));
        };
        let weak: Weak<Delivery> = Arc::downgrade(&delivery);
        // Declared with a route already there, it reports it at once.
        let listener = probe
            .matching_listener()
            .callback(move |status: MatchingStatus| {
                if let Some(delivery) = weak.upgrade() {
                    delivery
                        .held
                        .on_matching(status.matching(), |(p, a)| delivery.publisher.put(p, a));
                }
            })
            .wait()
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        Ok((
            delivery,
            Some(RouteListener {
                _listener: listener,
                _probe: probe,
            }),
        ))
    }

    /// Puts the sample, or holds it while the graph knows a subscription with no route yet.
    fn put(&self, graph: &Graph, payload: ZBytes, attachment: Vec<u8>) -> Result<(), DdsError> {
        if matches!(self.publisher, Publication::Advanced(_)) {
            return self.publisher.put(payload, attachment);
        }
        self.held.send_or_hold(
            (payload, attachment),
            || graph.has_remote_reader(&self.topic, &self.type_name),
            |(p, a)| self.publisher.put(p, a),
        )
    }
}

/// What tells a plain publisher's [`Delivery`] of routes to remote subscribers: the remote-only
/// probe publisher and its matching listener.
pub(crate) struct RouteListener {
    /// Before `_probe`, so dropped first: a publisher undeclared first undeclares its matching
    /// listeners (zenoh 1.8 `Publisher::undeclare_impl`), and the listener's own undeclaration
    /// then logs an ERROR ("Unable to find MatchingListener").
    _listener: MatchingListener<()>,
    _probe: Publisher<'static>,
}

/// A publisher: the Zenoh publisher, its token and its sequence numbers.
pub(crate) struct ZenohWriter {
    pub(crate) delivery: Arc<Delivery>,
    pub(crate) _routes: Option<RouteListener>,
    pub(crate) token: Option<LivelinessToken>,
    pub(crate) gid: Gid,
    pub(crate) sequence_number: AtomicI64,
    pub(crate) graph: Arc<Graph>,
    pub(crate) deleted: Arc<AtomicBool>,
    /// The context's shared-memory pool, when shared memory is on.
    pub(crate) shm: Option<Arc<ShmContext>>,
}

impl ZenohWriter {
    /// The payload of a sample: the encapsulation header and `body`, in a shared-memory buffer
    /// when the context has a pool, the payload reaches its threshold and the pool has room
    /// (rmw_publisher_data.cpp), else on the heap.
    fn payload(&self, body: &[u8]) -> ZBytes {
        let len = CDR_LE_HEADER.len() + body.len();
        if let Some(mut buffer) = self.shm.as_deref().and_then(|shm| shm.buffer(len)) {
            let (header, rest) = buffer.split_at_mut(CDR_LE_HEADER.len());
            header.copy_from_slice(&CDR_LE_HEADER);
            rest.copy_from_slice(body);
            return buffer.into();
        }
        let mut payload = Vec::with_capacity(len);
        payload.extend_from_slice(&CDR_LE_HEADER);
        payload.extend_from_slice(body);
        payload.into()
    }
}

impl ZenohWriter {
    /// Puts `payload` (header included) with its attachment; the sample's identity.
    fn put(&self, payload: ZBytes, related: Option<SampleId>) -> Result<SampleId, DdsError> {
        if related.is_some() {
            return Err(DdsError::RelatedSampleIdentityUnsupported);
        }
        if self.deleted.load(Ordering::SeqCst) {
            return Err(DdsError::ParticipantDeleted);
        }
        let sequence_number = self.sequence_number.fetch_add(1, Ordering::Relaxed) + 1;
        let attachment = Attachment {
            sequence_number,
            source_timestamp: now_ns(),
            gid: self.gid,
        };
        let attachment = attachment.to_bytes().to_vec();
        self.delivery.put(&self.graph, payload, attachment)?;
        Ok(SampleId {
            writer: self.gid,
            sequence_number,
        })
    }
}

/// A shared-memory buffer lent for one sample: the encapsulation header, then the body.
struct ShmLoan(ZShmMut);

impl LoanedBuffer for ShmLoan {
    fn body(&self) -> &[u8] {
        &self.0[CDR_LE_HEADER.len()..]
    }

    fn body_mut(&mut self) -> &mut [u8] {
        &mut self.0[CDR_LE_HEADER.len()..]
    }

    fn into_any(self: Box<Self>) -> Box<dyn Any> {
        self
    }
}

impl WriterBackend for ZenohWriter {
    /// Puts the sample with its attachment. `related` is refused (a Zenoh topic has no
    /// related sample identity; service replies go through `services`' queries); `only_to` is
    /// ignored.
    fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        _only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        let payload = self.payload(&body);
        self.put(payload, related)
    }

    /// At once: Zenoh has no acknowledgments (its TCP links are reliable; a RELIABLE publisher
    /// on a full link drops or blocks by its congestion control).
    fn wait_for_acknowledgments(&self, _timeout: Duration) -> bool {
        true
    }

    /// A buffer of the context's shared-memory pool, its encapsulation header written, when
    /// shared memory is on, the payload reaches the threshold and the pool has room (as
    /// [`write`](Self::write) chooses); else a heap buffer.
    fn loan(&self, len: usize) -> WriteLoan {
        let payload = CDR_LE_HEADER.len() + len;
        match self.shm.as_deref().and_then(|shm| shm.buffer(payload)) {
            Some(mut buffer) => {
                buffer[..CDR_LE_HEADER.len()].copy_from_slice(&CDR_LE_HEADER);
                WriteLoan::backend(Box::new(ShmLoan(buffer)))
            }
            None => WriteLoan::heap(len),
        }
    }

    /// A shared-memory loan goes out as it is, not copied; a heap one as [`write`](Self::write).
    fn write_loan(
        &self,
        loan: WriteLoan,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        match loan.into_inner() {
            Ok(body) => self.write(body, related, only_to),
            Err(buffer) => match buffer.into_any().downcast::<ShmLoan>() {
                Ok(shm) => self.put(shm.0.into(), related),
                Err(_) => Err(DdsError::ForeignLoan),
            },
        }
    }
}

impl Drop for ZenohWriter {
    fn drop(&mut self) {
        // The token first (as rmw_destroy_publisher undeclares it before the publisher).
        drop(self.token.take());
        self.graph.remove_local(self.gid);
    }
}

/// A sample as received: the payload and what its attachment said.
pub(crate) struct Incoming {
    /// The payload (encapsulation header included), as zenoh gave it: over a mapped
    /// shared-memory buffer when it came through one.
    pub(crate) payload: ZBytes,
    /// Its attachment.
    pub(crate) attachment: Attachment,
    /// When it arrived, in ns since the UNIX epoch.
    pub(crate) received: i64,
    /// The identity it is related to (a service request's client, a reply's request).
    pub(crate) related: Option<SampleId>,
}

/// A reader's bounded queue and whom it wakes.
pub(crate) struct ReaderQueue {
    samples: SampleQueue<Incoming>,
    /// The topic, for the one log line about samples dropped.
    topic: String,
    warned: AtomicBool,
    /// How many samples taken had come in a shared-memory buffer.
    shared_memory_samples: AtomicU64,
}

impl ReaderQueue {
    /// A queue keeping at most `depth` samples.
    pub(crate) fn new(depth: usize, topic: &str) -> Arc<Self> {
        Arc::new(Self {
            samples: SampleQueue::new(depth.clamp(1, MAX_SAMPLES)),
            topic: topic.to_owned(),
            warned: AtomicBool::new(false),
            shared_memory_samples: AtomicU64::new(0),
        })
    }

    /// What the subscriber's callback does with a sample: one without a valid attachment is
    /// dropped, as rmw_zenoh drops it ("Unable to obtain attachment"), logged once per reader.
    pub(crate) fn receive(&self, sample: &zenoh::sample::Sample) {
        let Some(attachment) = self.attachment_of(sample.attachment(), sample.key_expr()) else {
            return;
        };
        self.deliver(Incoming {
            payload: sample.payload().clone(),
            attachment,
            received: horus_ros_rmw_contract::unix_time_ns(),
            related: None,
        });
    }

    /// The attachment `raw` of a sample, query or reply on `key`; `None` (logged once per
    /// reader) if it has none or a malformed one.
    pub(crate) fn attachment_of(
        &self,
        raw: Option<&zenoh::bytes::ZBytes>,
        key: &zenoh::key_expr::KeyExpr<'_>,
    ) -> Option<Attachment> {
        match raw.map(|a| Attachment::parse(&a.to_bytes())) {
            Some(Ok(a)) => Some(a),
            problem => {
                if !self.warned.swap(true, Ordering::Relaxed) {
                    let why = match problem {
                        Some(Err(e)) => e.to_string(),
                        _ => "no attachment".to_owned(),
                    };
                    tracing::warn!(topic = %self.topic, %key, "zenoh: dropped a message: {why} (further ones of this endpoint are dropped silently)");
                }
                None
            }
        }
    }

    /// Queues a sample (the oldest goes when full) and wakes the reader or its wait set.
    pub(crate) fn deliver(&self, sample: Incoming) {
        self.samples.deliver(sample);
    }
}

/// A Zenoh subscriber: a plain one (VOLATILE) or zenoh-ext's advanced one (TRANSIENT_LOCAL:
/// it queries the caches of the publishers it detects), as rmw_zenoh declares them
/// (`rmw_subscription_data.cpp`).
// Held only: dropping one undeclares it.
#[allow(dead_code)]
pub(crate) enum Subscription {
    /// A plain subscriber.
    Plain(Subscriber<()>),
    /// An advanced subscriber.
    Advanced(zenoh_ext::AdvancedSubscriber<()>),
}

/// A subscription: the Zenoh subscriber feeding the queue, and its token.
pub(crate) struct ZenohReader {
    pub(crate) token: Option<LivelinessToken>,
    pub(crate) subscriber: Option<Subscription>,
    /// The service server or client whose request or reply reader this is (its queue is fed
    /// by the queryable or the queries' replies).
    pub(crate) service: Option<Arc<dyn std::any::Any + Send + Sync>>,
    pub(crate) queue: Arc<ReaderQueue>,
    pub(crate) gid: Gid,
    pub(crate) graph: Arc<Graph>,
}

/// A received payload of one contiguous buffer, lent as a sample's body.
struct Lent(ZBytes);

impl LentBody for Lent {
    fn body(&self) -> &[u8] {
        self.0
            .slices()
            .next()
            .and_then(|payload| payload.get(CDR_LE_HEADER.len()..))
            .unwrap_or_default()
    }
}

impl ZenohReader {
    /// The next sample's payload (header included, checked) and what its attachment said (the
    /// body left empty); counts it if it came through shared memory.
    fn next(&mut self) -> Result<Option<(ZBytes, RawSample)>, DdsError> {
        let Some(sample) = self.queue.samples.pop() else {
            return Ok(None);
        };
        if sample.payload.as_shm().is_some() {
            self.queue
                .shared_memory_samples
                .fetch_add(1, Ordering::Relaxed);
        }
        let mut header = [0; CDR_LE_HEADER.len()];
        let mut reader = sample.payload.reader();
        let len = sample.payload.len();
        if std::io::Read::read_exact(&mut reader, &mut header).is_err() {
            return Err(DdsError::ShortSample { len });
        }
        let big_endian = match [header[0], header[1]] {
            [0x00, 0x01] => false,
            [0x00, 0x00] => true,
            id => return Err(DdsError::UnsupportedEncapsulation { id }),
        };
        let meta = RawSample {
            body: Vec::new(),
            big_endian,
            id: SampleId {
                writer: sample.attachment.gid,
                sequence_number: sample.attachment.sequence_number,
            },
            related: sample.related,
            publication_handle: None,
            // The attachment's timestamp (rmw_zenoh's `source_timestamp`).
            source_timestamp: Some(sample.attachment.source_timestamp),
            received_timestamp: sample.received,
        };
        Ok(Some((sample.payload, meta)))
    }
}

impl ReaderBackend for ZenohReader {
    /// Takes the next sample: its payload after the 4-byte encapsulation header (copied once
    /// out of the received buffer, shared memory or not; a payload zenoh received in fragments
    /// is joined first), its identity from the attachment (the publisher's GID and sequence
    /// number).
    fn take(&mut self) -> Result<Option<RawSample>, DdsError> {
        let Some((payload, mut meta)) = self.next()? else {
            return Ok(None);
        };
        // One contiguous slice (a shared-memory buffer always is) is borrowed, not copied.
        meta.body = payload.to_bytes()[CDR_LE_HEADER.len()..].to_vec();
        Ok(Some(meta))
    }

    /// Takes the next sample as [`take`](Self::take) does, its body read in place where the
    /// payload is one contiguous buffer (a shared-memory buffer always is: the subscription
    /// then keeps the publisher's buffer until the loan is dropped); a payload received in
    /// fragments is joined, as `take` joins it.
    fn take_loan(&mut self) -> Result<Option<LoanedSample>, DdsError> {
        let Some((payload, meta)) = self.next()? else {
            return Ok(None);
        };
        if payload.slices().count() == 1 {
            return Ok(Some(LoanedSample::lent(Box::new(Lent(payload)), meta)));
        }
        let body = payload.to_bytes()[CDR_LE_HEADER.len()..].to_vec();
        Ok(Some(LoanedSample::from(RawSample { body, ..meta })))
    }

    fn wait(&mut self, timeout: Option<Duration>) -> bool {
        self.queue.samples.wait(timeout)
    }

    fn waker(&self) -> Arc<dyn Wake> {
        self.queue.samples.waker()
    }

    /// Counted at [`take`](Self::take): samples whose payload zenoh handed over as a mapped
    /// shared-memory buffer (`ZBytes::as_shm`).
    fn shared_memory_samples(&self) -> u64 {
        self.queue.shared_memory_samples.load(Ordering::Relaxed)
    }

    fn attach_to(&mut self, set: &dyn WaitSetBackend, key: usize) -> Result<(), WaitSetError> {
        self.queue.samples.attach_to(set, key)
    }
}

impl Drop for ZenohReader {
    fn drop(&mut self) {
        drop(self.token.take());
        drop(self.subscriber.take());
        drop(self.service.take());
        self.graph.remove_local(self.gid);
    }
}
