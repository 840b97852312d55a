//! Raw endpoints: readers and writers of pre-serialized CDR bodies with sample identities, for the
//! services layer (request/reply correlation) and anything that encodes its own payloads.
//!
//! Each endpoint is listed under its node in `ros_discovery_info` like any other (a reader made
//! with [`Node::create_raw_reader_unlisted`] under none); a reader can be
//! waited on without polling. Which endpoints are matched is reported by the discovery feed
//! ([`DiscoveryEvent::Matched`](crate::DiscoveryEvent::Matched)): rustdds' per-endpoint status
//! channels hold only 4 events and drop the rest.

use std::sync::Arc;
use std::time::Duration;

pub use crate::contract::{
    unix_time_ns, LoanedSample, RawEndpointSpec, RawSample, SampleId, ServiceEndpointId,
    ServiceEndpointRole, WriteLoan,
};
use crate::contract::{ReaderBackend, Wake, WriterBackend};
use crate::dds::entities::EndpointSide;
use crate::dds_error::DdsError;
use crate::discovery::DiscoveredEndpoint;
use crate::node::{Node, Registration};
use crate::pubsub::{EndpointError, PublishError, SampleError, TakeError};
use crate::qos::EndpointKind;
use crate::Gid;

fn describe(
    node: &Node,
    spec: &RawEndpointSpec,
    gid: Gid,
    kind: EndpointKind,
) -> DiscoveredEndpoint {
    let user_data = if node.context().capabilities().announces_user_data {
        spec.user_data().into_bytes()
    } else {
        Vec::new()
    };
    DiscoveredEndpoint {
        gid,
        participant_gid: node.context().gid(),
        kind,
        dds_topic_name: spec.dds_topic_name.clone(),
        dds_type_name: spec.dds_type_name.clone(),
        qos: spec.qos.effective(kind),
        type_hash: spec.type_hash,
        user_data,
    }
}

/// Writes raw CDR bodies, optionally with a `related_sample_identity`.
pub struct RawWriter {
    // Dropped first: withdrawn from ros_discovery_info before the writer is deleted.
    registration: Registration,
    topic: String,
    writer: Box<dyn WriterBackend>,
}

impl std::fmt::Debug for RawWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RawWriter")
            .field("gid", &self.gid())
            .finish()
    }
}

/// Reads raw CDR bodies with their sample identities.
pub struct RawReader {
    registration: Registration,
    topic: String,
    pub(crate) reader: Box<dyn ReaderBackend>,
    waker: RawReaderWaker,
}

/// Makes a [`RawReader`]'s current or next [`wait`](RawReader::wait) return, from any thread
/// (e.g. to stop the thread waiting on it, or to tell it of something other than data). Cheap
/// to clone; all clones wake the same reader.
#[derive(Clone)]
pub struct RawReaderWaker(pub(crate) Arc<dyn Wake>);

impl std::fmt::Debug for RawReaderWaker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("RawReaderWaker")
    }
}

impl RawReaderWaker {
    /// Wakes the reader's waiting thread (or makes its next wait return at once).
    pub fn wake(&self) {
        self.0.wake();
    }
}

impl std::fmt::Debug for RawReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RawReader")
            .field("gid", &self.gid())
            .finish()
    }
}

fn dds_error<'a>(
    kind: &'static str,
    spec: &'a RawEndpointSpec,
) -> impl Fn(DdsError) -> EndpointError + 'a {
    move |source| EndpointError::Dds {
        kind,
        topic: spec.dds_topic_name.clone(),
        cause: source,
    }
}

impl Node {
    /// Creates a raw writer on an already-mangled DDS topic.
    pub fn create_raw_writer(&self, spec: &RawEndpointSpec) -> Result<RawWriter, EndpointError> {
        self.raw_writer(spec, true)
    }

    /// Creates a raw writer that no node lists in `ros_discovery_info`, as
    /// [`create_raw_reader_unlisted`](Self::create_raw_reader_unlisted) does a reader: e.g. the
    /// reply writer, never written, that balances a passive echo's request reader (rmw_fastrtps
    /// clients take a service for available only while they see as many request readers as
    /// reply writers). DDS discovery still announces it.
    pub fn create_raw_writer_unlisted(
        &self,
        spec: &RawEndpointSpec,
    ) -> Result<RawWriter, EndpointError> {
        self.raw_writer(spec, false)
    }

    /// This node as the owner of an endpoint (listed under it or not).
    fn owner(&self, listed: bool) -> crate::contract::EndpointOwner {
        crate::contract::EndpointOwner {
            node: self.inner().key.id(),
            listed,
        }
    }

    fn raw_writer(&self, spec: &RawEndpointSpec, listed: bool) -> Result<RawWriter, EndpointError> {
        let dds_qos = spec
            .local_qos(EndpointKind::Writer)
            .to_dds(EndpointKind::Writer)
            .map_err(|source| EndpointError::InvalidQos {
                name: spec.dds_topic_name.clone(),
                cause: source,
            })?;
        let (writer, gid) = self
            .context()
            .inner()
            .participant
            .create_node_writer(self.owner(listed), spec, &dds_qos)
            .map_err(dds_error("writer", spec))?;
        let endpoint = describe(self, spec, gid, EndpointKind::Writer);
        let registration = if listed {
            Registration::new(self, EndpointSide::Writer, endpoint)
        } else {
            Registration::unlisted(self, EndpointSide::Writer, endpoint)
        };
        Ok(RawWriter {
            registration,
            topic: spec.dds_topic_name.clone(),
            writer,
        })
    }

    /// Creates a raw reader on an already-mangled DDS topic.
    pub fn create_raw_reader(&self, spec: &RawEndpointSpec) -> Result<RawReader, EndpointError> {
        self.raw_reader(spec, None)
    }

    /// Creates a raw reader that no node lists in `ros_discovery_info`: an observer, such as
    /// a passive service echo's readers on a service's `rq/…Request` and `rr/…Reply` topics,
    /// that node-based views (`ros2 node info`, a node's clients and servers, the pairing of a
    /// node's request and reply endpoints into servers and clients) must not show as the
    /// node's.
    ///
    /// DDS discovery (SEDP) still announces the reader — no DDS reader is matched otherwise —
    /// so graphs still see it as a reader of no node (rmw_dds_common names its node
    /// `_NODE_NAME_UNKNOWN_`), and counts by topic alone include it: rmw_fastrtps and
    /// rmw_cyclonedds `rmw_count_clients` count every reader on `rr/<service>Reply`.
    /// This context's own discovery feed reports it as well, with no node.
    pub fn create_raw_reader_unlisted(
        &self,
        spec: &RawEndpointSpec,
    ) -> Result<RawReader, EndpointError> {
        self.raw_reader_listed(spec, None, false)
    }

    /// Creates the reply reader of a service client that writes rmw_cyclonedds' request
    /// header with `client` as its id: it stores only the responses to that client. A server of
    /// that convention cannot address one reader, so every client's reader receives every
    /// response (rmw_cyclonedds' `rmw_take_response` drops the others'); on the Cyclone backend
    /// a content filter drops them inside Cyclone, before they are stored, taken or wake
    /// anyone. On rustdds this is [`create_raw_reader`](Self::create_raw_reader): its servers
    /// address the reader a request names.
    pub fn create_response_reader(
        &self,
        spec: &RawEndpointSpec,
        client: u64,
    ) -> Result<RawReader, EndpointError> {
        self.raw_reader(spec, Some(client))
    }

    fn raw_reader(
        &self,
        spec: &RawEndpointSpec,
        responses_of: Option<u64>,
    ) -> Result<RawReader, EndpointError> {
        self.raw_reader_listed(spec, responses_of, true)
    }

    fn raw_reader_listed(
        &self,
        spec: &RawEndpointSpec,
        responses_of: Option<u64>,
        listed: bool,
    ) -> Result<RawReader, EndpointError> {
        let dds_qos = spec
            .local_qos(EndpointKind::Reader)
            .to_dds(EndpointKind::Reader)
            .map_err(|source| EndpointError::InvalidQos {
                name: spec.dds_topic_name.clone(),
                cause: source,
            })?;
        let (reader, gid) = self
            .context()
            .inner()
            .participant
            .create_node_reader(self.owner(listed), spec, &dds_qos, responses_of)
            .map_err(dds_error("reader", spec))?;
        let waker = RawReaderWaker(reader.waker());
        let endpoint = describe(self, spec, gid, EndpointKind::Reader);
        let registration = if listed {
            Registration::new(self, EndpointSide::Reader, endpoint)
        } else {
            Registration::unlisted(self, EndpointSide::Reader, endpoint)
        };
        Ok(RawReader {
            registration,
            topic: spec.dds_topic_name.clone(),
            reader,
            waker,
        })
    }
}

impl RawWriter {
    /// The writer's GID.
    pub fn gid(&self) -> Gid {
        self.registration.gid()
    }

    /// Waits until every matched reliable reader acknowledged what was written, at most
    /// `timeout`; returns whether they all did. On the Cyclone backend it returns at once:
    /// Cyclone DDS delivers unacknowledged samples of a deleted writer itself (its writer
    /// linger duration).
    pub fn wait_for_acknowledgments(&self, timeout: Duration) -> bool {
        self.writer.wait_for_acknowledgments(timeout)
    }

    /// Writes `body` (a CDR_LE body) and returns the sample's identity. With `related`, the sample
    /// carries it as `related_sample_identity` (under both PIDs 0x0083 and 0x800f); with `only_to`,
    /// it is sent to that one matched reader only.
    ///
    /// On the Cyclone backend, `related` is refused (Cyclone DDS cannot send it), `only_to` is
    /// ignored (the sample goes to every matched reader) and the sequence number is counted by
    /// the writer itself (one per write, from 1, as RTPS numbers them).
    pub fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, PublishError> {
        self.writer
            .write(body, related, only_to)
            .map_err(|e| PublishError {
                topic: self.topic.clone(),
                cause: SampleError::Dds(e),
            })
    }

    /// Lends a buffer for a CDR body of `len` bytes (rmw `rmw_borrow_loaned_message`), to be
    /// filled in place and written with [`write_loan`](Self::write_loan): on the Zenoh backend
    /// with shared memory on, a buffer of the context's pool (for a message at or above its
    /// threshold), so that the message crosses to the subscriptions of this host with no copy;
    /// elsewhere a heap buffer.
    pub fn loan(&self, len: usize) -> WriteLoan {
        self.writer.loan(len)
    }

    /// Writes a body lent by this writer's [`loan`](Self::loan), as [`write`](Self::write) does
    /// (rmw `rmw_publish_loaned_message`).
    pub fn write_loan(
        &self,
        loan: WriteLoan,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, PublishError> {
        self.writer
            .write_loan(loan, related, only_to)
            .map_err(|e| PublishError {
                topic: self.topic.clone(),
                cause: SampleError::Dds(e),
            })
    }
}

impl RawReader {
    /// The reader's GID.
    pub fn gid(&self) -> Gid {
        self.registration.gid()
    }

    /// Takes the next sample, if any (non-blocking). A sample the DDS layer could not decode is
    /// reported as an error and dropped; the next call goes on with the following one.
    ///
    /// On the Cyclone backend, samples carry no `related_sample_identity` and their sequence
    /// number is [`SampleId::UNKNOWN_SEQUENCE_NUMBER`] (Cyclone DDS reports neither).
    pub fn take(&mut self) -> Result<Option<RawSample>, TakeError> {
        self.reader.take().map_err(|e| TakeError {
            topic: self.topic.clone(),
            cause: SampleError::Dds(e),
        })
    }

    /// Takes the next sample as [`take`](Self::take) does, its body lent in place where the
    /// backend holds it in memory of its own (rmw `rmw_take_loaned_message`): on the Zenoh
    /// backend, a received buffer of one piece (a shared-memory buffer always is) is read where
    /// it lies and given back when the sample is dropped. Elsewhere the body is owned.
    pub fn take_loan(&mut self) -> Result<Option<LoanedSample>, TakeError> {
        self.reader.take_loan().map_err(|e| TakeError {
            topic: self.topic.clone(),
            cause: SampleError::Dds(e),
        })
    }

    /// How many of the samples taken so far came in a same-host shared-memory buffer: on the
    /// Zenoh backend with shared memory on (`transport/shared_memory/enabled=true`), a message
    /// put in shared memory on this host (by its publisher's pool, or by zenoh's own transport
    /// optimization) that crossed only links where shared memory is on. Always 0 on the DDS
    /// backends. For checking that large messages cross without copies.
    pub fn shared_memory_samples(&self) -> u64 {
        self.reader.shared_memory_samples()
    }

    /// A handle that wakes this reader's [`wait`](Self::wait) from any thread.
    pub fn waker(&self) -> RawReaderWaker {
        self.waker.clone()
    }

    /// Waits until data may be there or the reader's [`waker`](Self::waker) was woken, at most
    /// `timeout` (a `Duration`, or `None` for no limit); returns whether something was
    /// signalled. Take until `None` after it: wake-ups are edge-triggered.
    pub fn wait(&mut self, timeout: impl Into<Option<Duration>>) -> bool {
        self.reader.wait(timeout.into())
    }
}
