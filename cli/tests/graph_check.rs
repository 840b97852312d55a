//! `horus-ros graph check`, run as the binary against live graphs where each finding is
//! provoked: our own nodes (in this process, on the backend HORUS_ROS_BACKEND names, or on
//! Cyclone DDS where the finding needs it), real rclpy nodes on Fast DDS
//! (`tests/peers/jazzy_set_bool.py`, `tests/peers/jazzy_qos_endpoint.py`) and a bare Cyclone
//! DDS participant (`tests/peers/bare_participant.py`).
//!
//! Every test joins its own domain (171-178), so they run in parallel; run them inside the
//! private network namespace (`scripts/isolated cargo test …`).

mod common;

use std::time::Duration;

use common::Peer;
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::std_srvs::srv::SetBool;
use horus_ros_msgs::{Message, TypeHash};
use horus_ros_rmw::qos::{LivelinessPolicy, Qos, ReliabilityPolicy};
use horus_ros_rmw::{Backend, Context, RawEndpointSpec};
use horus_ros_services::prelude::*;
use serde_json::Value;

/// `--spin-time` given to the CLI (it stops earlier once the graph is complete and quiet).
const SPIN_TIME: &str = "2";

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

/// A context on Cyclone DDS (a participant of vendor Cyclone DDS, endpoints announcing their
/// type hashes in USER_DATA), whatever HORUS_ROS_BACKEND says.
fn cyclone_context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .backend(Backend::Cyclone)
        .build()
        .expect("Cyclone DDS context")
}

/// `horus-ros --no-daemon --spin-time 2 graph check ARGS…`.
fn check(domain: u32, args: &[&str]) -> common::Run {
    let mut all = vec!["--spin-time", SPIN_TIME, "graph", "check"];
    all.extend_from_slice(args);
    common::horus(domain, &all)
}

/// Runs `graph check --json` once (it answers on the settled graph: every endpoint discovered
/// and listed by its node) and returns its document and run; asserts exit status 1.
fn findings(domain: u32) -> (Value, common::Run) {
    let run = check(domain, &["--json"]);
    let doc: Value = serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("graph check --json printed invalid JSON ({e}): {run:?}"));
    assert_eq!(run.code, Some(1), "exit status with findings: {run:?}");
    (doc, run)
}

/// The finding of `kind` about `subject` in a `graph check --json` document (asserted there,
/// with its summary and fix).
fn finding_in(doc: &Value, run: &common::Run, kind: &str, subject: &str) -> Value {
    let finding = doc["findings"]
        .as_array()
        .unwrap_or_else(|| panic!("no findings list: {doc}"))
        .iter()
        .find(|f| f["kind"] == kind && f["subject"] == subject)
        .cloned()
        .unwrap_or_else(|| {
            panic!(
                "no {kind} finding about {subject}: {doc:#}\nstderr: {}",
                run.stderr
            )
        });
    for key in ["summary", "fix"] {
        assert!(
            finding[key].as_str().is_some_and(|s| !s.is_empty()),
            "{key}: {finding}"
        );
    }
    finding
}

/// Runs `graph check --json` once; asserts exit status 1 and a finding of `kind` about
/// `subject`, and returns it.
fn expect_finding(domain: u32, kind: &str, subject: &str) -> Value {
    let (doc, run) = findings(domain);
    finding_in(&doc, &run, kind, subject)
}

/// The GIDs of a finding's endpoints.
fn gids(finding: &Value) -> Vec<String> {
    finding["endpoints"]
        .as_array()
        .unwrap_or_else(|| panic!("endpoints: {finding}"))
        .iter()
        .map(|e| e["gid"].as_str().expect("gid").to_owned())
        .collect()
}

fn why(finding: &Value) -> Vec<String> {
    finding["why"]
        .as_array()
        .unwrap_or_else(|| panic!("why: {finding}"))
        .iter()
        .map(|w| w.as_str().expect("a string").to_owned())
        .collect()
}

#[test]
fn qos_incompatibilities_are_found_with_the_change_to_make() {
    const DOMAIN: u32 = 171;
    let ctx = context(DOMAIN);
    let talker = ctx.create_node("talker", "/qos").expect("node");
    let listener = ctx.create_node("listener", "/qos").expect("node");
    let default = Qos::default();
    let cases: [(&str, Qos, Qos, &str, &str); 4] = [
        (
            "reliability",
            default.best_effort(),
            default.reliable(),
            "Best effort publisher and reliable subscription",
            "make the subscription BEST_EFFORT or the publisher RELIABLE",
        ),
        (
            "durability",
            default.volatile(),
            default.transient_local(),
            "Volatile publisher and transient local subscription",
            "make the subscription VOLATILE or the publisher TRANSIENT_LOCAL",
        ),
        (
            "deadline",
            default,
            default.with_deadline(Duration::from_secs(1)),
            // A publisher without a deadline announces an infinite one.
            "Subscription deadline is less than publisher deadline",
            "give the publisher a deadline of at most 1 s or remove the subscription's deadline",
        ),
        (
            "liveliness",
            default.with_liveliness(LivelinessPolicy::Automatic),
            default.with_liveliness(LivelinessPolicy::ManualByTopic),
            "Publisher's liveliness is automatic and subscription's is manual by topic",
            "make the subscription's liveliness AUTOMATIC or the publisher's MANUAL_BY_TOPIC",
        ),
    ];
    let mut publishers = Vec::new();
    let mut subscriptions = Vec::new();
    let mut keep = Vec::new();
    for (topic, pub_qos, sub_qos, _, _) in &cases {
        let publisher = talker
            .create_publisher::<Time>(topic, pub_qos)
            .expect("publisher");
        let subscription = listener
            .create_subscription::<Time>(topic, sub_qos)
            .expect("subscription");
        keep.push((publisher.gid(), subscription.gid()));
        publishers.push(publisher);
        subscriptions.push(subscription);
    }
    let (doc, run) = findings(DOMAIN);
    for ((topic, _, _, reason, fix), (publisher, subscription)) in cases.iter().zip(&keep) {
        let finding = finding_in(&doc, &run, "qos_incompatible", &format!("/qos/{topic}"));
        assert_eq!(why(&finding), [*reason], "{finding:#}");
        assert_eq!(finding["fix"], *fix, "{finding:#}");
        assert_eq!(
            gids(&finding),
            [publisher.to_string(), subscription.to_string()]
        );
        assert_eq!(finding["endpoints"][0]["node"], "/qos/talker");
        assert_eq!(finding["endpoints"][0]["role"], "publisher");
        assert_eq!(finding["endpoints"][1]["node"], "/qos/listener");
        assert_eq!(finding["endpoints"][1]["role"], "subscription");
    }
    // The text: one block a finding, a summary line, exit status 1.
    let run = check(DOMAIN, &[]);
    assert_eq!(run.code, Some(1), "{run:?}");
    assert!(
        run.stdout.contains(&format!(
            "    - publisher /qos/reliability  node /qos/talker  gid {}",
            keep[0].0
        )),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("    fix: make the subscription BEST_EFFORT or the publisher RELIABLE\n"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.ends_with(
            "4 findings: 4 QoS incompatibilities (2 nodes, 4 topics, 0 services checked)\n"
        ),
        "{}",
        run.stdout
    );
}

#[test]
fn different_type_hashes_on_one_topic_are_found() {
    const DOMAIN: u32 = 172;
    // Cyclone DDS announces each endpoint's type hash in USER_DATA (as rmw_cyclonedds does).
    let ctx = cyclone_context(DOMAIN);
    let node = ctx.create_node("hashes", "/check").expect("node");
    let spec = |type_hash: TypeHash| RawEndpointSpec {
        dds_topic_name: "rt/check/stamp".to_owned(),
        dds_type_name: Time::dds_type_name(),
        type_hash,
        qos: Qos::default(),
        service_id: None,
    };
    let other = TypeHash::parse(&format!("RIHS01_{}", "ab".repeat(32))).expect("hash");
    let right = node
        .create_raw_writer(&spec(Time::type_hash()))
        .expect("writer");
    let wrong = node.create_raw_writer(&spec(other)).expect("writer");
    let finding = expect_finding(DOMAIN, "type_hash_mismatch", "/check/stamp");
    let mut expected = vec![right.gid().to_string(), wrong.gid().to_string()];
    let mut got = gids(&finding);
    expected.sort();
    got.sort();
    assert_eq!(got, expected, "{finding:#}");
    let hashes: Vec<&str> = finding["endpoints"]
        .as_array()
        .expect("endpoints")
        .iter()
        .map(|e| e["type_hash"].as_str().expect("a hash"))
        .collect();
    assert!(
        hashes.contains(&Time::type_hash().to_string().as_str()),
        "{finding:#}"
    );
    assert!(hashes.contains(&other.to_string().as_str()), "{finding:#}");
}

#[test]
fn a_cyclone_dds_client_of_a_fast_dds_server_is_found() {
    const DOMAIN: u32 = 173;
    // A real rclpy server on rmw_fastrtps (Fast DDS).
    let server = Peer::start_path(
        &common::cli_peer_script("jazzy_set_bool.py"),
        &[
            &DOMAIN.to_string(),
            "setter",
            "/check/set_bool",
            common::LINGER,
        ],
        Duration::from_secs(20),
    );
    assert_eq!(server.field("/node"), "/setter");
    // A client on Cyclone DDS: the rmw_cyclonedds convention (ros2/rmw_cyclonedds#184).
    let ctx = cyclone_context(DOMAIN);
    let node = ctx.create_node("caller", "/check").expect("node");
    let client = ServiceClient::<SetBool>::builder()
        .node(&node)
        .name("/check/set_bool")
        .build()
        .expect("client");
    let finding = expect_finding(DOMAIN, "service_wire_convention", "/check/set_bool");
    let (request_writer, _) = client.gids();
    let endpoints = finding["endpoints"].as_array().expect("endpoints");
    assert_eq!(endpoints.len(), 2, "{finding:#}");
    assert_eq!(endpoints[0]["gid"], request_writer.to_string());
    assert_eq!(endpoints[0]["vendor"], "Cyclone DDS");
    assert_eq!(endpoints[0]["node"], "/check/caller");
    assert_eq!(endpoints[1]["vendor"], "Fast DDS");
    assert_eq!(endpoints[1]["node"], "/setter");
    assert_eq!(endpoints[1]["role"], "service_server");
    assert!(
        why(&finding)[0].contains("ros2/rmw_cyclonedds#184"),
        "{finding:#}"
    );
}

#[test]
fn duplicate_node_names_are_found() {
    const DOMAIN: u32 = 174;
    let first = context(DOMAIN);
    let second = context(DOMAIN);
    let a = first.create_node("twin", "/check").expect("node");
    let b = second.create_node("twin", "/check").expect("node");
    let pa = a
        .create_publisher::<Time>("from_a", &Qos::default())
        .expect("publisher");
    let pb = b
        .create_publisher::<Time>("from_b", &Qos::default())
        .expect("publisher");
    let finding = expect_finding(DOMAIN, "duplicate_node_name", "/check/twin");
    let mut got = gids(&finding);
    let mut expected = vec![pa.gid().to_string(), pb.gid().to_string()];
    got.sort();
    expected.sort();
    assert_eq!(got, expected, "{finding:#}");
}

#[test]
fn a_participant_that_announces_no_node_is_found_with_its_endpoints() {
    const DOMAIN: u32 = 175;
    // A bare Cyclone DDS application: a writer and a reader on `bare_chatter`, no
    // ros_discovery_info.
    let bare = Peer::start_path(
        &common::cli_peer_script("bare_participant.py"),
        &[&DOMAIN.to_string(), "plain", common::LINGER],
        common::PEER_START,
    );
    let participant = bare.field("/gid");
    let finding = expect_finding(DOMAIN, "participant_without_nodes", &participant);
    let endpoints = finding["endpoints"].as_array().expect("endpoints");
    assert_eq!(endpoints.len(), 2, "{finding:#}");
    for e in endpoints {
        assert_eq!(e["participant"], participant.as_str(), "{finding:#}");
        assert_eq!(e["dds_topic"], "bare_chatter", "{finding:#}");
        assert_eq!(e["node"], Value::Null, "{finding:#}");
        assert_eq!(e["vendor"], "Cyclone DDS", "{finding:#}");
    }
}

#[test]
fn a_client_without_server_is_found() {
    const DOMAIN: u32 = 176;
    let ctx = context(DOMAIN);
    let node = ctx.create_node("lonely", "/check").expect("node");
    let client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/check/nobody")
        .build()
        .expect("client");
    // A server of the same type under another name: the fix names it.
    let elsewhere = ctx.create_node("adder", "/check").expect("node");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&elsewhere)
        .name("/check/add")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let finding = expect_finding(DOMAIN, "client_without_server", "/check/nobody");
    let (request_writer, _) = client.gids();
    assert_eq!(gids(&finding), [request_writer.to_string()]);
    assert_eq!(
        finding["fix"],
        "start a server of /check/nobody (example_interfaces/srv/AddTwoInts), or point the \
         client at the right name (namespace, remapping); servers of \
         example_interfaces/srv/AddTwoInts run as /check/add"
    );
}

#[test]
fn a_clean_graph_exits_zero() {
    const DOMAIN: u32 = 177;
    let ctx = context(DOMAIN);
    let talker = ctx.create_node("talker", "/clean").expect("node");
    let listener = ctx.create_node("listener", "/clean").expect("node");
    let qos = Qos::default().with_reliability(ReliabilityPolicy::Reliable);
    let _publisher = talker
        .create_publisher::<Time>("chatter", &qos)
        .expect("publisher");
    let _subscription = listener
        .create_subscription::<Time>("chatter", &qos.best_effort())
        .expect("subscription");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&talker)
        .name("add")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let _client = ServiceClient::<AddTwoInts>::builder()
        .node(&listener)
        .name("add")
        .build()
        .expect("client");
    // Discovery settles before the answer: no transient finding (a client seen before its
    // server), the first run is the answer.
    let run = check(DOMAIN, &[]);
    assert_eq!(
        (run.code, run.stdout.as_str()),
        (
            Some(0),
            "No findings (2 nodes, 1 topic, 1 service checked)\n"
        ),
        "{run:?}"
    );
    let run = check(DOMAIN, &["--json"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    let doc: Value = serde_json::from_str(&run.stdout).expect("JSON");
    assert_eq!(doc["findings"], Value::Array(Vec::new()), "{doc}");
    assert_eq!(doc["domain_id"], DOMAIN);
}

#[test]
fn an_rclpy_best_effort_volatile_publisher_with_a_reliable_transient_local_subscription() {
    const DOMAIN: u32 = 178;
    // A real rclpy publisher on Fast DDS: BEST_EFFORT, VOLATILE.
    let talker = Peer::start_path(
        &common::cli_peer_script("jazzy_qos_endpoint.py"),
        &[
            &DOMAIN.to_string(),
            "rclpy_talker",
            "/rclpy_qos/chatter",
            "pub",
            "best_effort",
            "volatile",
            common::LINGER,
        ],
        Duration::from_secs(20),
    );
    assert_eq!(talker.field("/node"), "/rclpy_talker");
    // Our subscription: RELIABLE, TRANSIENT_LOCAL.
    let ctx = context(DOMAIN);
    let node = ctx.create_node("listener", "/rclpy_qos").expect("node");
    let subscription = node
        .create_subscription::<horus_ros_msgs::std_msgs::msg::String>(
            "chatter",
            &Qos::default().reliable().transient_local(),
        )
        .expect("subscription");
    let finding = expect_finding(DOMAIN, "qos_incompatible", "/rclpy_qos/chatter");
    assert_eq!(
        why(&finding),
        [
            "Best effort publisher and reliable subscription",
            "Volatile publisher and transient local subscription"
        ],
        "{finding:#}"
    );
    assert_eq!(
        finding["fix"],
        "make the subscription BEST_EFFORT or the publisher RELIABLE; make the subscription \
         VOLATILE or the publisher TRANSIENT_LOCAL"
    );
    let endpoints = finding["endpoints"].as_array().expect("endpoints");
    assert_eq!(endpoints[0]["node"], "/rclpy_talker", "{finding:#}");
    assert_eq!(endpoints[0]["vendor"], "Fast DDS", "{finding:#}");
    assert_eq!(endpoints[0]["qos"]["reliability"], "BEST_EFFORT");
    assert_eq!(endpoints[1]["gid"], subscription.gid().to_string());
}
