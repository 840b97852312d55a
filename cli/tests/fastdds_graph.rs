//! The CLI next to a real ROS 2 Jazzy node on Fast DDS (rclpy 7.1.6 on rmw_fastrtps_cpp 8.4.3 /
//! Fast DDS 2.14.5, Jazzy's default RMW) that was up before the CLI started: its node is listed
//! with every endpoint under its name, and an answer given before discovery completed is never
//! silently incomplete.
//!
//! The node's `ros_discovery_info` writer sends its periodic heartbeat only once an hour (a Fast
//! DDS XML profile for that topic), so its nodes reach the CLI only through the heartbeat the
//! writer sends when it matches a reader of ours: the case a late-joining rmw_cyclonedds or
//! rustdds reader used to miss.
//!
//! Run inside the private network namespace (`scripts/isolated`).

mod common;

use std::time::Duration;

use common::horus;
use interop_tests::peers::RclpyPeer;
use serde_json::json;

const DOMAIN: u32 = 63;
const WARNING: &str = "WARNING: discovery incomplete after ";

#[test]
fn a_fastdds_node_is_listed_completely_and_an_early_answer_says_it_is_incomplete() {
    let mut peer = RclpyPeer::start(&json!({
        "domain": DOMAIN, "namespace": "/fast_ns", "name": "fast_node",
        "servers": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
        "clients": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
        "info_heartbeat_s": 3600,
    }))
    .expect("start the rclpy peer");
    peer.ready(Duration::from_secs(20))
        .expect("the rclpy node is up");

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
    // As `ros2 node info` prints an rclpy node: its own entities, rclpy's parameter and type
    // description services, /parameter_events and /rosout.
    let want = "/fast_ns/fast_node
  Subscribers:

  Publishers:
    /parameter_events: rcl_interfaces/msg/ParameterEvent
    /rosout: rcl_interfaces/msg/Log
  Service Servers:
    /fast_ns/fast_node/describe_parameters: rcl_interfaces/srv/DescribeParameters
    /fast_ns/fast_node/get_parameter_types: rcl_interfaces/srv/GetParameterTypes
    /fast_ns/fast_node/get_parameters: rcl_interfaces/srv/GetParameters
    /fast_ns/fast_node/get_type_description: type_description_interfaces/srv/GetTypeDescription
    /fast_ns/fast_node/list_parameters: rcl_interfaces/srv/ListParameters
    /fast_ns/fast_node/set_parameters: rcl_interfaces/srv/SetParameters
    /fast_ns/fast_node/set_parameters_atomically: rcl_interfaces/srv/SetParametersAtomically
    /fast_ns/set: std_srvs/srv/SetBool
  Service Clients:
    /fast_ns/set: std_srvs/srv/SetBool
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
