//! A context that joins after a Fast DDS 2.9 ROS participant gets that participant's
//! transient-local `ros_discovery_info` sample from the heartbeat the writer sends when it
//! matches our reader, not from a later periodic one.
//!
//! The peer's `ros_discovery_info` writer is told to send its periodic heartbeat only once an
//! hour, so the sample can only come through the exchange that follows a match: a Fast DDS
//! writer heartbeats a reader it has just matched (`StatefulWriter::matched_reader_add`) and
//! answers a pre-emptive ACKNACK with a heartbeat only when its `bitmapBase` is 0, which neither
//! rustdds nor Cyclone DDS sends. Our feed announces a late-joiner reader once it knows the
//! writer (see `rmw/src/late_joiner.rs`), so that heartbeat finds the writer matched.

use std::time::{Duration, Instant};

use horus_ros_rmw::{Context, DiscoveryEvent};
use interop_tests::fastdds::FastDdsPeer;

const DOMAIN: u32 = 62;
/// Generous bound for discovery on a loaded machine: endpoint discovery of a Fast DDS peer can
/// take one SEDP heartbeat period (1 s); the test passes as soon as the sample is in.
const LIMIT: Duration = Duration::from_secs(20);

#[test]
fn a_late_joining_context_gets_a_fastdds_participants_nodes_without_its_periodic_heartbeat() {
    let mut peer = FastDdsPeer::start_with_info_heartbeat(
        DOMAIN,
        "/late_ns",
        "late_node",
        "/late_ns/add_two_ints",
        Duration::from_secs(60),
        Duration::from_secs(3600),
    )
    .expect("build and start the Fast DDS peer");
    let created = peer
        .created(Duration::from_secs(10))
        .expect("the peer says what it created");

    // Only now do we join: the peer's ros_discovery_info sample is historical for us.
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("feed");
    let started = Instant::now();
    let mut writer_discovered = false;
    loop {
        let left = LIMIT.saturating_sub(started.elapsed());
        assert!(
            !left.is_zero(),
            "no ros_discovery_info from the Fast DDS peer within {LIMIT:?} (its writer \
             discovered: {writer_discovered}): the heartbeat it sends on matching our reader was \
             missed and its next periodic one is an hour away"
        );
        match feed.next_timeout(left) {
            Some(DiscoveryEvent::EndpointDiscovered(e))
                if e.dds_topic_name == "ros_discovery_info"
                    && e.participant_gid.to_string() == created.participant =>
            {
                writer_discovered = true;
            }
            Some(DiscoveryEvent::ParticipantEntities(info))
                if info.gid.to_string() == created.participant =>
            {
                let nodes: Vec<(&str, &str)> = info
                    .node_entities_info_seq
                    .iter()
                    .map(|n| (n.node_namespace.as_str(), n.node_name.as_str()))
                    .collect();
                if nodes == [("/late_ns", "late_node")]
                    && !info.node_entities_info_seq[0].reader_gid_seq.is_empty()
                {
                    eprintln!(
                        "ros_discovery_info of the Fast DDS peer after {:?}",
                        started.elapsed()
                    );
                    return;
                }
            }
            _ => {}
        }
    }
}
