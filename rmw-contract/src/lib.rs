//! The backend contract: what a backend implements for a `Context` to run on
//! it. rmw draws the same line (`rmw_create_node`, `rmw_create_publisher`, `rmw_take`,
//! `rmw_wait`, `rmw_get_graph_guard_condition`); everything above it — nodes and their names,
//! `ros_discovery_info` bookkeeping, typed publishers and subscriptions, services, the graph
//! cache — is written once, against these traits, and never asks which backend it runs on
//! except through [`Capabilities`].
//!
//! | rmw | here |
//! |---|---|
//! | the implementation library (`RMW_IMPLEMENTATION`) | [`Implementation`] |
//! | `rmw_context_t` (one participant per context) | [`ParticipantBackend`] |
//! | `rmw_publisher_t`, a client's request / a server's reply writer | [`WriterBackend`] |
//! | `rmw_subscription_t`, a server's request / a client's reply reader | [`ReaderBackend`] |
//! | `rmw_service_t` / `rmw_client_t` | a request/reply [`ReaderBackend`] + [`WriterBackend`] pair sharing a [`ServiceEndpointId`] (one entity of the backend where [`Capabilities::service_queries`]) |
//! | `rmw_wait_set_t` | [`WaitSetBackend`] |
//! | `rmw_guard_condition_t` (a wake-up from another thread) | [`Wake`] |
//! | the graph guard condition and `rmw_dds_common::GraphCache`'s inputs | [`FeedBackend`] |
//!
//! The built-in backends (`Backend`) are DDS implementations: RustDDS and
//! Cyclone DDS. What they share — `ros_discovery_info` (endpoints listed under
//! nodes), topic mangling, the request/reply conventions and late joiners — lives in the layers
//! above and in the crate's shared DDS modules, so each of them is only the DDS calls. A test
//! (or a new backend) plugs in with
//! `ContextBuilder::implementation`.
//!
//! Endpoints are described by their DDS names ([`RawEndpointSpec`]): a backend that is not DDS
//! maps them to its own keys, as rmw_zenoh maps ROS names to key expressions; one whose services
//! are its own request/reply (Zenoh's queryables) makes a service's two endpoints one entity
//! ([`Capabilities::service_queries`]), the identities the services layer correlates by
//! travelling in its own form (rmw_zenoh's attachment).

use std::any::Any;
use std::sync::Arc;
use std::time::Duration;

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;

pub mod dds_error;
pub mod discovery;
mod endpoint;
pub mod env;
mod errors;
pub mod feed_wait;
pub mod gid;
pub mod loan;
pub mod local_sink;
pub mod names;
pub mod push;
pub mod qos;

pub use endpoint::{
    unix_time_ns, RawEndpointSpec, RawSample, SampleId, ServiceEndpointId, ServiceEndpointRole,
    MIN_SERVICE_HISTORY_DEPTH, MIN_SERVICE_READER_HISTORY_DEPTH,
};
pub use errors::{DiscoveryFeedError, WaitSetError};

pub use dds_error::{BackendCause, DdsError};
pub use discovery::{DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId};
pub use env::{DiscoveryOptions, DiscoveryRange, DomainId};
pub use gid::Gid;
pub use loan::{LentBody, LoanedBuffer, LoanedSample, WriteLoan};
use qos::DdsQos;

/// Marks a request as coming from a horus-ros client, in the otherwise unused sequence number of
/// its `related_sample_identity` (rmw_fastrtps sends SEQUENCENUMBER_UNKNOWN there and ignores it
/// on receipt). A horus-ros server answers such a client's failed handler with an error reply.
pub const HORUS_CLIENT_MARKER: i64 = 0x484f_5255_0000_0001;

/// What a backend can do, where backends differ; the layers above ask this rather than which
/// backend they run on.
///
/// Backends outside this crate build theirs from [`Capabilities::NONE`] with the `with_*`
/// methods, so a capability added later is off for them until they say otherwise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct Capabilities {
    /// Samples carry `related_sample_identity` both ways, and a writer can address one matched
    /// reader (needed to call or serve peers of the rmw_fastrtps service convention).
    pub carries_sample_identity: bool,
    /// Participants and endpoints announce USER_DATA (`enclave=`, `typehash=`,
    /// `clientid=`/`serviceid=`), as rmw_cyclonedds does.
    pub announces_user_data: bool,
    /// The discovery feed reads other participants' USER_DATA (so a participant reported
    /// without an enclave announced none).
    pub reads_participant_user_data: bool,
    /// Endpoints announce their type's hash to peers (in USER_DATA on DDS, as rmw_cyclonedds
    /// and rmw_fastrtps do; in the liveliness tokens on Zenoh); where not, peers list them with
    /// an unknown (zero) hash.
    pub announces_type_hashes: bool,
    /// A service's request writer and reply reader (client), or request reader and reply writer
    /// (server), are one entity of the backend's own request/reply (rmw_zenoh's queryable and
    /// `get`), paired by their [`ServiceEndpointId`]: a request carries its client's identity
    /// (the client's GID and its own sequence number from 1) as its [`RawSample::id`] and as its
    /// `related` identity (with [`HORUS_CLIENT_MARKER`]); a
    /// reply is written with `related` = that identity (a negated sequence number: an error
    /// reply) and goes back through the request it answers, so it needs no matched reader; a
    /// reply taken carries the request's identity as `related`.
    pub service_queries: bool,
}

impl Capabilities {
    /// No capability: a backend of plain topics that announces and reads no USER_DATA.
    pub const NONE: Self = Self {
        carries_sample_identity: false,
        announces_user_data: false,
        reads_participant_user_data: false,
        announces_type_hashes: false,
        service_queries: false,
    };

    /// With [`carries_sample_identity`](Self::carries_sample_identity).
    pub const fn with_sample_identity(mut self) -> Self {
        self.carries_sample_identity = true;
        self
    }

    /// With [`announces_user_data`](Self::announces_user_data).
    pub const fn with_user_data_announced(mut self) -> Self {
        self.announces_user_data = true;
        self
    }

    /// With [`reads_participant_user_data`](Self::reads_participant_user_data).
    pub const fn with_participant_user_data_read(mut self) -> Self {
        self.reads_participant_user_data = true;
        self
    }

    /// With [`announces_type_hashes`](Self::announces_type_hashes).
    pub const fn with_type_hashes_announced(mut self) -> Self {
        self.announces_type_hashes = true;
        self
    }

    /// With [`service_queries`](Self::service_queries).
    pub const fn with_service_queries(mut self) -> Self {
        self.service_queries = true;
        self
    }
}

/// What a participant is created with.
#[derive(Clone, Copy, Debug)]
pub struct ParticipantConfig<'a> {
    /// The domain.
    pub domain: DomainId,
    /// How far discovery reaches, and the static peers.
    pub discovery: &'a DiscoveryOptions,
    /// The security enclave to announce (`/` by default).
    pub enclave: &'a str,
}

/// A backend: its name, what it can do, and how it makes a context's participant.
pub trait Implementation: Send + Sync + std::fmt::Debug + 'static {
    /// Its name (e.g. `rustdds`), as logs and `Debug` show it.
    fn name(&self) -> &'static str;
    /// The rmw implementation it stands in for, as `RMW_IMPLEMENTATION` names it.
    fn rmw_implementation(&self) -> &'static str;
    /// The RTPS vendor id its participants announce.
    fn vendor_id(&self) -> VendorId;
    /// What it can do.
    fn capabilities(&self) -> Capabilities;
    /// Creates one context's participant.
    fn create_participant(
        &self,
        config: &ParticipantConfig<'_>,
    ) -> Result<Box<dyn ParticipantBackend>, DdsError>;
}

/// One context's participant (rmw's `rmw_context_t`): its endpoints, its `ros_discovery_info`
/// writer and the discovery of everybody else.
pub trait ParticipantBackend: Send + Sync {
    /// Its GID (`ros_discovery_info`'s `gid`).
    fn gid(&self) -> Gid;

    /// Creates a writer; returns it with its GID.
    fn create_writer(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError>;

    /// Creates a reader; returns it with its GID. With `responses_of`, it is the reply reader
    /// of a client of the rmw_cyclonedds convention with that id: it may drop other clients'
    /// responses before storing them (rmw_cyclonedds' `rmw_take_response` drops them anyway).
    fn create_reader(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
        responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError>;

    /// A node of this context was created, before any endpoint of it; `node.id` names it in
    /// [`create_node_writer`](Self::create_node_writer) and
    /// [`create_node_reader`](Self::create_node_reader) until
    /// [`node_removed`](Self::node_removed). DDS backends announce nodes only through
    /// `ros_discovery_info` and ignore it; Zenoh declares the node's liveliness token here.
    fn node_added(&self, _node: &NodeDescription<'_>) {}

    /// The node `id` went (after all its endpoints).
    fn node_removed(&self, _id: u64) {}

    /// Creates a writer of a node ([`create_writer`](Self::create_writer) unless the backend
    /// names endpoints by their node, as rmw_zenoh's liveliness tokens do).
    fn create_node_writer(
        &self,
        _owner: EndpointOwner,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        self.create_writer(spec, qos)
    }

    /// Creates a reader of a node ([`create_reader`](Self::create_reader) unless the backend
    /// names endpoints by their node).
    fn create_node_reader(
        &self,
        _owner: EndpointOwner,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
        responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        self.create_reader(spec, qos, responses_of)
    }

    /// Publishes the participant's whole `ros_discovery_info` message (called on every change,
    /// in order); a failure is logged, since the next change republishes everything.
    fn publish_discovery_info(&self, message: &ParticipantEntitiesInfo);

    /// Waits at most `limit` until every peer acknowledged the last `ros_discovery_info`
    /// message; whether they all did.
    fn wait_for_discovery_info_acks(&self, limit: Duration) -> bool;

    /// Deletes the participant now, taking it and its endpoints off every peer's graph; its
    /// endpoints fail from then on.
    fn delete(&self);

    /// Opens the discovery of other participants, which reports `local` first (see
    /// [`LocalEvents`]). One is open at a time; dropping it allows another, which reports
    /// again what was discovered before.
    fn open_feed(&self, local: LocalEvents) -> Result<Box<dyn FeedBackend>, DiscoveryFeedError>;

    /// Creates an empty wait set for this backend's readers.
    fn create_wait_set(&self) -> Result<Box<dyn WaitSetBackend>, WaitSetError>;
}

/// A node as [`ParticipantBackend::node_added`] reports it.
#[derive(Clone, Copy, Debug)]
pub struct NodeDescription<'a> {
    /// The context's id of the node.
    pub id: u64,
    /// Its namespace (`/` or `/ns`).
    pub namespace: &'a str,
    /// Its name.
    pub name: &'a str,
}

/// Which node an endpoint is created for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EndpointOwner {
    /// The node's id (see [`NodeDescription::id`]).
    pub node: u64,
    /// Whether the node lists the endpoint (`false`: an observer no node shows, see
    /// `Node::create_raw_reader_unlisted`).
    pub listed: bool,
}

/// A writer of raw CDR bodies.
pub trait WriterBackend: Send + Sync {
    /// Writes a CDR_LE body; with `related`, the sample carries it as `related_sample_identity`
    /// (a backend without [`Capabilities::carries_sample_identity`] refuses it); with
    /// `only_to`, it may go to that one matched reader only. Returns the sample's identity.
    fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError>;

    /// Waits until every matched reliable reader acknowledged what was written, at most
    /// `timeout`; whether they all did (a backend that delivers what a deleted writer left
    /// unacknowledged by itself may answer `true` at once).
    fn wait_for_acknowledgments(&self, timeout: Duration) -> bool;

    /// Lends a buffer for a CDR_LE body of `len` bytes, to be filled in place and written with
    /// [`write_loan`](Self::write_loan) (rmw `rmw_borrow_loaned_message`). By default a heap
    /// buffer; a backend with memory of its own (Zenoh's shared memory) lends that.
    fn loan(&self, len: usize) -> WriteLoan {
        WriteLoan::heap(len)
    }

    /// Writes a body lent by [`loan`](Self::loan), as [`write`](Self::write) writes one (rmw
    /// `rmw_publish_loaned_message`). A buffer another backend lent is
    /// [`DdsError::ForeignLoan`].
    fn write_loan(
        &self,
        loan: WriteLoan,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        match loan.into_inner() {
            Ok(body) => self.write(body, related, only_to),
            Err(_) => Err(DdsError::ForeignLoan),
        }
    }
}

/// A reader of raw CDR bodies.
pub trait ReaderBackend: Send {
    /// Takes the next sample, if any (non-blocking). One that cannot be read is consumed and
    /// reported as an error.
    fn take(&mut self) -> Result<Option<RawSample>, DdsError>;

    /// Takes the next sample as [`take`](Self::take) does, its body lent by the backend where it
    /// has it in memory of its own (Zenoh's shared memory: read in place, no copy; rmw
    /// `rmw_take_loaned_message`). By default the body [`take`](Self::take) returned.
    fn take_loan(&mut self) -> Result<Option<LoanedSample>, DdsError> {
        Ok(self.take()?.map(LoanedSample::from))
    }

    /// Waits until data may be there or the reader's [`waker`](Self::waker) was woken, at most
    /// `timeout` (`None`: no limit); whether something was signalled. Edge-triggered.
    fn wait(&mut self, timeout: Option<Duration>) -> bool;

    /// What ends the current or next [`wait`](Self::wait) from any thread.
    fn waker(&self) -> Arc<dyn Wake>;

    /// How many of the samples taken so far came in a same-host shared-memory buffer (Zenoh's
    /// shared-memory transport); 0 where the backend has none.
    fn shared_memory_samples(&self) -> u64 {
        0
    }

    /// Reports this reader's data to `set` under `key` for the rest of the reader's life (its
    /// own [`wait`](Self::wait) then returns only when woken). A set of another backend is
    /// [`WaitSetError::OtherBackend`].
    fn attach_to(&mut self, set: &dyn WaitSetBackend, key: usize) -> Result<(), WaitSetError>;
}

/// A wait set (`rmw_wait`): one thread waiting on the data of many readers at once.
pub trait WaitSetBackend: Send + Sync {
    /// Waits until an attached reader may have data or the set's waker was woken, at most
    /// `timeout`; puts the keys of the readers that may have data in `ready` (which the caller
    /// cleared); whether anything was signalled.
    fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool;

    /// What ends the current or next [`wait`](Self::wait) from any thread.
    fn waker(&self) -> Arc<dyn Wake>;

    /// The set itself, for a reader of the same backend to find its own type in
    /// [`ReaderBackend::attach_to`].
    fn as_any(&self) -> &dyn Any;
}

/// A wake-up from another thread (rmw's guard condition).
pub trait Wake: Send + Sync {
    /// Wakes the waiter; a failure (logged) only delays it until its next wake-up.
    fn wake(&self);
}

/// The context's own participant, nodes and endpoints as it reports them to its open feed (DDS
/// discovery reports only remote entities). A feed reports them before anything it discovered
/// since its last [`FeedBackend::try_next`], since they happened first; it may also learn from
/// them (e.g. which of its own endpoints' matches to watch). Sending wakes the feed's
/// [`waker`](FeedBackend::waker).
#[derive(Debug)]
pub struct LocalEvents(pub std::sync::mpsc::Receiver<DiscoveryEvent>);

impl LocalEvents {
    /// The next of the context's own events, if one is waiting.
    pub fn try_next(&self) -> Option<DiscoveryEvent> {
        self.0.try_recv().ok()
    }
}

/// The discovery of other participants: the inputs of rmw_dds_common's graph cache.
///
/// Reports remote participants, their readers and writers ([`DiscoveryEvent::EndpointDiscovered`]
/// with each endpoint's `ros_discovery_info`-independent facts), their `ros_discovery_info`
/// messages, their loss, and which of this participant's own endpoints matched which remote
/// ones; and, first, the context's own [`LocalEvents`].
pub trait FeedBackend: Send {
    /// The next event, if one is there (non-blocking).
    fn try_next(&mut self) -> Option<DiscoveryEvent>;

    /// Blocks until something may be there or the feed's [`waker`](Self::waker) was woken
    /// (`Ok(true)`), or `limit` passed (`Ok(false)`; `None`: no limit). It may return
    /// `Ok(false)` earlier, when it has work of its own to do in [`try_next`](Self::try_next)
    /// (e.g. renewing a late-joiner reader).
    fn wait(&mut self, limit: Option<Duration>) -> std::io::Result<bool>;

    /// What ends the current or next [`wait`](Self::wait) from any thread.
    fn waker(&self) -> Arc<dyn Wake>;
}
