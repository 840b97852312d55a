//! The [`Context`]: one DDS participant in one domain, shared by every node created from it
//! (rmw_cyclonedds and rmw_fastrtps both create one participant per context since Foxy).

pub use horus_ros_rmw_contract::env;
mod shutdown;

pub use shutdown::ShutdownFuture;

use std::any::{Any, TypeId};
use std::collections::{BTreeMap, HashMap};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, Weak};

use crate::backend::{Backend, BackendError};
pub use crate::contract::DiscoveryFeedError;
use crate::contract::{
    Capabilities, FeedBackend, Implementation, ParticipantBackend, ParticipantConfig,
};
use crate::dds::entities::{EndpointSide, LocalEntities, NodeKey};
use crate::dds_error::DdsError;
use crate::discovery::{DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId};
use crate::local_sink::LocalSink;
use crate::raw::{ServiceEndpointId, ServiceEndpointRole};
use crate::signal_handler::{self, SignalHandlerError, SignalHandlerOptions};
use crate::Gid;
use env::{DiscoveryOptions, DomainId, DomainIdError};
use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;

/// Why a [`Context`] could not be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ContextError {
    /// `ROS_DOMAIN_ID` (or the domain given) is not valid.
    #[error(transparent)]
    DomainId(#[from] DomainIdError),
    /// The backend asked for (by the builder, `HORUS_ROS_BACKEND` or `RMW_IMPLEMENTATION`) cannot
    /// be used.
    #[error(transparent)]
    Backend(#[from] BackendError),
    /// The process's `--ros-args` are malformed or unknown (rcl's / rclcpp's message).
    #[error(transparent)]
    Arguments(#[from] crate::args::ArgumentsError),
    /// The DDS participant could not be created (e.g. no free ports).
    #[error("could not create the DDS participant in domain {domain}: {cause}")]
    Participant {
        /// The domain asked for.
        domain: DomainId,
        /// What the DDS layer said.
        cause: DdsError,
    },
    /// The SIGINT/SIGTERM handlers asked for could not be installed.
    #[error(transparent)]
    SignalHandler(#[from] SignalHandlerError),
}

/// Builds a [`Context`]; values not set come from the environment as rcl reads it.
#[derive(Debug, Default, Clone)]
#[must_use = "a builder does nothing until .build() is called"]
pub struct ContextBuilder {
    domain_id: Option<u32>,
    discovery: Option<DiscoveryOptions>,
    backend: Option<Backend>,
    implementation: Option<Arc<dyn Implementation>>,
    enclave: Option<String>,
    arguments: Option<crate::args::Arguments>,
    signal_handler: Option<SignalHandlerOptions>,
}

/// rcl's environment variable overriding the security enclave (`ROS_SECURITY_ENCLAVE_OVERRIDE`).
pub const ENCLAVE_OVERRIDE_ENV: &str = "ROS_SECURITY_ENCLAVE_OVERRIDE";

impl ContextBuilder {
    /// Uses this domain instead of `ROS_DOMAIN_ID` (checked at [`build`](Self::build)).
    pub fn domain_id(mut self, domain_id: u32) -> Self {
        self.domain_id = Some(domain_id);
        self
    }

    /// Uses these discovery options instead of `ROS_AUTOMATIC_DISCOVERY_RANGE` / `ROS_STATIC_PEERS`.
    pub fn discovery(mut self, discovery: DiscoveryOptions) -> Self {
        self.discovery = Some(discovery);
        self
    }

    /// Runs on this DDS implementation instead of the one the environment chooses
    /// (`HORUS_ROS_BACKEND`, else `RMW_IMPLEMENTATION`: see [`Backend::select`]); the environment
    /// is then not consulted for it at all.
    pub fn backend(mut self, backend: Backend) -> Self {
        self.backend = Some(backend);
        self
    }

    /// Runs on this implementation of the [backend contract](crate::contract) instead of a
    /// built-in backend (e.g. an in-memory one in tests); it wins over
    /// [`backend`](Self::backend) and the environment.
    pub fn implementation(mut self, implementation: Arc<dyn Implementation>) -> Self {
        self.implementation = Some(implementation);
        self
    }

    /// Announces this security enclave (participant USER_DATA `enclave=…;`) instead of
    /// `ROS_SECURITY_ENCLAVE_OVERRIDE` or `/`.
    pub fn enclave(mut self, enclave: impl Into<String>) -> Self {
        self.enclave = Some(enclave.into());
        self
    }

    /// Uses these ROS arguments instead of the process's (`std::env::args`, parsed as
    /// `rclcpp::init` does). `Arguments::default()` means none.
    pub fn arguments(mut self, arguments: crate::args::Arguments) -> Self {
        self.arguments = Some(arguments);
        self
    }

    /// The signals that shut this context down (default: what
    /// [`set_default_signal_handler_options`](signal_handler::set_default_signal_handler_options)
    /// set, initially [`SignalHandlerOptions::All`], as `rclcpp::init`); building installs their
    /// handlers, process-wide and once (see [`signal_handler`]). `SignalHandlerOptions::None`
    /// opts this context out: a signal then neither shuts it down nor deletes its participant.
    pub fn signal_handler(mut self, options: SignalHandlerOptions) -> Self {
        self.signal_handler = Some(options);
        self
    }

    /// Creates the participant. Warnings (deprecated or unsupported settings) go to `tracing`.
    pub fn build(self) -> Result<Context, ContextError> {
        let get = |k: &str| std::env::var(k).ok();
        let environment = env::read_environment(get)?;
        let domain = match self.domain_id {
            Some(d) => DomainId::new(d)?,
            None => environment.domain_id,
        };
        let discovery = self.discovery.unwrap_or(environment.discovery);
        for w in &environment.warnings {
            tracing::warn!("{w}");
        }
        let (backend, implementation) = match self.implementation {
            Some(implementation) => (None, implementation),
            None => {
                let backend = match self.backend {
                    Some(b) => b,
                    None => Backend::from_env_with(get)?,
                };
                (Some(backend), backend.implementation()?)
            }
        };
        let arguments = match self.arguments {
            Some(a) => a,
            None => crate::args::Arguments::from_process()?,
        };
        // rcl: `--enclave` first, then ROS_SECURITY_ENCLAVE_OVERRIDE, then `/`.
        let enclave = self
            .enclave
            .or_else(|| arguments.enclave.clone())
            .or_else(|| get(ENCLAVE_OVERRIDE_ENV).filter(|e| !e.is_empty()))
            .unwrap_or_else(|| "/".to_owned());
        let signals = self
            .signal_handler
            .unwrap_or_else(signal_handler::default_signal_handler_options);
        Context::create(
            domain,
            discovery,
            (backend, implementation),
            enclave,
            arguments,
            signals,
        )
    }
}

/// A connection to one ROS 2 domain: a DDS participant and the nodes living on it.
///
/// Cloning is cheap; the participant goes away with the last clone and the last node.
#[derive(Clone)]
pub struct Context {
    inner: Arc<ContextInner>,
}

/// How long a goodbye waits for its peers to acknowledge the last `ros_discovery_info` message.
const GOODBYE_ACK_LIMIT: std::time::Duration = std::time::Duration::from_secs(1);

/// Fields drop in declaration order: the DDS participant goes after the local bookkeeping.
pub(crate) struct ContextInner {
    pub(crate) participant: Box<dyn ParticipantBackend>,
    pub(crate) implementation: Arc<dyn Implementation>,
    pub(crate) domain: DomainId,
    pub(crate) discovery: DiscoveryOptions,
    pub(crate) backend: Option<Backend>,
    pub(crate) enclave: String,
    pub(crate) arguments: Arc<crate::args::Arguments>,
    pub(crate) gid: Gid,
    local: Mutex<LocalState>,
    feed_open: AtomicBool,
    /// rmw_cyclonedds' per-context client/service counter (`client_service_id`).
    service_endpoint_ids: AtomicU32,
    /// What the layers above keep per context, one value per type (see [`Context::shared`]).
    shared: Mutex<HashMap<TypeId, Weak<dyn Any + Send + Sync>>>,
    /// Whether and why it was shut down (see [`Context::shutdown`]).
    pub(crate) shutdown: Arc<shutdown::Shutdown>,
}

/// What this participant itself holds: its nodes, its endpoints, and where to report changes to
/// them (the open [`DiscoveryFeed`], since DDS discovery reports only remote entities).
pub(crate) struct LocalState {
    entities: LocalEntities,
    endpoints: BTreeMap<Gid, DiscoveredEndpoint>,
    sink: Option<LocalSink>,
}

impl LocalState {
    /// Reports `event` to the open feed, if any; a closed feed stops the reporting.
    fn report(&mut self, event: DiscoveryEvent) {
        if let Some(sink) = &self.sink {
            if !sink.send(event) {
                self.sink = None;
            }
        }
    }
}

impl std::fmt::Debug for Context {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context")
            .field("backend", &self.inner.implementation.name())
            .field("domain", &self.inner.domain)
            .field("discovery", &self.inner.discovery)
            .field("gid", &self.inner.gid)
            .finish()
    }
}

impl Context {
    /// A context configured from the environment (`ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE`,
    /// `ROS_STATIC_PEERS`, `ROS_LOCALHOST_ONLY`).
    pub fn from_env() -> Result<Self, ContextError> {
        Self::builder().build()
    }

    /// The context's one value of type `T`: made by `create` on first use, then the same for
    /// every caller while any of them holds it (how the graph cache and the clients' response
    /// wait set are shared by everything on a context, without a process-wide registry).
    /// `create` must not call `shared` itself.
    pub fn shared<T, E>(&self, create: impl FnOnce() -> Result<T, E>) -> Result<Arc<T>, E>
    where
        T: Any + Send + Sync,
    {
        let mut shared = self.inner.shared.lock().unwrap_or_else(|p| p.into_inner());
        shared.retain(|_, v| v.strong_count() > 0);
        if let Some(value) = shared
            .get(&TypeId::of::<T>())
            .and_then(Weak::upgrade)
            .and_then(|v| v.downcast::<T>().ok())
        {
            return Ok(value);
        }
        let value = Arc::new(create()?);
        let erased: Arc<dyn Any + Send + Sync> = value.clone();
        shared.insert(TypeId::of::<T>(), Arc::downgrade(&erased));
        Ok(value)
    }

    /// A builder to override the environment.
    pub fn builder() -> ContextBuilder {
        ContextBuilder::default()
    }

    fn create(
        domain: DomainId,
        discovery: DiscoveryOptions,
        (backend, implementation): (Option<Backend>, Arc<dyn Implementation>),
        enclave: String,
        arguments: crate::args::Arguments,
        signals: SignalHandlerOptions,
    ) -> Result<Self, ContextError> {
        let participant = implementation
            .create_participant(&ParticipantConfig {
                domain,
                discovery: &discovery,
                enclave: &enclave,
            })
            .map_err(|cause| ContextError::Participant { domain, cause })?;
        let gid = participant.gid();
        let local = Mutex::new(LocalState {
            entities: LocalEntities::new(gid),
            endpoints: BTreeMap::new(),
            sink: None,
        });
        tracing::debug!(%domain, backend = implementation.name(), participant = %gid, "created the participant");
        let inner = Arc::new(ContextInner {
            participant,
            implementation,
            domain,
            discovery,
            backend,
            enclave,
            arguments: Arc::new(arguments),
            gid,
            local,
            feed_open: AtomicBool::new(false),
            service_endpoint_ids: AtomicU32::new(0),
            shared: Mutex::new(HashMap::new()),
            shutdown: Arc::new(shutdown::Shutdown::new(signals)),
        });
        signal_handler::register_context(&inner)?;
        Ok(Self { inner })
    }

    /// The ROS arguments its nodes follow (`--ros-args` of the process, unless the builder
    /// was given others).
    pub fn arguments(&self) -> &crate::args::Arguments {
        &self.inner.arguments
    }

    /// The built-in backend this context runs on; `None` for an implementation given with
    /// [`ContextBuilder::implementation`].
    pub fn backend(&self) -> Option<Backend> {
        self.inner.backend
    }

    /// What this context's backend can do.
    pub fn capabilities(&self) -> Capabilities {
        self.inner.implementation.capabilities()
    }

    /// The rmw implementation this context's backend stands in for (e.g. `rmw_fastrtps_cpp`).
    pub fn rmw_implementation(&self) -> &'static str {
        self.inner.implementation.rmw_implementation()
    }

    /// The security enclave announced (`/` unless set).
    pub fn enclave(&self) -> &str {
        &self.inner.enclave
    }

    /// The RTPS vendor id of this context's own participant.
    pub fn vendor_id(&self) -> VendorId {
        self.inner.implementation.vendor_id()
    }

    /// A new id for one service client or server (its request and reply endpoints share it),
    /// announced in their USER_DATA as `clientid=…;` / `serviceid=…;` by backends that announce
    /// USER_DATA. As rmw_cyclonedds `get_unique_csid`: the participant's 12-byte GUID prefix
    /// followed by a per-context counter (from 1), big-endian. `service_type_hash` is the RIHS01
    /// hash of the service type ([`TypeHash::ZERO`](horus_ros_msgs::TypeHash::ZERO) if unknown).
    pub fn new_service_endpoint_id(
        &self,
        role: ServiceEndpointRole,
        service_type_hash: horus_ros_msgs::TypeHash,
    ) -> ServiceEndpointId {
        let n = self
            .inner
            .service_endpoint_ids
            .fetch_add(1, Ordering::Relaxed)
            .wrapping_add(1);
        let mut id = [0u8; 16];
        id[..12].copy_from_slice(&self.inner.gid.as_bytes()[..12]);
        id[12..].copy_from_slice(&n.to_be_bytes());
        ServiceEndpointId {
            role,
            id,
            service_type_hash,
        }
    }

    /// The domain this context is in.
    pub fn domain_id(&self) -> DomainId {
        self.inner.domain
    }

    /// The discovery options in force.
    pub fn discovery_options(&self) -> &DiscoveryOptions {
        &self.inner.discovery
    }

    /// The participant's GID (the one it announces in `ros_discovery_info`).
    pub fn gid(&self) -> Gid {
        self.inner.gid
    }

    /// What this participant currently announces on `ros_discovery_info`.
    pub fn announced_entities(&self) -> ParticipantEntitiesInfo {
        self.inner.local().entities.message()
    }

    pub(crate) fn inner(&self) -> &Arc<ContextInner> {
        &self.inner
    }
}

impl ContextInner {
    /// Takes the context off every peer's graph now, while its nodes and endpoints may still be
    /// held (the goodbye of a process ending on a signal; see [`signal_handler`]): announces no
    /// nodes on `ros_discovery_info`, waits (bounded) for the peers' acknowledgments, then deletes
    /// the DDS participant with everything on it. The context's entities fail from then on.
    pub(crate) fn goodbye(&self) {
        // Under the lock, so that no later announcement overtakes the last one.
        let _local = self.local();
        tracing::debug!(participant = %self.gid, "goodbye: no nodes left");
        // As the nodes' own destruction announces it (rmw_destroy_node): what rmw_fastrtps and
        // rmw_cyclonedds peers build their node lists from (`GraphCache::update_participant_entities`).
        self.participant
            .publish_discovery_info(&ParticipantEntitiesInfo {
                gid: self.gid,
                node_entities_info_seq: Vec::new(),
            });
        // Reliable: the message is resent until each peer acknowledged it, which the
        // participant's deletion would cut short.
        if !self
            .participant
            .wait_for_discovery_info_acks(GOODBYE_ACK_LIMIT)
        {
            tracing::debug!("goodbye: not every peer acknowledged the last ros_discovery_info");
        }
        tracing::debug!(participant = %self.gid, "goodbye: deleting the participant");
        self.participant.delete();
    }

    /// Locks what this participant holds (a poisoned lock still holds consistent data: every
    /// mutation is a single push/retain/insert).
    fn local(&self) -> MutexGuard<'_, LocalState> {
        lock(&self.local)
    }

    /// Publishes the participant's new message and reports it to the feed. Called under the
    /// lock, so that messages leave in the order of the changes.
    fn announce(&self, local: &mut LocalState, message: ParticipantEntitiesInfo) {
        self.participant.publish_discovery_info(&message);
        local.report(DiscoveryEvent::ParticipantEntities(message));
    }

    /// Adds a node and announces it.
    pub(crate) fn add_node(&self, namespace: &str, name: &str) -> NodeKey {
        let mut local = self.local();
        let (key, message) = local.entities.add_node(namespace, name);
        self.participant
            .node_added(&crate::contract::NodeDescription {
                id: key.id(),
                namespace,
                name,
            });
        self.announce(&mut local, message);
        key
    }

    /// Removes a node and announces it.
    pub(crate) fn remove_node(&self, key: NodeKey) {
        let mut local = self.local();
        if let Some(message) = local.entities.remove_node(key) {
            self.announce(&mut local, message);
        }
        self.participant.node_removed(key.id());
    }

    /// Lists a new endpoint under a node and announces it.
    pub(crate) fn add_endpoint(
        &self,
        key: NodeKey,
        side: EndpointSide,
        endpoint: DiscoveredEndpoint,
    ) {
        let mut local = self.local();
        let gid = endpoint.gid;
        local.endpoints.insert(gid, endpoint.clone());
        local.report(DiscoveryEvent::EndpointDiscovered(endpoint));
        if let Some(message) = local.entities.associate(key, side, gid) {
            self.announce(&mut local, message);
        }
    }

    /// Records a new endpoint that no node lists: reported to this context's own feed (so
    /// its graph sees what peers see through SEDP), never put in `ros_discovery_info`.
    pub(crate) fn add_unlisted_endpoint(&self, endpoint: DiscoveredEndpoint) {
        let mut local = self.local();
        local.endpoints.insert(endpoint.gid, endpoint.clone());
        local.report(DiscoveryEvent::EndpointDiscovered(endpoint));
    }

    /// Withdraws an endpoint from its node and announces it.
    pub(crate) fn remove_endpoint(&self, key: NodeKey, side: EndpointSide, gid: Gid) {
        let mut local = self.local();
        if let Some(endpoint) = local.endpoints.remove(&gid) {
            local.report(DiscoveryEvent::EndpointLost {
                gid,
                kind: endpoint.kind,
            });
        }
        if let Some(message) = local.entities.dissociate(key, side, gid) {
            self.announce(&mut local, message);
        }
    }
}

/// Every [`DiscoveryEvent`] of a context: remote participants (SPDP), readers and writers (SEDP),
/// other participants' `ros_discovery_info` messages, and the context's own participant, nodes
/// and endpoints (reported by the context itself, first as a snapshot when the feed opens).
/// Dropping the feed allows opening another.
pub struct DiscoveryFeed {
    feed: Box<dyn FeedBackend>,
    context: Context,
}

impl Drop for DiscoveryFeed {
    fn drop(&mut self) {
        let inner = &self.context.inner;
        inner.local().sink = None;
        inner.feed_open.store(false, Ordering::SeqCst);
    }
}

/// Locks a mutex whose data stays consistent even if a holder panicked.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl std::fmt::Debug for DiscoveryFeed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiscoveryFeed")
            .field("participant", &self.context.gid())
            .finish()
    }
}

impl DiscoveryFeed {
    /// The next event, if one is waiting (non-blocking).
    pub fn try_next(&mut self) -> Option<DiscoveryEvent> {
        self.feed.try_next()
    }

    /// The next event, waiting for it at most `timeout` (woken by the DDS layer, no polling).
    /// With no timeout (`None`) it waits until an event comes or the feed's
    /// [`waker`](Self::waker) is woken; a wake-up with nothing to report returns `None`.
    pub fn next_timeout(
        &mut self,
        timeout: impl Into<Option<std::time::Duration>>,
    ) -> Option<DiscoveryEvent> {
        crate::feed_wait::next_timeout(self.feed.as_mut(), timeout.into())
    }

    /// A handle that makes the current or next [`next_timeout`](Self::next_timeout) return,
    /// from any thread (e.g. to stop the thread reading the feed).
    pub fn waker(&self) -> FeedWaker {
        FeedWaker(self.feed.waker())
    }
}

/// Wakes a [`DiscoveryFeed`]'s reader from any thread; cheap to clone.
#[derive(Clone)]
pub struct FeedWaker(Arc<dyn crate::contract::Wake>);

impl FeedWaker {
    /// Makes the feed's current or next wait return.
    pub fn wake(&self) {
        self.0.wake();
    }
}

impl std::fmt::Debug for FeedWaker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("FeedWaker")
    }
}

impl Context {
    /// Opens the context's discovery feed (one per context). What was discovered since the
    /// participant was created is delivered too.
    pub fn discovery_feed(&self) -> Result<DiscoveryFeed, DiscoveryFeedError> {
        if self.inner.feed_open.swap(true, Ordering::SeqCst) {
            return Err(DiscoveryFeedError::AlreadyOpen);
        }
        let (mut sink, local) = LocalSink::new();
        let feed = self.inner.participant.open_feed(local).inspect_err(|_| {
            self.inner.feed_open.store(false, Ordering::SeqCst);
        })?;
        sink.wake_with(feed.waker());
        // The snapshot of what this participant holds, then every later change, in order.
        let mut local = self.inner.local();
        let _ = sink.send(DiscoveryEvent::ParticipantDiscovered(
            DiscoveredParticipant {
                gid: self.inner.gid,
                vendor_id: self.vendor_id(),
                enclave: Some(self.inner.enclave.clone()),
            },
        ));
        for endpoint in local.endpoints.values() {
            let _ = sink.send(DiscoveryEvent::EndpointDiscovered(endpoint.clone()));
        }
        let _ = sink.send(DiscoveryEvent::ParticipantEntities(
            local.entities.message(),
        ));
        local.sink = Some(sink);
        drop(local);
        Ok(DiscoveryFeed {
            feed,
            context: self.clone(),
        })
    }
}
