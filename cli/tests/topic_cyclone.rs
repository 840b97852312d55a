//! `topic echo` and `topic pub` against a real rmw_cyclonedds_cpp node (rclpy 7.1.6 on
//! rmw_cyclonedds_cpp 2.2.2, whatever the run's peers use: `interop-tests/peers/jazzy_node.py`)
//! on `/chatter` as demo_nodes uses it (`std_msgs/msg/String`, rclpy's default QoS: KEEP_LAST
//! 10, RELIABLE, VOLATILE), on whichever backend HORUS_ROS_BACKEND names. Each test has its own
//! domain (231, 232). Run inside the private network namespace.

mod common;

use std::time::Duration;

use common::horus;
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use serde_json::json;

/// How long a peer may take to finish what it was asked.
const LIMIT: Duration = Duration::from_secs(40);

#[test]
fn topic_echo_prints_what_an_rmw_cyclonedds_talker_publishes() {
    let domain = 231;
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({
            "domain": domain, "namespace": "/", "name": "talker",
            "publishers": [{"topic": "/chatter", "type": "std_msgs/msg/String",
                            "period_s": 0.05}],
        }),
    )
    .expect("start the rclpy talker");
    peer.ready(LIMIT).expect("the rclpy talker is up");
    let run = horus(
        domain,
        &["topic", "echo", "/chatter", "std_msgs/msg/String", "--once"],
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let mut lines = run.stdout.lines();
    let first = lines.next().unwrap_or_default();
    // PyYAML quotes a string holding ": ", as `ros2 topic echo` prints it.
    let n = first
        .strip_prefix("data: 'Hello World: ")
        .and_then(|rest| rest.strip_suffix('\''));
    assert!(n.is_some_and(|n| n.parse::<u64>().is_ok()), "{run:?}");
    assert_eq!(lines.next(), Some("---"), "{run:?}");
    assert_eq!(lines.next(), None, "--once prints one message: {run:?}");
}

#[test]
fn topic_pub_is_heard_by_an_rmw_cyclonedds_listener() {
    let domain = 232;
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({
            "domain": domain, "namespace": "/", "name": "listener",
            "subscriptions": [{"topic": "/chatter", "type": "std_msgs/msg/String"}],
        }),
    )
    .expect("start the rclpy listener");
    peer.ready(LIMIT).expect("the rclpy listener is up");
    let run = horus(
        domain,
        &[
            "topic",
            "pub",
            "/chatter",
            "std_msgs/msg/String",
            "data: from horus-ros",
            "--times",
            "5",
            "--rate",
            "20",
            "-w",
            "1",
            "--keep-alive",
            "1",
        ],
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    assert_eq!(
        run.stdout
            .lines()
            .filter(|l| l.starts_with("publishing #"))
            .count(),
        5,
        "{run:?}"
    );
    // `-w 1` waits until our writer has matched the reader, as ros2cli's does; the reader may
    // match our writer a moment later, and a VOLATILE reader gets only what is written after
    // that (DDS semantics; rclcpp's listener loses the same first message of `ros2 topic pub`).
    // Five are sent: at least three are heard, each as sent.
    let heard = peer
        .wait_for_heard(LIMIT, 3)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(heard.iter().all(|h| h == "from horus-ros"), "{heard:?}");
    assert_eq!(peer.finish(LIMIT), Ok(Some(0)), "{}", peer.output());
}
