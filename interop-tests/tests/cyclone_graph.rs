//! The live graph against a Cyclone DDS peer that joins as a ROS 2 participant with an
//! example_interfaces/AddTwoInts server: our `servers_info_by_service` equals the GUIDs and QoS
//! Cyclone itself holds for the server's endpoints, our own node is in the graph too, and the
//! peer's departure is seen.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

use horus_ros_graph::{Graph, ServiceEndpointType};
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::{DurabilityPolicy, HistoryPolicy, Qos, ReliabilityPolicy};
use horus_ros_rmw::Context;
use interop_tests::{cyclone_config, peer_script, python};
use serde_json::Value;

const DOMAIN: u32 = 71;
const WAIT: Duration = Duration::from_secs(20);

#[test]
fn servers_info_matches_what_cyclone_holds() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let graph = Graph::of(&context).expect("graph");
    let node = context.create_node("horus_watcher", "/").expect("node");
    let publisher = node
        .create_publisher::<Time>("watch", &Qos::default())
        .expect("publisher");
    let changes = graph.subscribe();

    // Our own node and endpoint are in the graph (reported by the context, not by DDS).
    assert!(graph.wait_until(WAIT, |c| {
        c.publishers_info_by_topic("/watch", false)
            .iter()
            .any(|i| i.endpoint_gid == publisher.gid())
    }));

    let mut child = Command::new(python())
        .arg(peer_script("cyclone_ros_participant.py"))
        .args([
            &DOMAIN.to_string(),
            "/peer_ns",
            "cyclone_node",
            &Time::type_hash().to_string(),
            "3",
            "/add_two_ints",
        ])
        .env("CYCLONEDDS_URI", cyclone_config())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start the Cyclone DDS peer");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("piped stdout"))
        .read_line(&mut line)
        .expect("peer line");
    let created: Value = serde_json::from_str(line.trim()).expect("JSON line");
    let server = &created["server"];

    assert!(
        graph.wait_for_service("/add_two_ints", WAIT),
        "service not ready within {WAIT:?}"
    );
    // Ready means both endpoints are known, and the node too once its message arrived.
    assert!(graph.wait_until(WAIT, |c| {
        c.servers_info_by_service("/add_two_ints", false)
            .map(|s| s.first().is_some_and(|i| i.node_name == "cyclone_node"))
            .unwrap_or(false)
    }));
    let servers = graph
        .read(|c| c.servers_info_by_service("/add_two_ints", false))
        .expect("servers");
    assert_eq!(servers.len(), 1);
    let s = &servers[0];
    assert_eq!(
        (s.node_name.as_str(), s.node_namespace.as_str()),
        ("cyclone_node", "/peer_ns")
    );
    assert_eq!(s.service_type, "example_interfaces/srv/AddTwoInts");
    assert_eq!(s.endpoint_type, ServiceEndpointType::Server);
    assert_eq!(s.endpoint_count(), 2);
    let gids: Vec<String> = s.endpoint_gids.iter().map(ToString::to_string).collect();
    assert_eq!(
        gids,
        vec![
            server["request_reader"].as_str().unwrap_or(""),
            server["reply_writer"].as_str().unwrap_or("")
        ]
    );
    for (qos, theirs) in s
        .qos_profiles
        .iter()
        .zip([&server["request_reader_qos"], &server["reply_writer_qos"]])
    {
        assert_eq!(
            qos.reliability.to_string(),
            theirs["reliability"].as_str().unwrap_or("")
        );
        assert_eq!(
            qos.durability.to_string(),
            theirs["durability"].as_str().unwrap_or("")
        );
        assert_eq!(qos.reliability, ReliabilityPolicy::Reliable);
        assert_eq!(qos.durability, DurabilityPolicy::Volatile);
        // rustdds reports no history for a discovered endpoint (as rmw_fastrtps); the Cyclone
        // backend the one Cyclone DDS holds (as rmw_cyclonedds).
        if context.backend() == Some(horus_ros_rmw::Backend::Cyclone) {
            assert_ne!(qos.history, HistoryPolicy::Unknown);
        } else {
            assert_eq!(qos.history, HistoryPolicy::Unknown);
        }
    }
    assert_eq!(
        s.endpoint_type_hashes
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>(),
        vec![
            horus_ros_msgs::example_interfaces::srv::AddTwoIntsRequest::type_hash().to_string(),
            horus_ros_msgs::example_interfaces::srv::AddTwoIntsResponse::type_hash().to_string(),
        ]
    );
    assert!(graph
        .read(|c| c.clients_info_by_service("/add_two_ints", false))
        .expect("clients")
        .is_empty());
    let text = s.to_string();
    assert!(
        text.starts_with("Node name: cyclone_node\nNode namespace: /peer_ns\n"),
        "{text}"
    );

    let names: Vec<String> = graph
        .read(|c| c.node_names())
        .into_iter()
        .map(|n| format!("{}|{}", n.namespace, n.name))
        .collect();
    assert!(names.contains(&"/|horus_watcher".to_owned()), "{names:?}");
    assert!(
        names.contains(&"/peer_ns|cyclone_node".to_owned()),
        "{names:?}"
    );

    // The peer leaves after 3 s: its service and node go away.
    assert!(graph.wait_until(WAIT, |c| !c.service_is_available("/add_two_ints")));
    assert!(graph.wait_until(WAIT, |c| c
        .node_names()
        .iter()
        .all(|n| n.name != "cyclone_node")));
    let _ = child.wait();
    // Subscribers were told about the changes.
    let events: Vec<_> = changes.try_iter().collect();
    assert!(events.iter().any(|e| matches!(e, horus_ros_graph::GraphEvent::NodeAdded { name, .. } if name == "cyclone_node")));
    assert!(events.iter().any(|e| matches!(e, horus_ros_graph::GraphEvent::NodeRemoved { name, .. } if name == "cyclone_node")));
}

#[test]
fn wait_for_graph_change_wakes_on_a_new_node_and_times_out_otherwise() {
    let context = Context::builder()
        .domain_id(DOMAIN + 1)
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
        .domain_id(DOMAIN + 1)
        .build()
        .expect("second participant");
    let _node = other.create_node("newcomer", "/").expect("node");
    assert!(graph.wait_until(WAIT, |c| c
        .node_names()
        .iter()
        .any(|n| n.name == "newcomer")));
}
