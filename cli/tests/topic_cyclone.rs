//! `topic echo` and `topic pub` against an independent DDS implementation: a Cyclone DDS
//! (Python) peer on `/chatter` as demo_nodes uses it (`interop-tests/peers/cyclone_chatter.py`:
//! `rt/chatter`, `std_msgs::msg::dds_::String_`, rclcpp's default QoS and rmw_cyclonedds'
//! `typehash=` USER_DATA), on whichever backend HORUS_ROS_BACKEND names. Each test has its own
//! domain (231, 232). Run inside the private network namespace.

mod common;

use std::time::Duration;

use common::horus;
use interop_tests::Peer;

/// How long a peer may take to finish what it was asked.
const LIMIT: Duration = Duration::from_secs(40);

#[test]
fn topic_echo_prints_what_a_cyclone_dds_talker_publishes() {
    let domain = 231;
    let _peer = Peer::start(
        "cyclone_chatter.py",
        &[domain.to_string(), "talk".into(), "0".into(), "30".into()],
    )
    .expect("peer");
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
fn topic_pub_is_heard_by_a_cyclone_dds_listener() {
    let domain = 232;
    let peer = Peer::start(
        "cyclone_chatter.py",
        &[domain.to_string(), "listen".into(), "3".into(), "30".into()],
    )
    .expect("peer");
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
    // Five are sent, the listener exits after three.
    let out = peer.wait(LIMIT).expect("peer output");
    assert_eq!(out.code, Some(0), "{out:?}");
    let heard: Vec<_> = out
        .stdout
        .lines()
        .filter(|l| *l == "I heard: [from horus-ros]")
        .collect();
    assert_eq!(heard.len(), 3, "{out:?}");
}
