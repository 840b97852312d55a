//! The rustdds backend of horus-ros (for `rmw_fastrtps_cpp` peers): everything that touches
//! rustdds lives in this crate, which depends only on the backend contract
//! (`horus-ros-rmw-contract`) and the shared DDS layer (`horus-ros-dds-common`). The Cyclone
//! backend (`horus-ros-rmw-cyclone`) is its mirror image, file for file: `lib.rs` (the
//! contract's implementation), `participant.rs`, `discovery_info.rs`, `endpoints.rs`, `feed.rs`,
//! `wait_set.rs`, `qos.rs`; `raw.rs` (how rustdds carries raw CDR bodies) is what Cyclone's blob
//! sertype does there.

pub(crate) mod discovery_info;
pub(crate) mod endpoints;
pub(crate) mod feed;

#[doc(hidden)]
pub use feed::user_data_octets;
pub(crate) mod participant;
pub(crate) mod qos;
pub(crate) mod raw;
pub(crate) mod wait_set;

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use horus_ros_msgs::rmw_dds_common::{Gid, ParticipantEntitiesInfo};
use rustdds::GUID;

use horus_ros_dds_common as dds;
use horus_ros_rmw_contract as contract;
use horus_ros_rmw_contract::{dds_error, discovery, env};

use crate::contract::DiscoveryFeedError;
use crate::contract::RawEndpointSpec;
use crate::contract::WaitSetError;
use crate::contract::{
    Capabilities, FeedBackend, Implementation, LocalEvents, ParticipantBackend, ParticipantConfig,
    ReaderBackend, WaitSetBackend, WriterBackend,
};
use crate::dds_error::{boxed, DdsError};
use crate::discovery::VendorId;
use feed::{DdsDiscoveryFeed, InfoReaderFactory};
use horus_ros_rmw_contract::qos::DdsQos;
pub(crate) use participant::RustddsParticipant;

/// The backend's name (`HORUS_ROS_BACKEND=rustdds`).
pub const NAME: &str = "rustdds";

/// The rmw implementation it stands in for: Jazzy's default, `rmw_fastrtps_cpp` (Jazzy's
/// rmw_fastrtps_cpp and rmw_fastrtps_dynamic_cpp put the same bytes on the wire).
pub const RMW_IMPLEMENTATION: &str = "rmw_fastrtps_cpp";

/// The environment variables its own configuration reads, beyond ROS's (none: rustdds reads no configuration of its own): what
/// else, with the domain and the discovery options, decides which graph a context sees.
pub const CONFIGURATION_ENV: &[&str] = &[];

/// The RTPS vendor id of its participants.
pub const VENDOR_ID: VendorId = VendorId::RUSTDDS;

/// What it can do: samples carry `related_sample_identity` both ways (so it calls and serves
/// peers of both service conventions); it cannot send USER_DATA (no type hashes or enclaves for
/// peers) and rustdds 0.15 does not expose other participants' USER_DATA.
pub const CAPABILITIES: Capabilities = Capabilities::NONE.with_sample_identity();

/// The rustdds backend (for `rmw_fastrtps_cpp`): pure Rust.
#[derive(Debug, Clone, Copy, Default)]
pub struct RustDds;

impl Implementation for RustDds {
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
        let (participant, warnings) = RustddsParticipant::create(config)?;
        for w in warnings {
            tracing::warn!("{w}");
        }
        if config.enclave != "/" {
            tracing::debug!(
                "enclave {}: the rustdds backend cannot announce it (no USER_DATA)",
                config.enclave
            );
        }
        Ok(Box::new(participant))
    }
}

/// The GID of a DDS entity: its 16-byte GUID (12-byte prefix + 4-byte entity id), as rmw_dds_common
/// `convert_gid_to_message` / rmw_cyclonedds `convert_guid_to_gid` fill Jazzy's 16-byte GID.
pub(crate) fn gid_from_guid(guid: GUID) -> Gid {
    Gid::from_bytes(guid.to_bytes())
}

/// The DDS GUID a GID stands for.
pub(crate) fn guid_from_gid(gid: Gid) -> rustdds::GUID {
    rustdds::GUID::from_bytes(*gid.as_bytes())
}

impl ParticipantBackend for RustddsParticipant {
    fn gid(&self) -> Gid {
        gid_from_guid(self.guid)
    }

    fn create_writer(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
    ) -> Result<(Box<dyn WriterBackend>, Gid), DdsError> {
        let (writer, gid) = endpoints::RawWriter::create(self, spec, qos)?;
        Ok((Box::new(writer), gid))
    }

    /// Readers get every response: rustdds' servers address the reader a request names.
    fn create_reader(
        &self,
        spec: &RawEndpointSpec,
        qos: &DdsQos,
        _responses_of: Option<u64>,
    ) -> Result<(Box<dyn ReaderBackend>, Gid), DdsError> {
        let (reader, gid) = endpoints::RawReader::create(self, spec, qos)?;
        Ok((Box::new(reader), gid))
    }

    fn publish_discovery_info(&self, message: &ParticipantEntitiesInfo) {
        self.discovery_writer.publish(message.clone());
    }

    fn wait_for_discovery_info_acks(&self, limit: Duration) -> bool {
        self.discovery_writer.wait_for_acknowledgments(limit)
    }

    /// Deletes the participant now: as its last strong references (ours and the status
    /// listener's) go, rustdds' discovery sends the dispose of its endpoints and of the
    /// participant itself (`Discovery::on_participant_shutting_down`), and its threads end.
    fn delete(&self) {
        let listener = lock(&self.status_listener).take();
        let participant = lock(&self.participant).take();
        drop(listener);
        drop(participant);
    }

    /// Status events (queued by rustdds since the participant was created), a
    /// `ros_discovery_info` reader and a snapshot of the endpoints already known.
    fn open_feed(&self, local: LocalEvents) -> Result<Box<dyn FeedBackend>, DiscoveryFeedError> {
        let reader_error = |e| DiscoveryFeedError::Reader {
            cause: DdsError::Create(boxed(e)),
        };
        let participant = self
            .participant()
            .map_err(|source| DiscoveryFeedError::Reader { cause: source })?;
        let topic = discovery_info::topic(&participant).map_err(reader_error)?;
        let reader = self
            .subscriber
            .create_datareader_no_key(&topic, Some(discovery_info::reader_qos()))
            .map_err(reader_error)?;
        let own_gid = self.gid();
        let snapshot = feed::endpoint_snapshot(&participant, own_gid);
        let factory = InfoReaderFactory {
            subscriber: self.subscriber.clone(),
            topic,
        };
        let feed = DdsDiscoveryFeed::new(
            Arc::clone(&self.status_poll),
            reader,
            factory,
            own_gid,
            snapshot,
            local,
        )
        .map_err(|e| DiscoveryFeedError::Poll {
            cause: DdsError::Io(e),
        })?;
        Ok(Box::new(feed))
    }

    fn create_wait_set(&self) -> Result<Box<dyn WaitSetBackend>, WaitSetError> {
        let set = wait_set::WaitSet::new().map_err(|e| WaitSetError::Dds(DdsError::Io(e)))?;
        Ok(Box::new(set))
    }
}

/// Locks a mutex whose data stays consistent even if a holder panicked.
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}
