//! A context that joins after a real ROS 2 Jazzy node (rclpy 7.1.6 on the run's RMW:
//! rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5, or rmw_cyclonedds_cpp 2.2.2 / Cyclone DDS 0.10) gets
//! that node's transient-local `ros_discovery_info` sample from the heartbeat the writer sends
//! when it matches our reader, not from a later periodic one.
//!
//! The node's `ros_discovery_info` writer is given a periodic heartbeat of once an hour, so the
//! sample can only come through the exchange that follows a match.
//! - Fast DDS: by an XML profile named after the topic, which rmw_fastrtps_cpp loads for it. A
//!   Fast DDS writer heartbeats a reader it has just matched (`StatefulWriter::matched_reader_add`)
//!   and answers a pre-emptive ACKNACK with a heartbeat only when its `bitmapBase` is 0, which
//!   neither rustdds nor Cyclone DDS sends. Our feed announces a late-joiner reader once it knows
//!   the writer (see `dds-common/src/late_joiner.rs`), so that heartbeat finds the writer matched.
//! - Cyclone DDS: by `Internal/HeartbeatInterval` (every writer of the node: Cyclone DDS has no
//!   setting per topic). A Cyclone DDS writer schedules a heartbeat 1 ms after matching a reader
//!   (`ddsi_entity_match.c` `writer_add_connection`), unless it sent one within the periodic
//!   interval (`writer_hbcontrol_must_send`).
//!
//! DDS only (not in the Zenoh run): `ros_discovery_info` and its writer's heartbeats are DDS's.
//! rmw_zenoh has neither: a late joiner learns the graph by a liveliness query and the history of
//! its liveliness subscriber (rmw_zenoh_cpp 0.2.10 `rmw_context_impl_s.cpp`), as our Zenoh feed
//! does (`rmw-zenoh/src/feed.rs`); rclpy nodes on rmw_zenoh_cpp that were there before a
//! horus-ros process started are found that way by every `horus-ros` command of the Zenoh run
//! (`cli/tests/cli_diff.rs`, `cli/tests/zenoh.rs`).

use std::time::{Duration, Instant};

use horus_ros_rmw::{Context, DiscoveryEvent, VendorId};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use serde_json::json;

const DOMAIN: u32 = 114;
/// Generous bound for discovery on a loaded machine: endpoint discovery of a Fast DDS node can
/// take one SEDP heartbeat period; the test passes as soon as the sample is in.
const LIMIT: Duration = Duration::from_secs(30);

#[test]
fn a_late_joining_context_gets_an_rclpy_nodes_entities_without_its_periodic_heartbeat() {
    assert!(
        Rmw::of_peers().is_dds(),
        "DDS only: the peers' RMW is {} (see the module documentation)",
        Rmw::of_peers().name()
    );
    let mut peer = RclpyPeer::start(&json!({
        "domain": DOMAIN, "namespace": "/late_ns", "name": "late_node",
        "servers": [{"service": "/late_ns/set", "type": "std_srvs/srv/SetBool"}],
        "info_heartbeat_s": 3600,
    }))
    .expect("start the rclpy peer");
    peer.ready(LIMIT).expect("the rclpy node is up");

    // Only now do we join: the node's ros_discovery_info sample is historical for us.
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("feed");
    let started = Instant::now();
    let VendorId(vendor) = Rmw::of_peers()
        .dds_vendor_id()
        .map(VendorId)
        .expect("a DDS RMW");
    let mut writer_discovered = false;
    loop {
        let left = LIMIT.saturating_sub(started.elapsed());
        assert!(
            !left.is_zero(),
            "no ros_discovery_info from the rclpy node within {LIMIT:?} (its writer \
             discovered: {writer_discovered}): the heartbeat it sends on matching our reader was \
             missed and its next periodic one is an hour away\n{}",
            peer.output()
        );
        match feed.next_timeout(left) {
            // A Fast DDS or Cyclone DDS GUID prefix starts with its vendor id.
            Some(DiscoveryEvent::EndpointDiscovered(e))
                if e.dds_topic_name == "ros_discovery_info"
                    && e.participant_gid.data[..2] == vendor =>
            {
                writer_discovered |= e.kind == horus_ros_rmw::qos::EndpointKind::Writer;
            }
            Some(DiscoveryEvent::ParticipantEntities(info)) => {
                let nodes: Vec<(&str, &str)> = info
                    .node_entities_info_seq
                    .iter()
                    .map(|n| (n.node_namespace.as_str(), n.node_name.as_str()))
                    .collect();
                if nodes == [("/late_ns", "late_node")]
                    && !info.node_entities_info_seq[0].reader_gid_seq.is_empty()
                {
                    eprintln!(
                        "ros_discovery_info of the rclpy node after {:?}",
                        started.elapsed()
                    );
                    break;
                }
            }
            _ => {}
        }
    }
    assert_eq!(peer.finish(LIMIT), Ok(Some(0)), "{}", peer.output());
}
