//! A real rmw_cyclonedds_cpp node (rclpy 7.1.6 on rmw_cyclonedds_cpp 2.2.2, whatever the run's
//! peers use) joining after we dropped a node and an endpoint gets our `ros_discovery_info` as
//! it is now: the participant's message is republished on every change, so the late joiner sees
//! only the node that stays. (What rclpy sees of our nodes and their endpoints' GIDs, on the
//! run's RMW, is `jazzy_graph.rs`.)

use std::time::Duration;

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::{qos::Qos, Context};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use serde_json::{json, Value};

/// Each test uses its own domain so that tests running at once never see each other.
const DOMAIN: u32 = 42;
/// "Did not hang" bound for discovery on a loaded machine.
const WAIT: Duration = Duration::from_secs(30);

/// The `[namespace, name]` of every node in a `{"graph": …}` view of the peer.
fn node_names(view: &Value) -> Vec<(String, String)> {
    view["nodes"]
        .as_array()
        .map(|nodes| {
            nodes
                .iter()
                .map(|n| {
                    let s = |i: usize| n[i].as_str().unwrap_or_default().to_owned();
                    (s(0), s(1))
                })
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn dropping_endpoints_and_nodes_republishes_the_participant() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("short_lived", "/").expect("node");
    let other = context.create_node("stays", "/").expect("node");
    let publisher = node
        .create_publisher::<Time>("t", &Qos::default())
        .expect("publisher");
    drop(publisher);
    drop(node);
    // Only `stays` with no endpoints is left: the rclpy node, started now, must see exactly that
    // of our participant (beside itself).
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({"domain": DOMAIN, "namespace": "/", "name": "watcher", "graph": true}),
    )
    .expect("start the rclpy peer");
    let names = peer
        .wait_for(WAIT, "our node `stays` in rclpy's graph", |lines| {
            lines
                .iter()
                .rev()
                .find_map(|l| l.get("graph"))
                .map(node_names)
                .filter(|names| names.iter().any(|(_, name)| name == "stays"))
        })
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        names,
        vec![
            ("/".to_owned(), "stays".to_owned()),
            ("/".to_owned(), "watcher".to_owned())
        ],
        "{}",
        peer.output()
    );
    drop(other);
    // Our last node gone, rclpy sees only itself.
    peer.wait_for(WAIT, "our node `stays` gone from rclpy's graph", |lines| {
        lines
            .iter()
            .rev()
            .find_map(|l| l.get("graph"))
            .map(node_names)
            .filter(|names| names.iter().all(|(_, name)| name != "stays"))
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(peer.finish(WAIT), Ok(Some(0)), "{}", peer.output());
}
