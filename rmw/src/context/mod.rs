//! The [`Context`]: one DDS participant in one domain, shared by every node created from it
//! (rmw_cyclonedds and rmw_fastrtps both create one participant per context since Foxy).

pub mod env;

use std::sync::{Arc, Mutex, MutexGuard};

use rustdds::{DomainParticipant, QosPolicyBuilder, RTPSEntity};

use crate::dds::{self, discovery_info::DiscoveryInfoWriter};
use crate::discovery::DiscoveryEvent;
use crate::entities::LocalEntities;
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
    entities: Mutex<LocalEntities>,
    feed_open: std::sync::atomic::AtomicBool,
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
        let entities = Mutex::new(LocalEntities::new(gid));
        tracing::debug!(%domain, participant = %gid, "created DDS participant");
        Ok(Self {
            inner: Arc::new(ContextInner {
                domain,
                discovery,
                participant,
                publisher,
                subscriber,
                gid,
                entities,
                discovery_writer,
                feed_open: std::sync::atomic::AtomicBool::new(false),
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
        self.inner.entities().message()
    }

    pub(crate) fn inner(&self) -> &Arc<ContextInner> {
        &self.inner
    }
}

impl ContextInner {
    /// Locks the local node bookkeeping (a poisoned lock still holds consistent data: every
    /// mutation is a single push/retain).
    pub(crate) fn entities(&self) -> MutexGuard<'_, LocalEntities> {
        self.entities.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Adds a node to the bookkeeping and announces it.
    pub(crate) fn add_node(&self, namespace: &str, name: &str) -> crate::entities::NodeKey {
        let mut entities = self.entities();
        let (key, message) = entities.add_node(namespace, name);
        self.discovery_writer.publish(message);
        key
    }

    /// Applies a bookkeeping change and, if it changed anything, republishes the whole participant.
    pub(crate) fn update_entities(
        &self,
        change: impl FnOnce(&mut LocalEntities) -> Option<ParticipantEntitiesInfo>,
    ) {
        let mut entities = self.entities();
        if let Some(message) = change(&mut entities) {
            // Published under the lock so that messages leave in the order of the changes.
            self.discovery_writer.publish(message);
        }
    }
}

/// Why a [`DiscoveryFeed`] could not be opened.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DiscoveryFeedError {
    /// The context already has a feed: rustdds keeps one discovery event queue per participant.
    #[error("this context already has a discovery feed")]
    AlreadyOpen,
    /// The `ros_discovery_info` reader could not be created.
    #[error("could not create the ros_discovery_info reader: {reason}")]
    Reader {
        /// What the DDS layer said.
        reason: String,
    },
}

/// Every [`DiscoveryEvent`] of a context's participant: SPDP participants, SEDP (and local)
/// readers and writers, and other participants' `ros_discovery_info` messages.
pub struct DiscoveryFeed {
    feed: crate::dds::discovery_feed::DdsDiscoveryFeed,
    _context: Context,
}

impl std::fmt::Debug for DiscoveryFeed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiscoveryFeed")
            .field("participant", &self._context.gid())
            .finish()
    }
}

impl DiscoveryFeed {
    /// The next event, if one is waiting (non-blocking).
    pub fn try_next(&mut self) -> Option<DiscoveryEvent> {
        self.feed.try_next()
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
        Ok(DiscoveryFeed {
            feed: crate::dds::discovery_feed::DdsDiscoveryFeed {
                listener: self.inner.participant.status_listener(),
                reader,
                own_gid: self.inner.gid,
                pending: Default::default(),
            },
            _context: self.clone(),
        })
    }
}
