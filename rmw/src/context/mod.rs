//! The [`Context`]: one DDS participant in one domain, shared by every node created from it
//! (rmw_cyclonedds and rmw_fastrtps both create one participant per context since Foxy).

pub mod env;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use rustdds::{DomainParticipant, QosPolicyBuilder, RTPSEntity};

use crate::dds::{self, discovery_info::DiscoveryInfoWriter};
use crate::discovery::{DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId};
use crate::entities::{EndpointSide, LocalEntities, NodeKey};
use crate::Gid;
use env::{DiscoveryOptions, DomainId, DomainIdError};
use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;

/// Why a [`Context`] could not be created.
#[derive(Debug, thiserror::Error)]
pub enum ContextError {
    /// `ROS_DOMAIN_ID` (or the domain given) is not valid.
    #[error(transparent)]
    DomainId(#[from] DomainIdError),
    /// The DDS participant could not be created (e.g. no free ports).
    #[error("could not create the DDS participant in domain {domain}: {reason}")]
    Participant {
        /// The domain asked for.
        domain: DomainId,
        /// What the DDS layer said.
        reason: String,
    },
}

/// Builds a [`Context`]; values not set come from the environment as rcl reads it.
#[derive(Debug, Default, Clone)]
#[must_use = "a builder does nothing until .build() is called"]
pub struct ContextBuilder {
    domain_id: Option<u32>,
    discovery: Option<DiscoveryOptions>,
}

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

    /// Creates the participant. Warnings (deprecated or unsupported settings) go to `tracing`.
    pub fn build(self) -> Result<Context, ContextError> {
        let environment = env::read_environment(|k| std::env::var(k).ok())?;
        let domain = match self.domain_id {
            Some(d) => DomainId::new(d)?,
            None => environment.domain_id,
        };
        let discovery = self.discovery.unwrap_or(environment.discovery);
        for w in &environment.warnings {
            tracing::warn!("{w}");
        }
        Context::create(domain, discovery)
    }
}

/// A connection to one ROS 2 domain: a DDS participant and the nodes living on it.
///
/// Cloning is cheap; the participant goes away with the last clone and the last node.
#[derive(Clone)]
pub struct Context {
    inner: Arc<ContextInner>,
}

/// Fields drop in declaration order: endpoints and the publisher/subscriber go before the
/// participant they belong to (rustdds logs errors when the participant goes first).
pub(crate) struct ContextInner {
    discovery_writer: DiscoveryInfoWriter,
    pub(crate) publisher: rustdds::Publisher,
    pub(crate) subscriber: rustdds::Subscriber,
    pub(crate) participant: DomainParticipant,
    pub(crate) domain: DomainId,
    pub(crate) discovery: DiscoveryOptions,
    pub(crate) gid: Gid,
    local: Mutex<LocalState>,
    feed_open: AtomicBool,
    /// The status listener, registered once, kept between feeds.
    status_poll: Mutex<Option<dds::discovery_feed::StatusPoll>>,
}

/// What this participant itself holds: its nodes, its endpoints, and where to report changes to
/// them (the open [`DiscoveryFeed`], since DDS discovery reports only remote entities).
pub(crate) struct LocalState {
    entities: LocalEntities,
    endpoints: BTreeMap<Gid, DiscoveredEndpoint>,
    sink: Option<dds::discovery_feed::LocalSink>,
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

    /// A builder to override the environment.
    pub fn builder() -> ContextBuilder {
        ContextBuilder::default()
    }

    fn create(domain: DomainId, discovery: DiscoveryOptions) -> Result<Self, ContextError> {
        let fail = |e: rustdds::dds::CreateError| ContextError::Participant {
            domain,
            reason: e.to_string(),
        };
        let (participant, warnings) =
            dds::participant::create_participant(domain, &discovery).map_err(fail)?;
        for w in warnings {
            tracing::warn!("{w}");
        }
        let qos = QosPolicyBuilder::new().build();
        let publisher = participant.create_publisher(&qos).map_err(fail)?;
        let subscriber = participant.create_subscriber(&qos).map_err(fail)?;
        let topic = dds::discovery_info::topic(&participant).map_err(fail)?;
        let discovery_writer = DiscoveryInfoWriter::new(&publisher, &topic).map_err(fail)?;
        let gid = dds::gid_from_guid(participant.guid());
        let local = Mutex::new(LocalState {
            entities: LocalEntities::new(gid),
            endpoints: BTreeMap::new(),
            sink: None,
        });
        tracing::debug!(%domain, participant = %gid, "created DDS participant");
        Ok(Self {
            inner: Arc::new(ContextInner {
                domain,
                discovery,
                participant,
                publisher,
                subscriber,
                gid,
                local,
                discovery_writer,
                feed_open: AtomicBool::new(false),
                status_poll: Mutex::new(None),
            }),
        })
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
    /// Locks what this participant holds (a poisoned lock still holds consistent data: every
    /// mutation is a single push/retain/insert).
    fn local(&self) -> MutexGuard<'_, LocalState> {
        lock(&self.local)
    }

    /// Publishes the participant's new message and reports it to the feed. Called under the
    /// lock, so that messages leave in the order of the changes.
    fn announce(&self, local: &mut LocalState, message: ParticipantEntitiesInfo) {
        self.discovery_writer.publish(message.clone());
        local.report(DiscoveryEvent::ParticipantEntities(message));
    }

    /// Adds a node and announces it.
    pub(crate) fn add_node(&self, namespace: &str, name: &str) -> NodeKey {
        let mut local = self.local();
        let (key, message) = local.entities.add_node(namespace, name);
        self.announce(&mut local, message);
        key
    }

    /// Removes a node and announces it.
    pub(crate) fn remove_node(&self, key: NodeKey) {
        let mut local = self.local();
        if let Some(message) = local.entities.remove_node(key) {
            self.announce(&mut local, message);
        }
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

/// Why a [`DiscoveryFeed`] could not be opened.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DiscoveryFeedError {
    /// The context already has a feed: rustdds keeps one discovery event queue per participant.
    #[error("this context already has a discovery feed")]
    AlreadyOpen,
    /// The wake-up machinery (an OS poll instance) could not be set up.
    #[error("could not set up waiting for discovery events: {reason}")]
    Poll {
        /// What the OS said.
        reason: String,
    },
    /// The `ros_discovery_info` reader could not be created.
    #[error("could not create the ros_discovery_info reader: {reason}")]
    Reader {
        /// What the DDS layer said.
        reason: String,
    },
}

/// Every [`DiscoveryEvent`] of a context: remote participants (SPDP), readers and writers (SEDP),
/// other participants' `ros_discovery_info` messages, and the context's own participant, nodes
/// and endpoints (reported by the context itself, first as a snapshot when the feed opens).
/// Dropping the feed allows opening another.
pub struct DiscoveryFeed {
    /// Always `Some` until dropped.
    feed: Option<dds::discovery_feed::DdsDiscoveryFeed>,
    context: Context,
}

impl Drop for DiscoveryFeed {
    fn drop(&mut self) {
        let inner = &self.context.inner;
        inner.local().sink = None;
        if let Some(feed) = self.feed.take() {
            *lock(&inner.status_poll) = Some(feed.close());
        }
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
        self.feed.as_mut().and_then(|f| f.try_next())
    }

    /// The next event, waiting for it at most `timeout` (woken by the DDS layer, no polling).
    pub fn next_timeout(&mut self, timeout: std::time::Duration) -> Option<DiscoveryEvent> {
        self.feed.as_mut().and_then(|f| f.next_timeout(timeout))
    }
}

impl Context {
    /// Opens the context's discovery feed (one per context). Events that happened since the
    /// participant was created are delivered too: rustdds queues them from the start.
    pub fn discovery_feed(&self) -> Result<DiscoveryFeed, DiscoveryFeedError> {
        if self
            .inner
            .feed_open
            .swap(true, std::sync::atomic::Ordering::SeqCst)
        {
            return Err(DiscoveryFeedError::AlreadyOpen);
        }
        let fail = |e: rustdds::dds::CreateError| {
            self.inner
                .feed_open
                .store(false, std::sync::atomic::Ordering::SeqCst);
            DiscoveryFeedError::Reader {
                reason: e.to_string(),
            }
        };
        let topic = dds::discovery_info::topic(&self.inner.participant).map_err(fail)?;
        let reader = self
            .inner
            .subscriber
            .create_datareader_no_key(&topic, Some(dds::discovery_info::reader_qos()))
            .map_err(fail)?;
        let reopened = lock(&self.inner.status_poll).take();
        let status = match reopened {
            Some(status) => status,
            None => dds::discovery_feed::StatusPoll::new(self.inner.participant.status_listener())
                .map_err(|e| {
                    self.inner.feed_open.store(false, Ordering::SeqCst);
                    DiscoveryFeedError::Poll {
                        reason: e.to_string(),
                    }
                })?,
        };
        let snapshot =
            dds::discovery_feed::endpoint_snapshot(&self.inner.participant, self.inner.gid);
        let (feed, sink) =
            dds::discovery_feed::DdsDiscoveryFeed::new(status, reader, self.inner.gid, snapshot)
                .map_err(|(status, e)| {
                    *lock(&self.inner.status_poll) = Some(status);
                    self.inner.feed_open.store(false, Ordering::SeqCst);
                    DiscoveryFeedError::Poll {
                        reason: e.to_string(),
                    }
                })?;
        // The snapshot of what this participant holds, then every later change, in order.
        let mut local = self.inner.local();
        let _ = sink.send(DiscoveryEvent::ParticipantDiscovered(
            DiscoveredParticipant {
                gid: self.inner.gid,
                vendor_id: VendorId::RUSTDDS,
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
            feed: Some(feed),
            context: self.clone(),
        })
    }
}
