//! HORUS talker and listener against real ROS 2 Jazzy: an rclpy 7.1.6 node on the run's RMW
//! (`HORUS_ROS_PEER_RMW`: rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5 by default, or
//! rmw_cyclonedds_cpp 2.2.2) (`interop-tests/peers/jazzy_node.py`) acting as demo_nodes' listener
//! and talker on `/chatter` (std_msgs/msg/String, rclpy's default QoS: KEEP_LAST 10, RELIABLE,
//! VOLATILE), both directions, inside the test network namespace. Each test has its own domain.

mod common;

use std::collections::HashSet;

use common::{hear, run_listener, run_talker, LIMIT};
use interop_tests::peers::RclpyPeer;
use serde_json::{json, Value};

#[test]
fn a_horus_talker_is_heard_by_an_rclpy_listener() {
    let domain = 193;
    let mut peer = RclpyPeer::start(&json!({
        "domain": domain, "namespace": "/", "name": "listener",
        "subscriptions": [{"topic": "/chatter", "type": "std_msgs/msg/String"}],
    }))
    .expect("peer");
    peer.ready(LIMIT).expect("the rclpy listener is up");
    let talker = run_talker(domain);
    let heard: Vec<String> = peer
        .wait_for_heard(LIMIT, 3)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(talker.stop(), Ok(()));
    assert_eq!(peer.finish(LIMIT), Ok(Some(0)), "{}", peer.output());
    // Consecutive messages of the one HORUS writer, in order (RELIABLE, KEEP_LAST 10).
    let numbers: Vec<u64> = heard
        .iter()
        .map(|h| {
            h.strip_prefix("Hello World: ")
                .and_then(|n| n.parse().ok())
                .unwrap_or_else(|| panic!("unexpected message {h:?}"))
        })
        .collect();
    assert!(numbers.windows(2).all(|w| w[1] == w[0] + 1), "{numbers:?}");
}

#[test]
fn a_horus_listener_hears_an_rclpy_talker() {
    let domain = 194;
    let (listener, heard) = run_listener(domain);
    let mut peer = RclpyPeer::start(&json!({
        "domain": domain, "namespace": "/", "name": "talker",
        "publishers": [{"topic": "/chatter", "type": "std_msgs/msg/String", "period_s": 0.05}],
    }))
    .expect("peer");
    peer.ready(LIMIT).expect("the rclpy talker is up");
    let got = hear(&heard, 3);
    assert_eq!(peer.finish(LIMIT), Ok(Some(0)), "{}", peer.output());
    let (outcome, metrics) = listener.stop();
    assert_eq!(outcome, Ok(()));
    // Everything heard is what the rclpy talker published.
    let published: HashSet<&str> = peer
        .all("published")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert!(
        got.iter()
            .all(|m| m.starts_with("Hello World: ") && published.contains(m.as_str())),
        "heard {got:?}, published {published:?}"
    );
    assert!(metrics.expect("metrics").messages_received >= 3);
}
