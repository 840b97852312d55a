//! A Cyclone DDS peer reads our `ros_discovery_info` and sees our node with the GIDs of its
//! endpoints, equal to the GUIDs Cyclone discovers for those endpoints through DDS discovery.

use std::time::Duration;

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::{qos::Qos, Context};
use interop_tests::Peer;
use serde_json::Value;

/// Each test uses its own domain so that tests running at once never see each other.
const DOMAIN: u32 = 41;

fn strings(v: &Value) -> Vec<String> {
    v.as_array()
        .map(|a| {
            a.iter()
                .filter_map(|s| s.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn cyclone_peer_sees_our_node_and_endpoint_gids() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context
        .create_node("interop_talker", "/horus_test")
        .expect("node");
    let publisher = node
        .create_publisher::<Time>("clock_out", &Qos::default())
        .expect("publisher");
    let subscription = node
        .create_subscription::<Time>("~/clock_in", &Qos::default())
        .expect("subscription");

    let peer = Peer::start(
        "cyclone_discovery_info.py",
        &[DOMAIN.to_string(), "/horus_test".into(), "interop_talker".into(), "1".into(), "1".into(), "20".into()],
    )
    .expect("start the Cyclone DDS peer (is the cyclonedds Python package installed? run scripts/setup)");
    let out = peer.wait(Duration::from_secs(30)).expect("peer output");
    assert_eq!(
        out.code,
        Some(0),
        "peer failed: stdout={} stderr={}",
        out.stdout,
        out.stderr
    );
    let doc: Value = serde_json::from_str(out.stdout.trim()).expect("peer prints JSON");
    eprintln!("the Cyclone DDS peer saw: {doc}");

    // Our participant's message, as Cyclone received it.
    let ours = doc["discovery_info"]
        .as_array()
        .and_then(|a| a.iter().find(|p| p["gid"] == context.gid().to_string()))
        .unwrap_or_else(|| panic!("no ros_discovery_info from {} in {doc}", context.gid()));
    let nodes = ours["nodes"].as_array().expect("nodes");
    assert_eq!(nodes.len(), 1, "{ours}");
    assert_eq!(nodes[0]["namespace"], "/horus_test");
    assert_eq!(nodes[0]["name"], "interop_talker");
    assert_eq!(
        strings(&nodes[0]["writers"]),
        vec![publisher.gid().to_string()]
    );
    assert_eq!(
        strings(&nodes[0]["readers"]),
        vec![subscription.gid().to_string()]
    );

    // The same GIDs are the GUIDs Cyclone discovered, on the mangled topics with the DDS type name.
    let find = |table: &str, guid: String| {
        doc[table]
            .as_array()
            .and_then(|a| a.iter().find(|e| e["guid"] == guid.as_str()).cloned())
            .unwrap_or_else(|| panic!("{guid} not in Cyclone's {table}: {doc}"))
    };
    let w = find("publications", publisher.gid().to_string());
    assert_eq!(w["topic"], "rt/horus_test/clock_out");
    assert_eq!(w["type"], "builtin_interfaces::msg::dds_::Time_");
    assert_eq!(w["participant"], context.gid().to_string());
    let r = find("subscriptions", subscription.gid().to_string());
    assert_eq!(r["topic"], "rt/horus_test/interop_talker/clock_in");
    assert_eq!(r["type"], "builtin_interfaces::msg::dds_::Time_");
}

#[test]
fn dropping_endpoints_and_nodes_republishes_the_participant() {
    let context = Context::builder()
        .domain_id(DOMAIN + 1)
        .build()
        .expect("context");
    let node = context.create_node("short_lived", "/").expect("node");
    let other = context.create_node("stays", "/").expect("node");
    let publisher = node
        .create_publisher::<Time>("t", &Qos::default())
        .expect("publisher");
    drop(publisher);
    drop(node);
    // Only `stays` with no endpoints is left: the peer must end with exactly that message.
    let peer = Peer::start(
        "cyclone_discovery_info.py",
        &[
            (DOMAIN + 1).to_string(),
            "/".into(),
            "stays".into(),
            "0".into(),
            "0".into(),
            "20".into(),
        ],
    )
    .expect("start the Cyclone DDS peer");
    let out = peer.wait(Duration::from_secs(30)).expect("peer output");
    assert_eq!(
        out.code,
        Some(0),
        "peer failed: stdout={} stderr={}",
        out.stdout,
        out.stderr
    );
    let doc: Value = serde_json::from_str(out.stdout.trim()).expect("peer prints JSON");
    let ours = doc["discovery_info"]
        .as_array()
        .and_then(|a| a.iter().find(|p| p["gid"] == context.gid().to_string()))
        .unwrap_or_else(|| panic!("no ros_discovery_info from us in {doc}"));
    let names: Vec<&str> = ours["nodes"]
        .as_array()
        .expect("nodes")
        .iter()
        .filter_map(|n| n["name"].as_str())
        .collect();
    assert_eq!(names, vec!["stays"]);
    drop(other);
}
