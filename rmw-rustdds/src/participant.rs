//! A context's rustdds participant: created from ROS discovery options, with its publisher,
//! subscriber, `ros_discovery_info` writer and status listener.

use std::net::{IpAddr, Ipv4Addr};
use std::sync::{Arc, Mutex};

use nix::sys::signal::{pthread_sigmask, SigSet, SigmaskHow, Signal};
use rustdds::{DomainParticipant, DomainParticipantBuilder, QosPolicyBuilder, RTPSEntity, GUID};

use super::discovery_info::{self, DiscoveryInfoWriter};
use super::feed::{SharedListener, StatusPoll};
use super::lock;
use crate::contract::ParticipantConfig;
use crate::dds_error::{boxed, DdsError};
use crate::env::{DiscoveryOptions, DiscoveryRange, DomainId};

/// Builds the participant for `domain` with discovery limited as `discovery` asks, as far as rustdds
/// can; returns the warnings for what it cannot honour (the caller logs them).
///
/// rmw_cyclonedds (`rmw_node.cpp`, `configure_qos_for_discovery`) and rmw_fastrtps map the range onto
/// their transports; rustdds offers only an interface filter and its same-host loopback SPDP:
/// - SUBNET / SYSTEM_DEFAULT: rustdds defaults (every multicast-capable interface).
/// - LOCALHOST: only 127.0.0.1 is used and advertised; same-host peers are found over loopback.
/// - OFF: no interface is used or advertised and no loopback SPDP is sent, so nothing discovers us.
/// - Static peers: rustdds has no initial-peers list, so `ROS_STATIC_PEERS` cannot be honoured.
pub(crate) fn create_participant(
    domain: DomainId,
    discovery: &DiscoveryOptions,
) -> Result<(DomainParticipant, Vec<String>), rustdds::dds::CreateError> {
    let mut warnings = Vec::new();
    let builder = DomainParticipantBuilder::new(domain.get());
    let builder = match discovery.range {
        DiscoveryRange::Subnet | DiscoveryRange::SystemDefault => builder,
        DiscoveryRange::Localhost => builder
            .with_only_networks([IpAddr::V4(Ipv4Addr::LOCALHOST)])
            .same_host_loopback(true),
        DiscoveryRange::Off => {
            warnings.push(
                "ROS_AUTOMATIC_DISCOVERY_RANGE=OFF: the rustdds backend announces itself nowhere, so \
                 other processes cannot discover this one"
                    .to_owned(),
            );
            builder
                .with_only_networks(Vec::<IpAddr>::new())
                .same_host_loopback(false)
        }
    };
    if !discovery.static_peers.is_empty() {
        warnings.push(format!(
            "ROS_STATIC_PEERS ({}) cannot be honoured by the rustdds backend (it has no initial-peers \
             list); only automatic discovery ({}) is used",
            discovery.static_peers.join(";"),
            discovery.range
        ));
    }
    // rustdds' event-loop and discovery threads end on an interrupted wait (EINTR), which takes
    // the participant off the graph for good: a signal such as SIGCHLD from a child that exits
    // while `Command::spawn` has signals blocked is handed to any thread that does not block it.
    // Threads inherit the creating thread's mask, so rustdds' threads are started with
    // asynchronous signals blocked; this thread gets its mask back right after.
    let participant = {
        let _mask = AsyncSignalsBlocked::new();
        builder.build()?
    };
    Ok((participant, warnings))
}

/// Blocks asynchronous signals in this thread until dropped (synchronous fault signals stay
/// deliverable: blocking them would hide crashes).
struct AsyncSignalsBlocked {
    previous: Option<SigSet>,
}

impl AsyncSignalsBlocked {
    fn new() -> Self {
        let mut set = SigSet::all();
        for fault in [
            Signal::SIGSEGV,
            Signal::SIGBUS,
            Signal::SIGILL,
            Signal::SIGFPE,
            Signal::SIGTRAP,
        ] {
            set.remove(fault);
        }
        let mut previous = SigSet::empty();
        match pthread_sigmask(SigmaskHow::SIG_BLOCK, Some(&set), Some(&mut previous)) {
            Ok(()) => Self {
                previous: Some(previous),
            },
            Err(e) => {
                tracing::warn!("could not block signals for the DDS threads: {e}");
                Self { previous: None }
            }
        }
    }
}

impl Drop for AsyncSignalsBlocked {
    fn drop(&mut self) {
        if let Some(previous) = &self.previous {
            if let Err(e) = pthread_sigmask(SigmaskHow::SIG_SETMASK, Some(previous), None) {
                tracing::warn!("could not restore this thread's signal mask: {e}");
            }
        }
    }
}

/// A context's rustdds participant and what hangs off it.
///
/// Fields drop in declaration order: endpoints and the publisher/subscriber go before the
/// participant they belong to (rustdds logs errors when the participant goes first).
pub(crate) struct RustddsParticipant {
    pub(super) discovery_writer: DiscoveryInfoWriter,
    pub(crate) publisher: rustdds::Publisher,
    pub(crate) subscriber: rustdds::Subscriber,
    /// The participant; `None` once [deleted](Self::delete). Its endpoints, publisher and
    /// subscriber only hold weak references to it: this and `status_listener` keep it alive.
    pub(super) participant: Mutex<Option<DomainParticipant>>,
    /// Its status-event listener (a strong reference), shared with the discovery feeds.
    pub(super) status_listener: SharedListener,
    pub(super) guid: GUID,
    /// The status listener, registered once (rustdds allows no more), kept between feeds.
    pub(super) status_poll: Arc<Mutex<StatusPoll>>,
}

impl RustddsParticipant {
    /// Creates the participant, its publisher/subscriber and the `ros_discovery_info` writer;
    /// also returns the warnings for discovery settings rustdds cannot honour.
    pub(super) fn create(config: &ParticipantConfig<'_>) -> Result<(Self, Vec<String>), DdsError> {
        let fail = |e| DdsError::Create(boxed(e));
        let (participant, warnings) =
            create_participant(config.domain, config.discovery).map_err(fail)?;
        let qos = QosPolicyBuilder::new().build();
        let publisher = participant.create_publisher(&qos).map_err(fail)?;
        let subscriber = participant.create_subscriber(&qos).map_err(fail)?;
        let topic = discovery_info::topic(&participant).map_err(fail)?;
        let discovery_writer = DiscoveryInfoWriter::new(&publisher, &topic).map_err(fail)?;
        let status_listener: SharedListener =
            Arc::new(Mutex::new(Some(participant.status_listener())));
        let status_poll = StatusPoll::new(Arc::clone(&status_listener)).map_err(DdsError::Poll)?;
        Ok((
            Self {
                discovery_writer,
                publisher,
                subscriber,
                guid: participant.guid(),
                status_listener,
                participant: Mutex::new(Some(participant)),
                status_poll: Arc::new(Mutex::new(status_poll)),
            },
            warnings,
        ))
    }

    /// The participant, unless it was deleted.
    pub(crate) fn participant(&self) -> Result<DomainParticipant, DdsError> {
        lock(&self.participant)
            .clone()
            .ok_or(DdsError::ParticipantDeleted)
    }
}
