//! HORUS talker and listener against eProsima Fast DDS 2.9 (the DDS of `rmw_fastrtps_cpp`,
//! Jazzy's default RMW): the C++ peer `interop-tests/peers/fastdds/ros_participant.cpp` acting as
//! demo_nodes_cpp's listener and talker on `/chatter` (std_msgs/String, rclcpp's default QoS,
//! typehash USER_DATA, its node announced on `ros_discovery_info`), both directions, inside the
//! test network namespace. Each test has its own domain.

mod common;

use std::collections::HashSet;
use std::time::Instant;

use common::{hear, run_listener, run_talker, LIMIT};
use interop_tests::fastdds::{self, ChatterCreated, FastDdsPeer};

/// The peer's endpoint is the one rmw_fastrtps_cpp would create for demo_nodes' chatter.
fn assert_chatter_endpoint(created: &ChatterCreated, mode: &str) {
    assert_eq!(created.vendor, "010f", "{created:?}");
    assert_eq!(created.mode, mode, "{created:?}");
    assert_eq!(created.topic, "rt/chatter", "{created:?}");
    assert_eq!(
        created.type_name, "std_msgs::msg::dds_::String_",
        "{created:?}"
    );
    let qos = &created.json["qos"];
    assert_eq!(qos["reliability"], "RELIABLE", "{created:?}");
    assert_eq!(qos["durability"], "VOLATILE", "{created:?}");
    assert_eq!(qos["history"], "KEEP_LAST", "{created:?}");
    assert_eq!(qos["depth"], 10, "{created:?}");
}

#[test]
fn a_horus_talker_is_heard_by_a_fast_dds_listener() {
    let domain = 193;
    let mut peer =
        FastDdsPeer::start_listener(domain, "/", "listener", "/chatter", LIMIT, 3).expect("peer");
    let created = peer.chatter_created(LIMIT).expect("listener created");
    assert_chatter_endpoint(&created, "listen");
    let talker = run_talker(domain);
    let deadline = Instant::now() + LIMIT;
    let mut heard = Vec::new();
    while heard.len() < 3 {
        match peer.next_heard(deadline.saturating_duration_since(Instant::now())) {
            Some(h) => heard.push(h),
            None => panic!(
                "the Fast DDS listener heard only {heard:?}: {}",
                peer.output()
            ),
        }
    }
    let (code, _) = peer.finish(LIMIT).expect("peer exit");
    assert_eq!(talker.stop(), Ok(()));
    assert_eq!(code, Some(0), "{}", peer.output());
    // Consecutive messages of the one HORUS writer, in order (RELIABLE, KEEP_LAST 10).
    let numbers: Vec<u64> = heard
        .iter()
        .map(|h| {
            h.data
                .strip_prefix("Hello World: ")
                .and_then(|n| n.parse().ok())
                .unwrap_or_else(|| panic!("unexpected message {h:?}"))
        })
        .collect();
    assert!(numbers.windows(2).all(|w| w[1] == w[0] + 1), "{numbers:?}");
    assert!(
        heard.iter().all(|h| h.writer == heard[0].writer),
        "{heard:?}"
    );
}

#[test]
fn a_horus_listener_hears_a_fast_dds_talker() {
    let domain = 194;
    let (listener, heard) = run_listener(domain);
    let mut peer =
        FastDdsPeer::start_talker(domain, "/", "talker", "/chatter", LIMIT, 0).expect("peer");
    let created = peer.chatter_created(LIMIT).expect("talker created");
    assert_chatter_endpoint(&created, "talk");
    let got = hear(&heard, 3);
    peer.leave().expect("SIGTERM to the talker");
    let (code, rest) = peer.finish(LIMIT).expect("peer exit");
    let (outcome, metrics) = listener.stop();
    assert_eq!(outcome, Ok(()));
    assert_eq!(code, Some(0), "{}", peer.output());
    // Everything heard is what the Fast DDS talker published.
    let published: HashSet<String> = rest.iter().filter_map(|l| fastdds::published(l)).collect();
    assert!(
        got.iter()
            .all(|m| m.starts_with("Hello World: ") && published.contains(m)),
        "heard {got:?}, published {published:?}"
    );
    assert!(metrics.expect("metrics").messages_received >= 3);
}
