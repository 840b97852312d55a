//! horus-ros' Zenoh backend, wire-compatible with rmw_zenoh_cpp 0.2.10 (ROS 2 Jazzy) on zenoh
//! 1.8 (`Backend::Zenoh`, `horus-ros-rmw`'s cargo feature `zenoh`), behind the backend contract
//! (`horus-ros-rmw-contract`), its only horus-ros dependency beside the messages. What goes on the wire is written down in
//! `shared/docs/rmw-zenoh-jazzy-wire-facts.md`; each file cites the rmw_zenoh source it follows.
//!
//! - [`config`]: the session (peer, `tcp/localhost:7447`) and router configurations and the
//!   environment rmw_zenoh reads (`ZENOH_SESSION_CONFIG_URI`, `ZENOH_CONFIG_OVERRIDE`,
//!   `ZENOH_ROUTER_CHECK_ATTEMPTS`).
//! - [`shm`]: same-host shared memory, off by default as in rmw_zenoh, on with
//!   `transport/shared_memory/enabled=true` (`ZENOH_SHM_ALLOC_SIZE`,
//!   `ZENOH_SHM_MESSAGE_SIZE_THRESHOLD`).
//! - `liveliness`: the `@ros2_lv/…` tokens, their QoS chunk and the GIDs (XXH3-128 of the key).
//! - `keyexpr`: data keys `<domain>/<name>/<type>/<hash>`.
//! - `attachment`: the 33-byte attachment of every sample.
//! - `endpoints`: publishers and subscriptions (TRANSIENT_LOCAL ones on zenoh-ext's advanced
//!   publisher and subscriber, as rmw_zenoh's); `services`: servers (queryables) and clients
//!   (queries), each with its `SS`/`SC` token; `feed`: the graph from tokens, as the
//!   DDS-shaped [`DiscoveryEvent`](horus_ros_rmw_contract::DiscoveryEvent)s; waiting on the contract's `push` helpers.
//!
//! One Zenoh session per context (rmw_zenoh's `rmw_context_impl_s`); nodes and entities are
//! numbered by one per-context counter, the node first (rmw_zenoh's `get_next_entity_id`).
//! A service's request and reply endpoints (the contract's, paired by their service id) are one
//! queryable or client, as rmw_zenoh's. `ROS_AUTOMATIC_DISCOVERY_RANGE`
//! and `ROS_STATIC_PEERS` are not used, as rmw_zenoh 0.2.10 does not use them
//! (ros2/rmw_zenoh#241): the Zenoh configuration decides whom a session reaches.

pub mod config;
pub mod shm;

mod attachment;
mod endpoints;
mod feed;
mod keyexpr;
mod liveliness;
mod route;
mod services;

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicI64, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::time::Duration;

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use zenoh::liveliness::LivelinessToken;
use zenoh::qos::{CongestionControl, Priority, Reliability};
use zenoh::sample::Locality;
use zenoh::Wait;

use endpoints::{
    zenoh_error, Delivery, Publication, ReaderQueue, Subscription, ZenohReader, ZenohWriter,
};
use feed::Graph;
use horus_ros_rmw_contract::dds_error::DdsError;
use horus_ros_rmw_contract::discovery::VendorId;
use horus_ros_rmw_contract::push::{lock, WaitSet};
use horus_ros_rmw_contract::qos::{
    DdsQos, DurabilityPolicy, EndpointKind, HistoryPolicy, Qos, ReliabilityPolicy,
};
use horus_ros_rmw_contract::Gid;
use horus_ros_rmw_contract::{
    Capabilities, DiscoveryFeedError, EndpointOwner, FeedBackend, Implementation, LocalEvents,
    NodeDescription, ParticipantBackend, ParticipantConfig, RawEndpointSpec, ReaderBackend,
    ServiceEndpointId, ServiceEndpointRole, WaitSetBackend, WaitSetError, WriterBackend,
};
use liveliness::{EntityKind, Token, TopicInfo, ADMIN_SPACE, DEFAULT_DEPTH};
use services::{ServiceEntity, ServiceWriter};
use zenoh_ext::{
    AdvancedPublisherBuilderExt, AdvancedSubscriberBuilderExt, CacheConfig, HistoryConfig,
    MissDetectionConfig, RecoveryConfig,
};

/// The period of a RELIABLE TRANSIENT_LOCAL publisher's sporadic heartbeats (zenoh-ext's
/// sample-miss detection, which rmw_zenoh turns on; the wire facts do not give the period).
const HEARTBEAT_PERIOD: Duration = Duration::from_millis(500);

/// How many samples an endpoint keeps: its KEEP_LAST depth (rmw_zenoh's 42 for the system
/// default), at most [`endpoints::MAX_SAMPLES`] for KEEP_ALL.
fn history_depth(qos: &Qos) -> usize {
    match (qos.history, qos.depth) {
        (HistoryPolicy::KeepAll, _) => endpoints::MAX_SAMPLES,
        (_, 0) => DEFAULT_DEPTH,
        (_, d) => d.min(endpoints::MAX_SAMPLES),
    }
}

/// The backend's name (`HORUS_ROS_BACKEND=zenoh`).
pub const NAME: &str = "zenoh";

/// The rmw implementation it stands in for.
pub const RMW_IMPLEMENTATION: &str = "rmw_zenoh_cpp";

/// The environment variables its own configuration reads, beyond ROS's (rmw_zenoh's session configuration file and its overrides): what
/// else, with the domain and the discovery options, decides which graph a context sees.
pub const CONFIGURATION_ENV: &[&str] = &["ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE"];

/// The vendor id its sessions report (Zenoh is not RTPS: horus-ros' own mark).
pub const VENDOR_ID: VendorId = VendorId::ZENOH;

/// What it can do: services are Zenoh's own request/reply (queryables and queries, the
/// identities in rmw_zenoh's attachment); no DDS USER_DATA (the liveliness tokens carry the
/// type hashes and enclaves).
pub const CAPABILITIES: Capabilities = Capabilities::NONE
    .with_service_queries()
    .with_type_hashes_announced();

/// The Zenoh backend: a Zenoh session per context, configured from the environment as rmw_zenoh
/// configures it, or with a configuration of the program's own ([`implementation`]).
#[derive(Debug, Default)]
pub struct Zenoh {
    /// The session configuration, instead of the environment's.
    config: Option<zenoh::Config>,
}

/// The Zenoh backend with this session configuration instead of the one the environment gives
/// (`ZENOH_SESSION_CONFIG_URI`, `ZENOH_CONFIG_OVERRIDE`; see [`config::config`]), for
/// `ContextBuilder::implementation` (horus-ros-rmw): e.g. a program that
/// joins two Zenoh networks at once, or tests with routers of their own.
/// `ZENOH_ROUTER_CHECK_ATTEMPTS` is still read.
pub fn implementation(config: zenoh::Config) -> Arc<dyn Implementation> {
    Arc::new(Zenoh {
        config: Some(config),
    })
}

impl Implementation for Zenoh {
    fn name(&self) -> &'static str {
        NAME
    }

    fn rmw_implementation(&self) -> &'static str {
        RMW_IMPLEMENTATION
    }

    fn vendor_id(&self) -> VendorId {
        VENDOR_ID
    }

    fn capabilities(&self) -> Capabilities {
        CAPABILITIES
    }

    fn create_participant(
        &self,
        config: &ParticipantConfig<'_>,
    ) -> Result<Box<dyn ParticipantBackend>, DdsError> {
        let get = |k: &str| std::env::var(k).ok();
        let zenoh_config = match &self.config {
            Some(c) => c.clone(),
            None => config::config(config::ConfigKind::Session, get)
                .map_err(|e| DdsError::Create(horus_ros_rmw_contract::dds_error::boxed(e)))?,
        };
        let attempts = config::router_check_attempts(get)
            .map_err(|e| DdsError::Create(horus_ros_rmw_contract::dds_error::boxed(e)))?;
        // rmw_context_impl_s.cpp: the ShmContext when the configuration enables shared memory.
        let shm = shm::ShmContext::for_session(&zenoh_config, get)
            .map_err(|e| DdsError::Create(horus_ros_rmw_contract::dds_error::boxed(e)))?
            .map(Arc::new);
        let session = off_current_thread_runtime(|| zenoh::open(zenoh_config).wait())
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        if let Some(attempts) = attempts {
            if !off_current_thread_runtime(|| config::wait_for_router(&session, attempts)) {
                tracing::warn!(
                    "Unable to connect to a Zenoh router after {attempts} retries (rmw_zenoh's \
                     warning); going on without one: start `horus-ros router` (or rmw_zenohd) \
                     or set {}",
                    config::ROUTER_CHECK_ATTEMPTS_ENV
                );
            }
        }
        ZenohParticipant::new(session, u32::from(config.domain.get()), config.enclave, shm)
            .map(|p| Box::new(p) as Box<dyn ParticipantBackend>)
    }
}

/// Runs `f`, a call that may block inside zenoh, where zenoh can block: zenoh 1.8 blocks with
/// tokio's `block_in_place`, which it refuses (panics) on a thread that runs a current-thread
/// tokio runtime (zenoh-runtime's `ZRuntime::block_in_place`) — a program under
/// `#[tokio::main(flavor = "current_thread")]` creating a context. There `f` runs on a thread
/// of its own, the caller waiting for it; elsewhere, on the caller's thread.
fn off_current_thread_runtime<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    use tokio_runtime::runtime::{Handle, RuntimeFlavor};
    let current_thread =
        Handle::try_current().is_ok_and(|h| h.runtime_flavor() == RuntimeFlavor::CurrentThread);
    if !current_thread {
        return f();
    }
    std::thread::scope(|scope| {
        scope
            .spawn(f)
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

/// A node of this context: its ids and its token.
struct NodeEntry {
    /// rmw_zenoh's node id (from the context's entity counter).
    id: u64,
    namespace: String,
    name: String,
    _token: Option<LivelinessToken>,
}

/// A context's session, closed and dropped where zenoh may block
/// ([`off_current_thread_runtime`]): dropping the last handle of a session closes it.
struct SessionHandle(Option<zenoh::Session>);

impl std::ops::Deref for SessionHandle {
    type Target = zenoh::Session;

    fn deref(&self) -> &zenoh::Session {
        // Taken only by `drop`.
        self.0
            .as_ref()
            .unwrap_or_else(|| unreachable!("a session is held until dropped"))
    }
}

impl Drop for SessionHandle {
    fn drop(&mut self) {
        if let Some(session) = self.0.take() {
            off_current_thread_runtime(move || drop(session));
        }
    }
}

/// A context's session, its nodes and the graph it sees.
pub(crate) struct ZenohParticipant {
    session: SessionHandle,
    zid: String,
    domain: u32,
    enclave: String,
    gid: Gid,
    /// rmw_zenoh's per-context entity counter: nodes and entities alike.
    next_id: AtomicU64,
    nodes: Mutex<HashMap<u64, NodeEntry>>,
    /// The service servers and clients whose first endpoint was made, by service id, until the
    /// second one takes it.
    services: Mutex<HashMap<[u8; 16], Weak<ServiceEntity>>>,
    graph: Arc<Graph>,
    _graph_subscriber: zenoh::pubsub::Subscriber<()>,
    deleted: Arc<AtomicBool>,
    /// The shared-memory provider publishers put large messages in, when enabled.
    shm: Option<Arc<shm::ShmContext>>,
}

impl ZenohParticipant {
    fn new(
        session: zenoh::Session,
        domain: u32,
        enclave: &str,
        shm: Option<Arc<shm::ShmContext>>,
    ) -> Result<Self, DdsError> {
        let session = SessionHandle(Some(session));
        let zid = session.zid().to_string();
        let graph = Arc::new(Graph::new(zid.clone(), domain));
        // rmw_context_impl_s.cpp: a liveliness subscriber on the domain's tokens with history,
        // and a liveliness get for what was there before (duplicates are ignored).
        let prefix = format!("{ADMIN_SPACE}/{domain}/**");
        // DELETEs are confirmed before they are applied (see `Graph::token`).
        let confirmer = feed::DeleteConfirmer::start((*session).clone(), Arc::clone(&graph))
            .map_err(|e| DdsError::Create(horus_ros_rmw_contract::dds_error::boxed(e)))?;
        let on_token = {
            let graph = Arc::clone(&graph);
            move |sample: zenoh::sample::Sample| {
                let put = sample.kind() == zenoh::sample::SampleKind::Put;
                let key = sample.key_expr().as_str();
                if let Some(ticket) = graph.token(key, put) {
                    confirmer.confirm(key, ticket);
                }
            }
        };
        let graph_subscriber = session
            .liveliness()
            .declare_subscriber(&prefix)
            .history(true)
            .callback(on_token)
            .wait()
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let replies = session
            .liveliness()
            .get(&prefix)
            .timeout(Duration::from_secs(10))
            .wait()
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        while let Ok(reply) = replies.recv() {
            if let Ok(sample) = reply.result() {
                graph.token(sample.key_expr().as_str(), true);
            }
        }
        Ok(Self {
            gid: feed::participant_gid(&zid),
            session,
            zid,
            domain,
            enclave: enclave.to_owned(),
            next_id: AtomicU64::new(0),
            nodes: Mutex::new(HashMap::new()),
            services: Mutex::new(HashMap::new()),
            graph,
            _graph_subscriber: graph_subscriber,
            deleted: Arc::new(AtomicBool::new(false)),
            shm,
        })
    }

    fn next_id(&self) -> u64 {
        self.next_id.fetch_add(1, Ordering::Relaxed)
    }

    /// Declares a liveliness token (a failure is logged: the entity works, unseen).
    fn declare_token(&self, key: &str) -> Option<LivelinessToken> {
        match self
            .session
            .liveliness()
            .declare_token(key.to_owned())
            .wait()
        {
            Ok(token) => Some(token),
            Err(e) => {
                tracing::warn!(key, "zenoh: could not declare the liveliness token: {e}");
                None
            }
        }
    }

    /// The token of a node's entity, if it has one: a listed entity of a known node.
    fn entity_token(
        &self,
        owner: EndpointOwner,
        kind: EntityKind,
        entity_id: u64,
        topic: TopicInfo,
    ) -> Option<Token> {
        if !owner.listed {
            return None;
        }
        let nodes = lock(&self.nodes);
        let node = nodes.get(&owner.node)?;
        let mut topic = topic;
        if topic.qos.depth == 0 && topic.qos.history != HistoryPolicy::KeepAll {
            topic.qos.depth = DEFAULT_DEPTH;
        }
        Some(Token {
            domain: self.domain,
            zid: self.zid.clone(),
            node_id: node.id,
            entity_id,
            kind,
            enclave: self.enclave.clone(),
            namespace: node.namespace.clone(),
            node_name: node.name.clone(),
            topic: Some(topic),
        })
    }

    /// The token of a node's endpoint on a ROS topic (`rt/…`), if it has one.
    fn endpoint_token(
        &self,
        owner: EndpointOwner,
        spec: &RawEndpointSpec,
        kind: EntityKind,
        entity_id: u64,
    ) -> Option<Token> {
        let topic = keyexpr::ros_topic_of(&spec.dds_topic_name)?;
        self.entity_token(
            owner,
            kind,
            entity_id,
            TopicInfo {
                name: topic,
                type_name: spec.dds_type_name.clone(),
                type_hash: spec.type_hash,
                qos: spec.qos,
            },
        )
    }

    /// The service server or client that the request/reply endpoint `spec` belongs to: the one
    /// its other endpoint made, or a new one (its queryable or client, and its `SS`/`SC` token,
    /// whose hash is the request endpoint's GID; the reply endpoint's is the hash of the key
    /// followed by `#reply`, as the graph maps remote tokens).
    fn service_entity(
        &self,
        owner: Option<EndpointOwner>,
        spec: &RawEndpointSpec,
        id: ServiceEndpointId,
        (name, type_name): (String, String),
    ) -> Result<Arc<ServiceEntity>, DdsError> {
        let mut services = lock(&self.services);
        if let Some(entity) = services.remove(&id.id).and_then(|w| w.upgrade()) {
            return Ok(entity);
        }
        services.retain(|_, w| w.strong_count() > 0);
        let entity_id = self.next_id();
        let kind = match id.role {
            ServiceEndpointRole::Server => EntityKind::Service,
            ServiceEndpointRole::Client => EntityKind::Client,
        };
        let hash = id.service_type_hash;
        let (key, query) = (
            keyexpr::service_key(self.domain, &name, &type_name, &hash),
            keyexpr::service_query(self.domain, &name, &type_name, &hash),
        );
        let topic = TopicInfo {
            name,
            type_name,
            type_hash: id.service_type_hash,
            qos: spec.qos,
        };
        let token = owner.and_then(|o| self.entity_token(o, kind, entity_id, topic));
        let token_key = token
            .as_ref()
            .map_or_else(|| format!("{}/{entity_id}", self.zid), Token::key);
        let gids = (
            liveliness::gid_of_key(&token_key),
            liveliness::gid_of_key(&format!("{token_key}#reply")),
        );
        // The token after the queryable (the entity declares it): a client that sees it finds
        // the queryable.
        let declare = || {
            token
                .is_some()
                .then(|| self.declare_token(&token_key))
                .flatten()
        };
        let queue = ReaderQueue::new(services::MAX_HELD_QUERIES, &spec.dds_topic_name);
        let entity = Arc::new(match id.role {
            ServiceEndpointRole::Server => {
                ServiceEntity::server(&self.session, key, gids, declare, queue)?
            }
            ServiceEndpointRole::Client => {
                ServiceEntity::client(&self.session, query, gids, declare, queue)?
            }
        });
        services.insert(id.id, Arc::downgrade(&entity));
        Ok(entity)
    }

    /// The service and its endpoint id, for an endpoint of a service's request or reply topic.
    fn service_of(spec: &RawEndpointSpec) -> Option<(ServiceEndpointId, (String, String))> {
        let id = spec.service_id?;
        let service = keyexpr::service_of(&spec.dds_topic_name, &spec.dds_type_name)?;
        Some((id, service))
    }

    /// A request writer (client) or reply writer (server).
    fn service_writer(
        &self,
        owner: Option<EndpointOwner>,
        spec: &RawEndpointSpec,
        (id, service): (ServiceEndpointId, (String, String)),
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        let entity = self.service_entity(owner, spec, id, service)?;
        let gid = match id.role {
            ServiceEndpointRole::Client => entity.gid,
            ServiceEndpointRole::Server => entity.reply_gid,
        };
        self.graph.add_local(
            gid,
            EndpointKind::Writer,
            &spec.dds_topic_name,
            &spec.dds_type_name,
        );
        Ok((
            Box::new(ServiceWriter {
                entity,
                gid,
                graph: Arc::clone(&self.graph),
                deleted: Arc::clone(&self.deleted),
            }),
            gid,
        ))
    }

    /// A request reader (server) or reply reader (client).
    fn service_reader(
        &self,
        owner: Option<EndpointOwner>,
        spec: &RawEndpointSpec,
        (id, service): (ServiceEndpointId, (String, String)),
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        let entity = self.service_entity(owner, spec, id, service)?;
        let gid = match id.role {
            ServiceEndpointRole::Server => entity.gid,
            ServiceEndpointRole::Client => entity.reply_gid,
        };
        self.graph.add_local(
            gid,
            EndpointKind::Reader,
            &spec.dds_topic_name,
            &spec.dds_type_name,
        );
        Ok((
            Box::new(ZenohReader {
                token: None,
                subscriber: None,
                queue: Arc::clone(&entity.queue),
                service: Some(entity as Arc<dyn std::any::Any + Send + Sync>),
                gid,
                graph: Arc::clone(&self.graph),
            }),
            gid,
        ))
    }

    /// The data key, token key and GID of a new endpoint: with a token, the GID is its hash (as
    /// rmw_zenoh's); without one, the hash of a key of this session's own. The caller declares
    /// the token once its publisher or subscriber is declared, as rmw_zenoh does ("a new
    /// publisher is in town" after the publisher), so that whoever sees the token reaches it.
    fn endpoint_identity(
        &self,
        owner: Option<EndpointOwner>,
        spec: &RawEndpointSpec,
        kind: EntityKind,
    ) -> (String, Option<String>, Gid) {
        let entity_id = self.next_id();
        let data_key = keyexpr::data_key(
            self.domain,
            &spec.dds_topic_name,
            &spec.dds_type_name,
            &spec.type_hash,
        );
        match owner.and_then(|o| self.endpoint_token(o, spec, kind, entity_id)) {
            Some(token) => {
                let key = token.key();
                let gid = liveliness::gid_of_key(&key);
                (data_key, Some(key), gid)
            }
            None => {
                let gid = liveliness::gid_of_key(&format!("{}/{entity_id}", self.zid));
                (data_key, None, gid)
            }
        }
    }

    fn writer(
        &self,
        owner: Option<EndpointOwner>,
        spec: &RawEndpointSpec,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        if self.deleted.load(Ordering::SeqCst) {
            return Err(DdsError::ParticipantDeleted);
        }
        if let Some(service) = Self::service_of(spec) {
            return self.service_writer(owner, spec, service);
        }
        let (key, token_key, gid) = self.endpoint_identity(owner, spec, EntityKind::Publisher);
        // rmw_publisher_data.cpp: BLOCK only for RELIABLE + KEEP_ALL, DROP otherwise.
        let congestion = match (spec.qos.reliability, spec.qos.history) {
            (ReliabilityPolicy::BestEffort, _) => CongestionControl::Drop,
            (_, HistoryPolicy::KeepAll) => CongestionControl::Block,
            _ => CongestionControl::Drop,
        };
        let builder = self
            .session
            .declare_publisher(key.clone())
            .congestion_control(congestion)
            .priority(Priority::Data)
            .express(false)
            // rmw_publisher_data.cpp: BEST_EFFORT is Zenoh's best-effort reliability.
            .reliability(match spec.qos.reliability {
                ReliabilityPolicy::BestEffort => Reliability::BestEffort,
                _ => Reliability::Reliable,
            });
        let publisher = if spec.qos.durability == DurabilityPolicy::TransientLocal {
            // rmw_publisher_data.cpp: a cache of `depth` samples that late joiners query, the
            // publisher announced for them to detect, and sporadic heartbeats when RELIABLE.
            let mut advanced = builder
                .cache(CacheConfig::default().max_samples(history_depth(&spec.qos)))
                .publisher_detection();
            if spec.qos.reliability != ReliabilityPolicy::BestEffort {
                advanced = advanced.sample_miss_detection(
                    MissDetectionConfig::default().sporadic_heartbeat(HEARTBEAT_PERIOD),
                );
            }
            advanced.wait().map(Publication::Advanced)
        } else {
            builder.wait().map(Publication::Plain)
        }
        .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let probe = match publisher {
            Publication::Plain(_) => Some(
                self.session
                    .declare_publisher(key)
                    .allowed_destination(Locality::Remote)
                    .wait()
                    .map_err(|e| zenoh_error(DdsError::Create, e))?,
            ),
            Publication::Advanced(_) => None,
        };
        let (delivery, routes) = Delivery::new(
            publisher,
            probe,
            history_depth(&spec.qos),
            (&spec.dds_topic_name, &spec.dds_type_name),
        )?;
        let token = token_key.and_then(|k| self.declare_token(&k));
        self.graph.add_local(
            gid,
            EndpointKind::Writer,
            &spec.dds_topic_name,
            &spec.dds_type_name,
        );
        Ok((
            Box::new(ZenohWriter {
                delivery,
                _routes: routes,
                token,
                gid,
                sequence_number: AtomicI64::new(0),
                graph: Arc::clone(&self.graph),
                deleted: Arc::clone(&self.deleted),
                shm: self.shm.clone(),
            }),
            gid,
        ))
    }

    fn reader(
        &self,
        owner: Option<EndpointOwner>,
        spec: &RawEndpointSpec,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        if self.deleted.load(Ordering::SeqCst) {
            return Err(DdsError::ParticipantDeleted);
        }
        if let Some(service) = Self::service_of(spec) {
            return self.service_reader(owner, spec, service);
        }
        let (key, token_key, gid) = self.endpoint_identity(owner, spec, EntityKind::Subscription);
        let queue = ReaderQueue::new(history_depth(&spec.qos), &spec.dds_topic_name);
        let builder = {
            let queue = Arc::clone(&queue);
            self.session
                .declare_subscriber(key)
                .callback(move |sample| queue.receive(&sample))
        };
        let subscriber = if spec.qos.durability == DurabilityPolicy::TransientLocal {
            // rmw_subscription_data.cpp: the history of the publishers it detects (late
            // joiners), and recovery of missed samples from their heartbeats when RELIABLE.
            let mut advanced = builder.history(HistoryConfig::default().detect_late_publishers());
            if spec.qos.reliability != ReliabilityPolicy::BestEffort {
                advanced = advanced.recovery(RecoveryConfig::default().heartbeat());
            }
            advanced.wait().map(Subscription::Advanced)
        } else {
            builder.wait().map(Subscription::Plain)
        }
        .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let token = token_key.and_then(|k| self.declare_token(&k));
        self.graph.add_local(
            gid,
            EndpointKind::Reader,
            &spec.dds_topic_name,
            &spec.dds_type_name,
        );
        Ok((
            Box::new(ZenohReader {
                token,
                subscriber: Some(subscriber),
                service: None,
                queue,
                gid,
                graph: Arc::clone(&self.graph),
            }),
            gid,
        ))
    }
}

impl ParticipantBackend for ZenohParticipant {
    fn gid(&self) -> Gid {
        self.gid
    }

    /// Declares the node's `NN` token; the node takes the next entity id (rmw_zenoh's
    /// `rmw_create_node`).
    fn node_added(&self, node: &NodeDescription<'_>) {
        let id = self.next_id();
        let token = Token {
            domain: self.domain,
            zid: self.zid.clone(),
            node_id: id,
            entity_id: id,
            kind: EntityKind::Node,
            enclave: self.enclave.clone(),
            namespace: node.namespace.to_owned(),
            node_name: node.name.to_owned(),
            topic: None,
        };
        let token = self.declare_token(&token.key());
        lock(&self.nodes).insert(
            node.id,
            NodeEntry {
                id,
                namespace: node.namespace.to_owned(),
                name: node.name.to_owned(),
                _token: token,
            },
        );
    }

    fn node_removed(&self, id: u64) {
        lock(&self.nodes).remove(&id);
    }

    fn create_writer(
        &self,
        spec: &RawEndpointSpec,
        _qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        self.writer(None, spec)
    }

    fn create_reader(
        &self,
        spec: &RawEndpointSpec,
        _qos: &DdsQos,
        _responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        self.reader(None, spec)
    }

    fn create_node_writer(
        &self,
        owner: EndpointOwner,
        spec: &RawEndpointSpec,
        _qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        self.writer(Some(owner), spec)
    }

    fn create_node_reader(
        &self,
        owner: EndpointOwner,
        spec: &RawEndpointSpec,
        _qos: &DdsQos,
        _responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        self.reader(Some(owner), spec)
    }

    /// Nothing: on Zenoh, nodes and their endpoints are announced by liveliness tokens.
    fn publish_discovery_info(&self, _message: &ParticipantEntitiesInfo) {}

    /// At once: there is no `ros_discovery_info` to acknowledge.
    fn wait_for_discovery_info_acks(&self, _limit: Duration) -> bool {
        true
    }

    /// Closes the session: every peer sees its tokens' DELETEs.
    fn delete(&self) {
        if !self.deleted.swap(true, Ordering::SeqCst) {
            lock(&self.nodes).clear();
            lock(&self.services).clear();
            if let Err(e) = off_current_thread_runtime(|| self.session.close().wait()) {
                tracing::debug!("zenoh: closing the session: {e}");
            }
        }
    }

    fn open_feed(&self, local: LocalEvents) -> Result<Box<dyn FeedBackend>, DiscoveryFeedError> {
        Ok(Box::new(self.graph.open_feed(local)))
    }

    fn create_wait_set(&self) -> Result<Box<dyn WaitSetBackend>, WaitSetError> {
        Ok(Box::new(WaitSet {
            shared: Arc::default(),
        }))
    }
}

impl Drop for ZenohParticipant {
    fn drop(&mut self) {
        self.delete();
    }
}
