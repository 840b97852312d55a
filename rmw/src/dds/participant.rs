//! Creating the rustdds participant from ROS discovery options.

use std::net::{IpAddr, Ipv4Addr};

use rustdds::{DomainParticipant, DomainParticipantBuilder};

use crate::context::env::{DiscoveryOptions, DiscoveryRange, DomainId};

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
    let participant = builder.build()?;
    Ok((participant, warnings))
}
