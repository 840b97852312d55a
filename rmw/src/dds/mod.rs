//! The rustdds backend: everything that touches rustdds lives below this module, so the rest of
//! horus-ros sees only our own types (the Cyclone backend sits beside it, in `cyclone/`).

pub(crate) mod discovery_feed;
pub(crate) mod discovery_info;
pub(crate) mod endpoints;
pub(crate) mod participant;
pub(crate) mod qos;
pub(crate) mod raw;
pub(crate) mod waiter;

use std::sync::{Arc, Mutex, MutexGuard};

use horus_ros_msgs::rmw_dds_common::{Gid, ParticipantEntitiesInfo};
use rustdds::{DomainParticipant, QosPolicyBuilder, RTPSEntity, GUID};

use crate::context::env::{DiscoveryOptions, DomainId};
use crate::context::DiscoveryFeedError;
use crate::dds_error::DdsError;
use crate::local_sink::LocalSink;
use discovery_feed::{DdsDiscoveryFeed, InfoReaderFactory, SharedListener, StatusPoll};
use discovery_info::DiscoveryInfoWriter;

/// The GID of a DDS entity: its 16-byte GUID (12-byte prefix + 4-byte entity id), as rmw_dds_common
/// `convert_gid_to_message` / rmw_cyclonedds `convert_guid_to_gid` fill Jazzy's 16-byte GID.
pub(crate) fn gid_from_guid(guid: GUID) -> Gid {
    Gid::from_bytes(guid.to_bytes())
}

/// The DDS GUID a GID stands for.
pub(crate) fn guid_from_gid(gid: Gid) -> rustdds::GUID {
    rustdds::GUID::from_bytes(*gid.as_bytes())
}

/// A context's rustdds participant and what hangs off it.
///
/// Fields drop in declaration order: endpoints and the publisher/subscriber go before the
/// participant they belong to (rustdds logs errors when the participant goes first).
pub(crate) struct RustddsParticipant {
    discovery_writer: DiscoveryInfoWriter,
    pub(crate) publisher: rustdds::Publisher,
    pub(crate) subscriber: rustdds::Subscriber,
    /// The participant; `None` once [deleted](Self::delete). Its endpoints, publisher and
    /// subscriber only hold weak references to it: this and `status_listener` keep it alive.
    participant: Mutex<Option<DomainParticipant>>,
    /// Its status-event listener (a strong reference), shared with the discovery feeds.
    status_listener: SharedListener,
    guid: GUID,
    /// The status listener, registered once, kept between feeds.
    status_poll: Mutex<Option<StatusPoll>>,
}

impl RustddsParticipant {
    /// Creates the participant, its publisher/subscriber and the `ros_discovery_info` writer;
    /// also returns the warnings for discovery settings rustdds cannot honour.
    pub(crate) fn create(
        domain: DomainId,
        discovery: &DiscoveryOptions,
    ) -> Result<(Self, Vec<String>), DdsError> {
        let fail = DdsError::RustDdsCreate;
        let (participant, warnings) =
            participant::create_participant(domain, discovery).map_err(fail)?;
        let qos = QosPolicyBuilder::new().build();
        let publisher = participant.create_publisher(&qos).map_err(fail)?;
        let subscriber = participant.create_subscriber(&qos).map_err(fail)?;
        let topic = discovery_info::topic(&participant).map_err(fail)?;
        let discovery_writer = DiscoveryInfoWriter::new(&publisher, &topic).map_err(fail)?;
        Ok((
            Self {
                discovery_writer,
                publisher,
                subscriber,
                guid: participant.guid(),
                status_listener: Arc::new(Mutex::new(Some(participant.status_listener()))),
                participant: Mutex::new(Some(participant)),
                status_poll: Mutex::new(None),
            },
            warnings,
        ))
    }

    /// The participant's GID.
    pub(crate) fn gid(&self) -> Gid {
        gid_from_guid(self.guid)
    }

    /// The participant, unless it was deleted.
    pub(crate) fn participant(&self) -> Result<DomainParticipant, DdsError> {
        lock(&self.participant)
            .clone()
            .ok_or(DdsError::ParticipantDeleted)
    }

    /// Waits at most `limit` for the `ros_discovery_info` readers' acknowledgments.
    pub(crate) fn wait_for_discovery_info_acks(&self, limit: std::time::Duration) -> bool {
        self.discovery_writer.wait_for_acknowledgments(limit)
    }

    /// Deletes the participant now: as its last strong references (ours and the status
    /// listener's) go, rustdds' discovery sends the dispose of its endpoints and of the
    /// participant itself (`Discovery::on_participant_shutting_down`), and its threads end.
    pub(crate) fn delete(&self) {
        let listener = lock(&self.status_listener).take();
        let participant = lock(&self.participant).take();
        drop(listener);
        drop(participant);
    }

    /// Publishes the participant's `ros_discovery_info` message.
    pub(crate) fn publish_discovery_info(&self, message: ParticipantEntitiesInfo) {
        self.discovery_writer.publish(message);
    }

    /// Opens the discovery feed: status events (queued by rustdds since the participant was
    /// created), a `ros_discovery_info` reader and a snapshot of the endpoints already known.
    pub(crate) fn open_feed(
        &self,
        own_gid: Gid,
    ) -> Result<(DdsDiscoveryFeed, LocalSink), DiscoveryFeedError> {
        let reader_error = |e| DiscoveryFeedError::Reader {
            cause: DdsError::RustDdsCreate(e),
        };
        let participant = self
            .participant()
            .map_err(|source| DiscoveryFeedError::Reader { cause: source })?;
        let topic = discovery_info::topic(&participant).map_err(reader_error)?;
        let reader = self
            .subscriber
            .create_datareader_no_key(&topic, Some(discovery_info::reader_qos()))
            .map_err(reader_error)?;
        let status = match lock(&self.status_poll).take() {
            Some(status) => status,
            None => StatusPoll::new(Arc::clone(&self.status_listener)).map_err(|e| {
                DiscoveryFeedError::Poll {
                    cause: DdsError::Io(e),
                }
            })?,
        };
        let snapshot = discovery_feed::endpoint_snapshot(&participant, own_gid);
        let factory = InfoReaderFactory {
            subscriber: self.subscriber.clone(),
            topic,
        };
        DdsDiscoveryFeed::new(status, reader, factory, own_gid, snapshot).map_err(|(status, e)| {
            *lock(&self.status_poll) = Some(status);
            DiscoveryFeedError::Poll {
                cause: DdsError::Io(e),
            }
        })
    }

    /// Closes a feed, keeping its registered status listener for the next one.
    pub(crate) fn close_feed(&self, feed: DdsDiscoveryFeed) {
        *lock(&self.status_poll) = Some(feed.close());
    }
}

/// Locks a mutex whose data stays consistent even if a holder panicked.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}
