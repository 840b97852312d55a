//! A process that uses topics and services without a node of its own has one node (and one
//! DDS participant): the topics' and the clients' default node is the same. Inside the test
//! network namespace, in the environment's domain.

use std::time::Duration;

use horus::msgs::std_msgs::msg::Int32;
use horus::prelude::*;
use horus_ros_graph::Graph;
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_services::ServiceClient;

const WAIT: Duration = Duration::from_secs(30);

#[test]
fn a_topic_and_a_client_made_without_a_node_share_the_process_default_node() {
    let topic = Topic::<Int32>::new("default_node_topic").expect("topic");
    topic.connect_subscriber().expect("subscriber");
    let _client = ServiceClient::<AddTwoInts>::builder()
        .name("/default_node_service")
        .build()
        .expect("client");
    let node = horus_ros_services::default_node().expect("default node");
    let graph = Graph::of(node.context()).expect("graph");
    // Our own endpoints are in our graph; both must name the one default node.
    let found = |c: &horus_ros_graph::GraphCache| {
        let subscriptions = c.subscriptions_info_by_topic("/default_node_topic", false);
        let clients = c
            .clients_info_by_service("/default_node_service", false)
            .unwrap_or_default();
        (subscriptions, clients)
    };
    assert!(
        graph.wait_until(WAIT, |c| {
            let (s, k) = found(c);
            !s.is_empty() && !k.is_empty()
        }),
        "our own subscription and client never appeared in our graph"
    );
    let (subscriptions, clients) = graph.read(found);
    for s in &subscriptions {
        assert_eq!(s.node_name, node.name().as_str(), "the topic's node");
    }
    for c in &clients {
        assert_eq!(c.node_name, node.name().as_str(), "the client's node");
    }
}
