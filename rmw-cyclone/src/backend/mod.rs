//! The Cyclone DDS backend (`horus-ros-rmw`'s cargo feature `cyclone`), on this crate's safe
//! binding layer (where all `unsafe` code lives, in `sys`).
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
//! It implements the backend contract (`horus-ros-rmw-contract`) file for file as
//! `horus-ros-rmw-rustdds` does: `mod.rs` (the contract's implementation), `participant.rs`,
//! `discovery_info.rs`, `endpoints.rs`, `feed.rs`, `wait_set.rs`, `qos.rs`.

pub(crate) mod discovery_info;
pub(crate) mod endpoints;
pub(crate) mod feed;
pub(crate) mod participant;
pub(crate) mod qos;
pub(crate) mod wait_set;

use std::collections::HashMap;
use std::sync::{Mutex, MutexGuard};

use horus_ros_msgs::rmw_dds_common::{Gid, ParticipantEntitiesInfo};

use crate as cyc;
use horus_ros_dds_common::discovery_info::TOPIC_NAME;
use horus_ros_rmw_contract::dds_error::{boxed, DdsError};
use horus_ros_rmw_contract::discovery::VendorId;
use horus_ros_rmw_contract::qos::{DdsQos, EndpointKind};
use horus_ros_rmw_contract::DiscoveryFeedError;
use horus_ros_rmw_contract::RawEndpointSpec;
use horus_ros_rmw_contract::WaitSetError;
use horus_ros_rmw_contract::{
    Capabilities, FeedBackend, Implementation, LocalEvents, ParticipantBackend, ParticipantConfig,
    ReaderBackend, WaitSetBackend, WriterBackend,
};
pub(crate) use participant::CycloneParticipant;

/// The backend's name (`HORUS_ROS_BACKEND=cyclone`).
pub const NAME: &str = "cyclone";

/// The rmw implementation it stands in for.
pub const RMW_IMPLEMENTATION: &str = "rmw_cyclonedds_cpp";

/// The environment variables its own configuration reads, beyond ROS's (Cyclone DDS's own configuration, applied after the domain configuration made from ROS's variables): what
/// else, with the domain and the discovery options, decides which graph a context sees.
pub const CONFIGURATION_ENV: &[&str] = &["CYCLONEDDS_URI"];

/// The RTPS vendor id of its participants.
pub const VENDOR_ID: VendorId = VendorId::CYCLONE_DDS;

/// What it can do: USER_DATA both ways (`enclave=`, `typehash=`, `clientid=`/`serviceid=`), as
/// rmw_cyclonedds; no `related_sample_identity` (Cyclone DDS's C API has none), so it speaks only
/// the rmw_cyclonedds service convention.
pub const CAPABILITIES: Capabilities = Capabilities::NONE
    .with_user_data_announced()
    .with_participant_user_data_read()
    .with_type_hashes_announced();

/// The Cyclone DDS backend (for `rmw_cyclonedds_cpp`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Cyclone;

impl Implementation for Cyclone {
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
