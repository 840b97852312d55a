//! `Graph::wait_for_graph_change`: it wakes when a node joins the graph and times out when
//! nothing changes; one `Graph` per context. (The live graph against real ROS 2 nodes, on both
//! DDS RMWs, is `jazzy_graph.rs`.)

use std::time::Duration;

use horus_ros_graph::Graph;
use horus_ros_rmw::Context;

const DOMAIN: u32 = 72;
const WAIT: Duration = Duration::from_secs(20);

#[test]
fn wait_for_graph_change_wakes_on_a_new_node_and_times_out_otherwise() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let graph = Graph::of(&context).expect("graph");
    assert!(
        std::sync::Arc::ptr_eq(&graph, &Graph::of(&context).expect("graph")),
        "one graph per context"
    );
    // Let the initial snapshot settle, then nothing changes.
    graph.wait_until(WAIT, |c| c.node_count() == 0);
    while graph.wait_for_graph_change(Duration::from_millis(200)) {}
    assert!(!graph.wait_for_graph_change(Duration::from_millis(100)));
    let other = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("second participant");
    let _node = other.create_node("newcomer", "/").expect("node");
    assert!(graph.wait_until(WAIT, |c| c
        .node_names()
        .iter()
        .any(|n| n.name == "newcomer")));
}
