//! Node churn: 200 nodes (each with a publisher and a subscription) created and dropped in 4
//! waves of 50 in one process, while another participant watches the graph: after each wave,
//! and after the churning participant leaves, the watcher's graph is back to what it was
//! before — no node, endpoint or topic left behind. Inside the test network namespace, on the
//! backend of `HORUS_ROS_BACKEND`; every wait is on the graph's own change events.

use std::collections::BTreeSet;
use std::time::Duration;

use horus_ros_graph::{Graph, GraphCache};
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Context, Publisher, Subscription};

const DOMAIN: u32 = 143;
const WAVES: usize = 4;
const NODES_PER_WAVE: usize = 50;
/// How long one wave may take to appear, or to go.
const WAIT: Duration = Duration::from_secs(30);

/// What the watcher sees: nodes, and every topic and service (hidden ones too) with its
/// endpoint counts.
#[derive(Debug, PartialEq, Eq)]
struct Snapshot {
    nodes: Vec<(String, String)>,
    topics: Vec<(String, BTreeSet<String>, usize, usize)>,
    services: Vec<(String, BTreeSet<String>, usize, usize)>,
}

fn snapshot(g: &GraphCache) -> Snapshot {
    let mut nodes: Vec<(String, String)> = g
        .node_names()
        .into_iter()
        .map(|n| (n.namespace, n.name))
        .collect();
    nodes.sort();
    let topics = g
        .topic_names_and_types(true)
        .into_iter()
        .map(|(topic, types)| {
            let (pubs, subs) = (g.count_publishers(&topic), g.count_subscribers(&topic));
            (topic, types, pubs, subs)
        })
        .collect();
    let services = g
        .service_names_and_types(true)
        .into_iter()
        .map(|(service, types)| {
            let (servers, clients) = (g.count_services(&service), g.count_clients(&service));
            (service, types, servers, clients)
        })
        .collect();
    Snapshot {
        nodes,
        topics,
        services,
    }
}

/// A churning node and its two endpoints (dropped with it).
struct Churner {
    _publisher: Publisher<StringMsg>,
    _subscription: Subscription<StringMsg>,
    _node: horus_ros_rmw::Node,
}

#[test]
fn nodes_created_and_dropped_in_waves_leave_the_graph_as_it_was() {
    let watcher = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("watcher context");
    let graph = Graph::of(&watcher).expect("graph");
    let churn = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("churning context");
    // The churning participant with no node yet: the baseline (an empty graph would not show a
    // participant that is gone but whose nodes linger).
    let anchor = churn.create_node("anchor", "/churn").expect("anchor node");
    assert!(
        graph.wait_until(WAIT, |g| g.node_names().iter().any(|n| n.name == "anchor")),
        "the churning participant's first node was never seen"
    );
    assert!(
        graph.wait_until(WAIT, GraphCache::is_consistent),
        "the graph did not settle"
    );
    let base = graph.read(snapshot);

    let qos = Qos::default();
    for wave in 0..WAVES {
        let churners: Vec<Churner> = (0..NODES_PER_WAVE)
            .map(|i| {
                let node = churn
                    .create_node(&format!("churner_{wave}_{i}"), "/churn")
                    .expect("node");
                Churner {
                    _publisher: node
                        .create_publisher::<StringMsg>("chatter", &qos)
                        .expect("publisher"),
                    _subscription: node
                        .create_subscription::<StringMsg>("echo", &qos)
                        .expect("subscription"),
                    _node: node,
                }
            })
            .collect();
        let mut seen = None;
        let all_there = graph.wait_until(WAIT, |g| {
            seen = Some((
                g.node_count(),
                g.count_publishers("/churn/chatter"),
                g.count_subscribers("/churn/echo"),
            ));
            seen == Some((
                base.nodes.len() + NODES_PER_WAVE,
                NODES_PER_WAVE,
                NODES_PER_WAVE,
            ))
        });
        assert!(all_there, "wave {wave}: the graph shows {seen:?}");
        drop(churners);
        let mut last = None;
        let back = graph.wait_until(WAIT, |g| {
            let now = snapshot(g);
            let same = now == base;
            last = Some(now);
            same
        });
        assert!(back, "wave {wave}: left {last:#?}\nbaseline {base:#?}");
    }

    // The participant itself leaves: its last node goes with it.
    drop(anchor);
    drop(churn);
    let mut last = None;
    let gone = graph.wait_until(WAIT, |g| {
        let nodes: Vec<String> = g.node_names().into_iter().map(|n| n.name).collect();
        let gone =
            !nodes.iter().any(|n| n == "anchor") && g.count_publishers("/churn/chatter") == 0;
        last = Some(nodes);
        gone
    });
    assert!(gone, "after the churning participant left: {last:?}");
}
