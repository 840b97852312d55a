//! A context's Cyclone DDS participant: its domain, configured as rmw_cyclonedds configures it,
//! and its `ros_discovery_info` writer.

use std::sync::Arc;

use crate as cyc;
use horus_ros_msgs::rmw_dds_common::Gid;

use super::discovery_info::discovery_info_user_data;
use super::{cyclone_error, gid, qos, LocalEndpoints};
use horus_ros_dds_common::discovery_info::{TOPIC_NAME, TYPE_NAME};
use horus_ros_rmw_contract::dds_error::DdsError;
use horus_ros_rmw_contract::env::{DiscoveryOptions, DiscoveryRange};
use horus_ros_rmw_contract::ParticipantConfig;

/// A context's Cyclone participant and its `ros_discovery_info` writer.
pub(crate) struct CycloneParticipant {
    pub(super) info_writer: cyc::Writer,
    pub(super) info_topic: cyc::Topic,
    pub(crate) participant: cyc::Participant,
    pub(crate) local_endpoints: Arc<LocalEndpoints>,
    pub(super) gid: Gid,
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
    pub(super) fn create(config: &ParticipantConfig<'_>) -> Result<Self, DdsError> {
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
