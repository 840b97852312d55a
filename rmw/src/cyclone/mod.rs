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
//!
//! It implements the [backend contract](crate::contract) file for file as `rustdds/` does:
//! `mod.rs` (the implementation and its participant), `endpoints.rs`, `feed.rs`, `wait_set.rs`,
//! `qos.rs`.

pub(crate) mod endpoints;
pub(crate) mod feed;
pub(crate) mod qos;
pub(crate) mod wait_set;

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use horus_ros_msgs::rmw_dds_common::{Gid, ParticipantEntitiesInfo};
use horus_ros_rmw_cyclone as cyc;

use crate::backend::Backend;
use crate::context::env::{DiscoveryOptions, DiscoveryRange};
use crate::context::DiscoveryFeedError;
use crate::contract::{
    Capabilities, FeedBackend, Implementation, LocalEvents, ParticipantBackend, ParticipantConfig,
    ReaderBackend, WaitSetBackend, WriterBackend,
};
use crate::dds_error::{boxed, DdsError};
use crate::discovery::VendorId;
use crate::qos::{DdsQos, EndpointKind};
use crate::raw::RawEndpointSpec;
use crate::rustdds::discovery_info::{TOPIC_NAME, TYPE_NAME};
use crate::wait_set::WaitSetError;

/// The Cyclone DDS backend (for `rmw_cyclonedds_cpp`).
#[derive(Debug)]
pub(crate) struct Cyclone;

impl Implementation for Cyclone {
    fn name(&self) -> &'static str {
        Backend::Cyclone.name()
    }

    fn rmw_implementation(&self) -> &'static str {
        Backend::Cyclone.rmw_implementation()
    }

    fn vendor_id(&self) -> VendorId {
        VendorId::CYCLONE_DDS
    }

    fn capabilities(&self) -> Capabilities {
        Backend::Cyclone.capabilities()
    }

    fn create_participant(
        &self,
        config: &ParticipantConfig<'_>,
    ) -> Result<Box<dyn ParticipantBackend>, DdsError> {
        Ok(Box::new(CycloneParticipant::create(config)?))
    }
}

/// A Cyclone DDS error as [`DdsError`] keeps it.
pub(crate) fn cyclone_error(e: cyc::Error) -> DdsError {
    DdsError::Backend(boxed(e))
}

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
    fn create(config: &ParticipantConfig<'_>) -> Result<Self, DdsError> {
        let fail = cyclone_error;
        let domain = u32::from(config.domain.get());
        let dom = cyc::Domain::acquire(domain, &domain_config(config.discovery)).map_err(fail)?;
        let user_data = format!("enclave={};", config.enclave);
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
}

impl ParticipantBackend for CycloneParticipant {
    fn gid(&self) -> Gid {
        self.gid
    }

    fn create_writer(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        let (writer, gid) = endpoints::RawWriter::create(self, spec, qos)?;
        Ok((Box::new(writer), gid))
    }

    fn create_reader(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
        responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        let (reader, gid) = endpoints::RawReader::create(self, spec, qos, responses_of)?;
        Ok((Box::new(reader), gid))
    }

    /// A failure is logged, since discovery catches up with the next change.
    fn publish_discovery_info(&self, message: &ParticipantEntitiesInfo) {
        let result = horus_ros_msgs::cdr::to_cdr(message)
            .map_err(|e| e.to_string())
            .and_then(|cdr| self.info_writer.write(&cdr).map_err(|e| e.to_string()));
        if let Err(e) = result {
            tracing::warn!("could not publish on {TOPIC_NAME}: {e}");
        }
    }

    fn wait_for_discovery_info_acks(&self, limit: std::time::Duration) -> bool {
        self.info_writer.wait_for_acks(limit).unwrap_or(false)
    }

    /// Deletes the participant now, and its domain, which waits until Cyclone has sent the
    /// participant's dispose (the entities on them go stale).
    fn delete(&self) {
        if let Err(e) = self.participant.delete_with_domain() {
            tracing::warn!("could not delete the participant: {e}");
        }
    }

    /// The built-in topics and `ros_discovery_info`.
    fn open_feed(&self, local: LocalEvents) -> Result<Box<dyn FeedBackend>, DiscoveryFeedError> {
        let feed = feed::CycloneDiscoveryFeed::new(self, &self.info_topic, local)?;
        Ok(Box::new(feed))
    }

    fn create_wait_set(&self) -> Result<Box<dyn WaitSetBackend>, WaitSetError> {
        Ok(Box::new(wait_set::WaitSet::new()))
    }
}
