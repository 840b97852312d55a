//! The CLI next to a Fast DDS 2.9 ROS participant (the DDS of rmw_fastrtps_cpp, Jazzy's default
//! RMW) that was up before the CLI started: its node is listed with every endpoint under its
//! name, and an answer given before discovery completed is never silently incomplete.
//!
//! The peer's `ros_discovery_info` writer sends its periodic heartbeat only once an hour, so
//! its nodes reach the CLI only through the heartbeat the writer sends when it matches a reader
//! of ours: the case a late-joining rmw_cyclonedds or rustdds reader used to miss.
//!
//! Run inside the private network namespace (`scripts/isolated`).

mod common;

use std::time::Duration;

use common::horus;
use interop_tests::fastdds::FastDdsPeer;

const DOMAIN: u32 = 63;
const WARNING: &str = "WARNING: discovery incomplete after ";

#[test]
fn a_fastdds_node_is_listed_completely_and_an_early_answer_says_it_is_incomplete() {
    let mut peer = FastDdsPeer::start_with_info_heartbeat(
        DOMAIN,
        "/fast_ns",
        "fast_node",
        "/fast_ns/add_two_ints",
        Duration::from_secs(90),
        Duration::from_secs(3600),
    )
    .expect("build and start the Fast DDS peer");
    peer.created(Duration::from_secs(10))
        .expect("the peer says what it created");

    // With the default options the CLI waits for the peer's nodes up to the bound a real Fast
    // DDS node needs (its ros_discovery_info writer's periodic heartbeat is 3 s by default, this
    // one's an hour): should the answer still be incomplete, stderr says so, in one line.
    let quick = horus(DOMAIN, &["node", "list"]);
    assert_eq!(quick.code, Some(0), "{quick:?}");
    if quick.stdout != "/fast_ns/fast_node\n" {
        let warnings: Vec<&str> = quick
            .stderr
            .lines()
            .filter(|l| l.starts_with(WARNING))
            .collect();
        assert_eq!(
            warnings.len(),
            1,
            "an incomplete answer ({:?}) must say so on stderr, once: {quick:?}",
            quick.stdout
        );
    }

    // Given the time, the answer is complete and says nothing more.
    let args = ["--spin-time", "15", "node", "list"];
    let full = horus(DOMAIN, &args);
    assert_eq!(full.stdout, "/fast_ns/fast_node\n", "{full:?}");
    assert!(!full.stderr.contains(WARNING), "{full:?}");

    // Every endpoint of the peer is under its node's name.
    let info = horus(
        DOMAIN,
        &["--spin-time", "15", "node", "info", "/fast_ns/fast_node"],
    );
    let want = "/fast_ns/fast_node
  Subscribers:

  Publishers:

  Service Servers:
    /fast_ns/add_two_ints: example_interfaces/srv/AddTwoInts
  Service Clients:
    /fast_ns/add_two_ints: example_interfaces/srv/AddTwoInts
  Action Servers:

  Action Clients:

";
    assert_eq!(info.stdout, want, "{info:?}");
    let graph = horus(DOMAIN, &["--spin-time", "15", "graph", "--json"]);
    assert!(
        !graph.stdout.contains("_NODE_NAME_UNKNOWN_") && graph.stdout.contains("fast_node"),
        "{graph:?}"
    );
}
