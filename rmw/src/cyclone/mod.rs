//! The Cyclone DDS backend (cargo feature `cyclone`), on the safe binding layer of
//! `horus-ros-rmw-cyclone` (where all `unsafe` code lives).
//!
//! As rmw_cyclonedds_cpp (jazzy `rmw_node.cpp`) sets a context up:
//! - the domain is configured from `ROS_AUTOMATIC_DISCOVERY_RANGE` / `ROS_STATIC_PEERS`, followed
//!   by `CYCLONEDDS_URI` (`check_create_domain`);
//! - the participant announces `enclave=<enclave>;` in USER_DATA (`rmw_context_impl_s::init`);
//! - endpoints announce `typehash=RIHS01_…;` (services: `clientid=`/`serviceid=` first) in
//!   USER_DATA (`create_readwrite_qos`, `rmw_init_cs`);
//! - `ros_discovery_info` is published RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1;
//! - samples are raw CDR (the "blob" sertype), GIDs the 16-byte GUIDs.

pub(crate) mod endpoints;
pub(crate) mod feed;
pub(crate) mod qos;

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use horus_ros_msgs::rmw_dds_common::{Gid, ParticipantEntitiesInfo};
use horus_ros_rmw_cyclone as cyc;

use crate::context::env::{DiscoveryOptions, DiscoveryRange, DomainId};
use crate::context::DiscoveryFeedError;
use crate::dds::discovery_info::{TOPIC_NAME, TYPE_NAME};
use crate::dds_error::DdsError;
use crate::local_sink::LocalSink;
use crate::qos::EndpointKind;

/// A Cyclone GUID as a GID (the same 16 bytes).
pub(crate) fn gid(guid: cyc::Guid) -> Gid {
    Gid::from_bytes(guid.0)
}

/// Our live endpoints, by GID, for the discovery feed to watch their matches. Entries do not
/// keep the endpoints alive; each endpoint removes its own entry when dropped.
#[derive(Default)]
pub(crate) struct LocalEndpoints(Mutex<HashMap<Gid, (cyc::WeakEntity, EndpointKind)>>);

impl LocalEndpoints {
    fn lock(&self) -> MutexGuard<'_, HashMap<Gid, (cyc::WeakEntity, EndpointKind)>> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub(crate) fn insert(&self, gid: Gid, entity: &cyc::Entity, kind: EndpointKind) {
        self.lock().insert(gid, (entity.downgrade(), kind));
    }

    pub(crate) fn remove(&self, gid: Gid) {
        self.lock().remove(&gid);
    }

    pub(crate) fn get(&self, gid: Gid) -> Option<(cyc::Entity, EndpointKind)> {
        let (weak, kind) = self.lock().get(&gid).cloned()?;
        Some((weak.upgrade()?, kind))
    }
}

/// The USER_DATA of the `ros_discovery_info` reader and writer: rmw_cyclonedds creates them as
/// ordinary endpoints (`create_publisher` / `create_subscription`), so they carry the type hash.
pub(crate) fn discovery_info_user_data() -> String {
    use horus_ros_msgs::Message;
    ParticipantEntitiesInfo::type_hash().to_user_data()
}

/// A context's Cyclone participant and its `ros_discovery_info` writer.
pub(crate) struct CycloneParticipant {
    info_writer: cyc::Writer,
    info_topic: cyc::Topic,
    pub(crate) participant: cyc::Participant,
    pub(crate) local_endpoints: Arc<LocalEndpoints>,
    gid: Gid,
}

/// Cyclone DDS sends no key hash with its samples unless told to (`Internal/GenerateKeyhash`,
/// default false); Fast DDS (rmw_fastrtps) ignores a dispose without one, so without it the
/// disposes of our participant and endpoints never take them off Fast DDS peers' graphs: they
/// stayed there until their lease ended, even after a clean exit. The key hash is an ordinary
/// inline QoS every implementation accepts. First, so that `CYCLONEDDS_URI` can still override it.
const KEY_HASH_CONFIG: &str =
    "<CycloneDDS><Domain><Internal><GenerateKeyhash>true</GenerateKeyhash></Internal></Domain></CycloneDDS>,";

/// Key hashes on ([`KEY_HASH_CONFIG`]), then the configuration rmw_cyclonedds builds for these
/// discovery options, then `CYCLONEDDS_URI`.
pub(crate) fn domain_config(discovery: &DiscoveryOptions) -> String {
    let range = match discovery.range {
        DiscoveryRange::Off => cyc::config::DiscoveryRange::Off,
        DiscoveryRange::Localhost => cyc::config::DiscoveryRange::Localhost,
        DiscoveryRange::Subnet => cyc::config::DiscoveryRange::Subnet,
        DiscoveryRange::SystemDefault => cyc::config::DiscoveryRange::SystemDefault,
    };
    let rmw_config = cyc::config::domain_config_from_env(range, &discovery.static_peers);
    format!("{KEY_HASH_CONFIG}{rmw_config}")
}

impl CycloneParticipant {
    /// Creates (or joins) the configured domain, the participant with `enclave=…;` and the
    /// `ros_discovery_info` writer.
    pub(crate) fn create(
        domain: DomainId,
        discovery: &DiscoveryOptions,
        enclave: &str,
    ) -> Result<Self, DdsError> {
        let fail = DdsError::Cyclone;
        let dom = cyc::Domain::acquire(u32::from(domain.get()), &domain_config(discovery))
            .map_err(fail)?;
        let user_data = format!("enclave={enclave};");
        let participant = cyc::Participant::new(dom, user_data.as_bytes()).map_err(fail)?;
        let info_topic = participant
            .blob_topic(TOPIC_NAME, TYPE_NAME)
            .map_err(fail)?;
        let info_writer = participant
            .writer(
                &info_topic,
                &qos::discovery_info(1),
                discovery_info_user_data().as_bytes(),
            )
            .map_err(fail)?;
        let gid = gid(participant.guid().map_err(fail)?);
        Ok(Self {
            info_writer,
            info_topic,
            participant,
            local_endpoints: Arc::default(),
            gid,
        })
    }

    /// The participant's GID.
    pub(crate) fn gid(&self) -> Gid {
        self.gid
    }

    /// Waits at most `limit` for the `ros_discovery_info` readers' acknowledgments.
    pub(crate) fn wait_for_discovery_info_acks(&self, limit: std::time::Duration) -> bool {
        self.info_writer.wait_for_acks(limit).unwrap_or(false)
    }

    /// Deletes the participant now, and its domain, which waits until Cyclone has sent the
    /// participant's dispose (the entities on them go stale).
    pub(crate) fn delete(&self) {
        if let Err(e) = self.participant.delete_with_domain() {
            tracing::warn!("could not delete the participant: {e}");
        }
    }

    /// Publishes the participant's `ros_discovery_info` message; a failure is logged, since
    /// discovery catches up with the next change.
    pub(crate) fn publish_discovery_info(&self, message: &ParticipantEntitiesInfo) {
        let result = horus_ros_msgs::cdr::to_cdr(message)
            .map_err(|e| e.to_string())
            .and_then(|cdr| self.info_writer.write(&cdr).map_err(|e| e.to_string()));
        if let Err(e) = result {
            tracing::warn!("could not publish on {TOPIC_NAME}: {e}");
        }
    }

    /// Opens a discovery feed on the built-in topics and `ros_discovery_info`.
    pub(crate) fn open_feed(
        &self,
    ) -> Result<(feed::CycloneDiscoveryFeed, LocalSink), DiscoveryFeedError> {
        feed::CycloneDiscoveryFeed::new(self, &self.info_topic)
    }
}
