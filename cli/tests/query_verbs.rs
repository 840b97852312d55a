//! Output tests of the query verbs — `service list|type|find|info`, `node list|info`,
//! `topic list|info` — against a live graph: real rmw_cyclonedds_cpp nodes (rclpy 7.1.6 on
//! rmw_cyclonedds_cpp 2.2.2, whatever the run's peers use: `interop-tests/peers/jazzy_node.py`,
//! bare: no parameter services, no `~/get_type_description`, no /rosout, only rclpy's
//! /parameter_events publisher beside what each test gives them) and our own nodes in this
//! process. Whole stdout is compared line for
//! line with ros2cli's (Jazzy; Rolling's `service info -v`) format; `--json` output is parsed back.
//!
//! Each test has its own DDS domain. Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test query_verbs`.

mod common;

use std::time::Duration;

use common::{expect, expect_failure, expect_json, expect_stdout, horus, service_qos, topic_qos};
use horus_ros_msgs::builtin_interfaces::msg::{Duration as RosDuration, Time};
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolResponse};
use horus_ros_msgs::{DescriptionBuilder, Message, TypeDescription};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Backend, Context};
use horus_ros_services::{EndpointBuilder, ServiceClient, ServiceServer};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use serde_json::{json, Value};

/// The type hash of the rclpy peers' topics (std_msgs/msg/String).
fn string_hash() -> String {
    StringMsg::type_hash().to_string()
}

/// How long an rclpy peer may take to start.
const PEER_START: Duration = Duration::from_secs(30);

/// A real rmw_cyclonedds_cpp node NAMESPACE/NAME, bare (see the module documentation), with a
/// publisher of `NAMESPACE/chatter` and a subscription of `NAMESPACE/echo` (std_msgs/msg/String,
/// KEEP_LAST 10, RELIABLE, VOLATILE) when `topics`, and an AddTwoInts server of `service` when
/// given. Returned with the GIDs rmw gave its endpoints, as rclpy lists them: the chatter writer
/// (when `topics`), then the server's request reader and reply writer (when a server). It
/// leaves when dropped.
fn rclpy_node(
    domain: u32,
    namespace: &str,
    name: &str,
    topics: bool,
    service: Option<&str>,
) -> (RclpyPeer, Vec<String>) {
    let mut spec = json!({
        "domain": domain, "namespace": namespace, "name": name, "bare": true, "graph": true,
    });
    let chatter = format!("rt{namespace}/chatter");
    let (request, reply) = service
        .map(|s| (format!("rq{s}Request"), format!("rr{s}Reply")))
        .unwrap_or_default();
    let mut endpoints = Vec::new();
    if topics {
        spec["publishers"] = json!([{"topic": format!("{namespace}/chatter"),
                                     "type": "std_msgs/msg/String", "period_s": 1.0}]);
        spec["subscriptions"] = json!([{"topic": format!("{namespace}/echo"),
                                        "type": "std_msgs/msg/String"}]);
        endpoints.push((chatter.as_str(), "publishers"));
    }
    if let Some(service) = service {
        spec["servers"] = json!([{"service": service,
                                  "type": "example_interfaces/srv/AddTwoInts"}]);
        endpoints.push((request.as_str(), "subscriptions"));
        endpoints.push((reply.as_str(), "publishers"));
    }
    let mut peer = RclpyPeer::start_on(Rmw::CycloneDds, &spec).expect("start the rclpy peer");
    let gids = peer
        .own_gids(name, &endpoints, PEER_START)
        .unwrap_or_else(|e| panic!("{e}"));
    (peer, gids.iter().map(ToString::to_string).collect())
}

/// A stand-in for an action's feedback message (`test_msgs/action/Fibonacci_FeedbackMessage`):
/// publishing it on `<action>/_action/feedback` makes a node an action server for rcl_action.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct FibonacciFeedbackMessage {
    sequence: i32,
}

impl Message for FibonacciFeedbackMessage {
    const TYPE_NAME: &'static str = "test_msgs/action/Fibonacci_FeedbackMessage";
    fn type_description() -> TypeDescription {
        DescriptionBuilder::new(Self::TYPE_NAME)
            .field::<i32>("sequence")
            .build()
    }
}

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

/// Endpoints as another process sees them through DDS discovery: on the Cyclone backend the
/// history Cyclone DDS announces and reports (KEEP_LAST `depth`, as `ros2` on rmw_cyclonedds
/// prints it), on rustdds none (UNKNOWN, as on rmw_fastrtps); `service` adds the depth rclpy's
/// `ServiceEndpointInfo` prints beside UNKNOWN. The type hash only where the backend announces
/// USER_DATA (Cyclone; rustdds sends none, shown as INVALID).
fn seen_history(ctx: &Context, depth: u32, service: bool) -> String {
    match (ctx.backend(), service) {
        (Some(Backend::Cyclone), _) => format!("KEEP_LAST ({depth})"),
        (_, false) => "UNKNOWN".to_owned(),
        (_, true) => "UNKNOWN (0)".to_owned(),
    }
}

/// The JSON `history` and `depth` of an endpoint keeping `depth` samples (see [`seen_history`]).
fn seen_history_json(ctx: &Context, depth: u32) -> (Value, Value) {
    match ctx.backend() {
        Some(Backend::Cyclone) => (json!("KEEP_LAST"), json!(depth)),
        _ => (json!("UNKNOWN"), json!(0)),
    }
}

/// Our services' local depths (the services layer's, deeper than the profile asked for) and the
/// rclpy peers' (rmw_qos_profile_services_default, and their topics' KEEP_LAST 10).
const OUR_REQUEST_WRITER_DEPTH: u32 = 256;
const OUR_REPLY_READER_DEPTH: u32 = 4096;
const PEER_DEPTH: u32 = 10;
/// Our topic endpoints' depth (`Qos::default()`: KEEP_LAST 10).
const OUR_TOPIC_DEPTH: u32 = 10;

/// The `Topic type hash` line value for an endpoint of ours announcing `hash`: the hash where
/// the backend announces USER_DATA, else INVALID.
fn ours_hash_text(ctx: &Context, hash: &str) -> String {
    if ctx.capabilities().announces_user_data {
        hash.to_owned()
    } else {
        "INVALID".to_owned()
    }
}

/// The JSON `type_hash` of an endpoint of ours announcing `hash` (null where none is announced).
fn ours_hash_json(ctx: &Context, hash: &str) -> Value {
    if ctx.capabilities().announces_user_data {
        Value::from(hash)
    } else {
        Value::Null
    }
}

#[test]
fn service_verbs() {
    const D: u32 = 101;
    let (_peer, peer) = rclpy_node(D, "/peer_ns", "cyclone_node", true, Some("/add_two_ints"));
    let _hidden = rclpy_node(D, "/", "add_two_ints_server", false, Some("/_private/add"));
    let ctx = context(D);
    let node = ctx.create_node("horus_node", "/").expect("node");
    let server = ServiceServer::<SetBool>::builder()
        .node(&node)
        .name("set_flag")
        .on_request(|_| {
            Ok(SetBoolResponse {
                success: true,
                message: String::new(),
            })
        })
        .build()
        .expect("server");
    let client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/add_two_ints")
        .build()
        .expect("client");
    assert!(client.wait_for_service(Duration::from_secs(8)));

    expect(D, &["service", "list"], "/add_two_ints\n/set_flag\n");
    expect(
        D,
        &["service", "list", "-t"],
        "/add_two_ints [example_interfaces/srv/AddTwoInts]\n/set_flag [std_srvs/srv/SetBool]\n",
    );
    expect(
        D,
        &["service", "list", "--include-hidden-services"],
        "/_private/add\n/add_two_ints\n/set_flag\n",
    );
    expect(D, &["service", "list", "-c"], "2\n");
    expect(
        D,
        &["service", "list", "-c", "--include-hidden-services"],
        "3\n",
    );

    expect(
        D,
        &["service", "type", "/set_flag"],
        "std_srvs/srv/SetBool\n",
    );
    // ros2cli's type verb returns 1 without a message for an unknown (or hidden) service.
    expect_failure(D, &["service", "type", "/_private/add"], "");
    expect_failure(D, &["service", "type", "/nope"], "");
    expect(
        D,
        &[
            "service",
            "type",
            "/_private/add",
            "--include-hidden-services",
        ],
        "example_interfaces/srv/AddTwoInts\n",
    );

    expect(
        D,
        &["service", "find", "example_interfaces/srv/AddTwoInts"],
        "/add_two_ints\n",
    );
    expect(
        D,
        &[
            "service",
            "find",
            "example_interfaces/srv/AddTwoInts",
            "--include-hidden-services",
        ],
        "/_private/add\n/add_two_ints\n",
    );
    expect(
        D,
        &["service", "find", "-c", "example_interfaces/srv/AddTwoInts"],
        "1\n",
    );
    expect(D, &["service", "find", "std_srvs/srv/Empty"], "");

    expect(
        D,
        &["service", "info", "/add_two_ints"],
        "Type: example_interfaces/srv/AddTwoInts\nClients count: 1\nServices count: 1\n",
    );
    expect(
        D,
        &["service", "info", "/set_flag"],
        "Type: std_srvs/srv/SetBool\nClients count: 0\nServices count: 1\n",
    );
    expect_failure(
        D,
        &["service", "info", "/nope"],
        "Unknown service '/nope'\n",
    );
    expect_failure(
        D,
        &["service", "info", "/_private/add"],
        "Unknown service '/_private/add'\n",
    );
    expect(
        D,
        &[
            "service",
            "info",
            "--include-hidden-services",
            "/_private/add",
        ],
        "Type: example_interfaces/srv/AddTwoInts\nClients count: 0\nServices count: 1\n",
    );

    // -v: Rolling's blocks, the client (ours) then the server (the rclpy node's).
    let (request_writer, reply_reader) = client.gids();
    let verbose = format!(
        "Type: example_interfaces/srv/AddTwoInts\n\
         Clients count: 1\n\
         \n\
         Node name: horus_node\n\
         Node namespace: /\n\
         Service type: example_interfaces/srv/AddTwoInts\n\
         Service type hash: INVALID\n\
         Endpoint type: CLIENT\n\
         Endpoint count: 2\n\
         GIDs:\n \
         - Request Writer : {request_writer}\n \
         - Response Reader : {reply_reader}\n\
         QoS profiles:\n \
         - Request Writer :\n{ours_writer} \
         - Response Reader :\n{ours_reader}\
         \n\
         Services count: 1\n\
         \n\
         Node name: cyclone_node\n\
         Node namespace: /peer_ns\n\
         Service type: example_interfaces/srv/AddTwoInts\n\
         Service type hash: INVALID\n\
         Endpoint type: SERVER\n\
         Endpoint count: 2\n\
         GIDs:\n \
         - Request Reader : {request_reader}\n \
         - Response Writer : {reply_writer}\n\
         QoS profiles:\n \
         - Request Reader :\n{theirs} \
         - Response Writer :\n{theirs}\
         \n",
        ours_writer = service_qos(
            "RELIABLE",
            &seen_history(&ctx, OUR_REQUEST_WRITER_DEPTH, true),
            "VOLATILE"
        ),
        ours_reader = service_qos(
            "RELIABLE",
            &seen_history(&ctx, OUR_REPLY_READER_DEPTH, true),
            "VOLATILE"
        ),
        theirs = service_qos(
            "RELIABLE",
            &seen_history(&ctx, PEER_DEPTH, true),
            "VOLATILE"
        ),
        request_reader = peer[1],
        reply_writer = peer[2],
    );
    expect(D, &["service", "info", "/add_two_ints", "-v"], &verbose);

    // --json, parsed back.
    let list = expect_json(D, &["--json", "service", "list"], |doc| {
        doc.as_array().is_some_and(|a| a.len() == 2)
    });
    assert_eq!(
        list,
        json!([
            {"name": "/add_two_ints", "types": ["example_interfaces/srv/AddTwoInts"]},
            {"name": "/set_flag", "types": ["std_srvs/srv/SetBool"]},
        ])
    );
    let count = expect_json(D, &["--json", "service", "list", "-c"], |_| true);
    assert_eq!(count, json!({"count": 2}));
    let ty = expect_json(D, &["--json", "service", "type", "/set_flag"], |_| true);
    assert_eq!(
        ty,
        json!({"name": "/set_flag", "types": ["std_srvs/srv/SetBool"]})
    );
    let found = expect_json(
        D,
        &["--json", "service", "find", "std_srvs/srv/SetBool"],
        |_| true,
    );
    assert_eq!(
        found,
        json!([{"name": "/set_flag", "types": ["std_srvs/srv/SetBool"]}])
    );

    let info = expect_json(D, &["--json", "service", "info", "/add_two_ints"], |doc| {
        doc["clients"].as_array().is_some_and(|a| a.len() == 1)
            && doc["servers"].as_array().is_some_and(|a| a.len() == 1)
    });
    assert_eq!(info["name"], "/add_two_ints");
    assert_eq!(info["types"], json!(["example_interfaces/srv/AddTwoInts"]));
    assert_eq!(
        (
            info["clients_count"].as_u64(),
            info["services_count"].as_u64()
        ),
        (Some(1), Some(1))
    );
    let qos = |reliability: &str, depth: u32| {
        let (history, depth) = seen_history_json(&ctx, depth);
        json!({
            "reliability": reliability, "history": history, "depth": depth,
            "durability": "VOLATILE", "lifespan_ns": null, "deadline_ns": null,
            "liveliness": "AUTOMATIC", "liveliness_lease_duration_ns": null,
        })
    };
    assert_eq!(
        info["clients"][0],
        json!({
            "node_name": "horus_node",
            "node_namespace": "/",
            "type": "example_interfaces/srv/AddTwoInts",
            "type_hash": null,
            "endpoint_type": "CLIENT",
            // rmw's order: reader then writer.
            "gids": [reply_reader.to_string(), request_writer.to_string()],
            "qos": [
                qos("RELIABLE", OUR_REPLY_READER_DEPTH),
                qos("RELIABLE", OUR_REQUEST_WRITER_DEPTH)
            ],
        })
    );
    assert_eq!(
        info["servers"][0],
        json!({
            "node_name": "cyclone_node",
            "node_namespace": "/peer_ns",
            "type": "example_interfaces/srv/AddTwoInts",
            "type_hash": null,
            "endpoint_type": "SERVER",
            "gids": [peer[1], peer[2]],
            "qos": [qos("RELIABLE", PEER_DEPTH), qos("RELIABLE", PEER_DEPTH)],
        })
    );
    // Our server, in JSON: its request reader and reply writer.
    let (request_reader, reply_writer) = server.gids();
    let flag = expect_json(D, &["--json", "service", "info", "/set_flag"], |doc| {
        doc["servers"].as_array().is_some_and(|a| a.len() == 1)
    });
    assert_eq!(
        flag["servers"][0]["gids"],
        json!([request_reader.to_string(), reply_writer.to_string()])
    );
    assert_eq!(flag["clients"], json!([]));
    expect_failure(
        D,
        &["--json", "service", "info", "/nope"],
        "Unknown service '/nope'\n",
    );
}

#[test]
fn node_verbs() {
    const D: u32 = 102;
    let _peer = rclpy_node(D, "/peer_ns", "cyclone_node", true, Some("/add_two_ints"));
    // Two processes with a node of the same name.
    let _twin1 = rclpy_node(D, "/dup", "twin", true, None);
    let _twin2 = rclpy_node(D, "/dup", "twin", true, None);

    let ctx = context(D);
    let node = ctx.create_node("horus_node", "/").expect("node");
    let qos = Qos::default();
    let _chatter = node
        .create_publisher::<Time>("/horus/chatter", &qos)
        .expect("publisher");
    let _listener = node
        .create_subscription::<StringMsg>("/peer_ns/chatter", &qos)
        .expect("subscription");
    let _hidden = node
        .create_publisher::<RosDuration>("/_hidden/topic", &qos)
        .expect("hidden publisher");
    let _action_server = node
        .create_publisher::<FibonacciFeedbackMessage>("/fib/_action/feedback", &qos)
        .expect("feedback publisher");
    let _action_client = node
        .create_subscription::<FibonacciFeedbackMessage>("/other/_action/feedback", &qos)
        .expect("feedback subscription");
    let _server = ServiceServer::<SetBool>::builder()
        .node(&node)
        .name("set_flag")
        .on_request(|_| {
            Ok(SetBoolResponse {
                success: true,
                message: String::new(),
            })
        })
        .build()
        .expect("server");
    let _client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/add_two_ints")
        .build()
        .expect("client");
    // A second node of ours, hidden.
    let _hidden_node = ctx.create_node("_secret", "/").expect("hidden node");

    const DUPLICATES: &str = "WARNING: Be aware that there are nodes in the graph that share an \
                              exact name, which can have unintended side effects.\n";
    let run = expect(
        D,
        &["node", "list"],
        "/dup/twin\n/dup/twin\n/horus_node\n/peer_ns/cyclone_node\n",
    );
    assert_eq!(run.stderr, DUPLICATES);
    // -a adds the hidden nodes: ours and the CLI's own `_horus_ros_<pid>`.
    let run = expect_stdout(D, &["node", "list", "-a"], |run| {
        format!(
            "/_horus_ros_{}\n/_secret\n/dup/twin\n/dup/twin\n/horus_node\n/peer_ns/cyclone_node\n",
            run.pid
        )
    });
    assert_eq!(run.stderr, DUPLICATES);
    expect(D, &["node", "list", "-c"], "4\n");
    expect(D, &["node", "list", "-a", "-c"], "6\n");

    expect(
        D,
        &["node", "info", "/peer_ns/cyclone_node"],
        "/peer_ns/cyclone_node\n\
         \x20 Subscribers:\n\
         \x20   /peer_ns/echo: std_msgs/msg/String\n\
         \x20 Publishers:\n\
         \x20   /parameter_events: rcl_interfaces/msg/ParameterEvent\n\
         \x20   /peer_ns/chatter: std_msgs/msg/String\n\
         \x20 Service Servers:\n\
         \x20   /add_two_ints: example_interfaces/srv/AddTwoInts\n\
         \x20 Service Clients:\n\
         \n\
         \x20 Action Servers:\n\
         \n\
         \x20 Action Clients:\n\
         \n",
    );
    let run = expect(
        D,
        &["node", "info", "/dup/twin"],
        "/dup/twin\n\
         \x20 Subscribers:\n\
         \x20   /dup/echo: std_msgs/msg/String\n\
         \x20 Publishers:\n\
         \x20   /dup/chatter: std_msgs/msg/String\n\
         \x20   /parameter_events: rcl_interfaces/msg/ParameterEvent\n\
         \x20 Service Servers:\n\
         \n\
         \x20 Service Clients:\n\
         \n\
         \x20 Action Servers:\n\
         \n\
         \x20 Action Clients:\n\
         \n",
    );
    assert_eq!(
        run.stderr,
        "There are 2 nodes in the graph with the exact name \"/dup/twin\". You are seeing \
         information about only one of them.\n"
    );
    expect(
        D,
        &["node", "info", "/horus_node"],
        "/horus_node\n\
         \x20 Subscribers:\n\
         \x20   /peer_ns/chatter: std_msgs/msg/String\n\
         \x20 Publishers:\n\
         \x20   /horus/chatter: builtin_interfaces/msg/Time\n\
         \x20 Service Servers:\n\
         \x20   /set_flag: std_srvs/srv/SetBool\n\
         \x20 Service Clients:\n\
         \x20   /add_two_ints: example_interfaces/srv/AddTwoInts\n\
         \x20 Action Servers:\n\
         \x20   /fib: test_msgs/action/Fibonacci\n\
         \x20 Action Clients:\n\
         \x20   /other: test_msgs/action/Fibonacci\n",
    );
    expect(
        D,
        &["node", "info", "/horus_node", "--include-hidden"],
        "/horus_node\n\
         \x20 Subscribers:\n\
         \x20   /other/_action/feedback: test_msgs/action/Fibonacci_FeedbackMessage\n\
         \x20   /peer_ns/chatter: std_msgs/msg/String\n\
         \x20 Publishers:\n\
         \x20   /_hidden/topic: builtin_interfaces/msg/Duration\n\
         \x20   /fib/_action/feedback: test_msgs/action/Fibonacci_FeedbackMessage\n\
         \x20   /horus/chatter: builtin_interfaces/msg/Time\n\
         \x20 Service Servers:\n\
         \x20   /set_flag: std_srvs/srv/SetBool\n\
         \x20 Service Clients:\n\
         \x20   /add_two_ints: example_interfaces/srv/AddTwoInts\n\
         \x20 Action Servers:\n\
         \x20   /fib: test_msgs/action/Fibonacci\n\
         \x20 Action Clients:\n\
         \x20   /other: test_msgs/action/Fibonacci\n",
    );
    expect(
        D,
        &["node", "info", "/_secret", "--include-hidden"],
        "/_secret\n  Subscribers:\n\n  Publishers:\n\n  Service Servers:\n\n  Service Clients:\n\n  \
         Action Servers:\n\n  Action Clients:\n\n",
    );
    expect_failure(
        D,
        &["node", "info", "/_secret"],
        "Unable to find node '/_secret'\n",
    );
    expect_failure(
        D,
        &["node", "info", "/nope"],
        "Unable to find node '/nope'\n",
    );
    // ros2cli compares full names exactly: no leading slash, no match.
    expect_failure(
        D,
        &["node", "info", "peer_ns/cyclone_node"],
        "Unable to find node 'peer_ns/cyclone_node'\n",
    );

    let list = expect_json(D, &["--json", "node", "list"], |doc| {
        doc.as_array().is_some_and(|a| a.len() == 4)
    });
    let names: Vec<(&str, &str, &str)> = list
        .as_array()
        .map(|a| {
            a.iter()
                .map(|n| {
                    (
                        n["full_name"].as_str().unwrap_or(""),
                        n["namespace"].as_str().unwrap_or(""),
                        n["name"].as_str().unwrap_or(""),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    assert_eq!(
        names,
        vec![
            ("/dup/twin", "/dup", "twin"),
            ("/dup/twin", "/dup", "twin"),
            ("/horus_node", "/", "horus_node"),
            ("/peer_ns/cyclone_node", "/peer_ns", "cyclone_node"),
        ]
    );
    assert_eq!(
        expect_json(D, &["--json", "node", "list", "-c"], |_| true),
        json!({"count": 4})
    );
    let info = expect_json(D, &["--json", "node", "info", "/horus_node"], |doc| {
        doc["action_clients"]
            .as_array()
            .is_some_and(|a| a.len() == 1)
    });
    assert_eq!(
        info,
        json!({
            "full_name": "/horus_node",
            "name": "horus_node",
            "namespace": "/",
            "subscribers": [{"name": "/peer_ns/chatter", "types": ["std_msgs/msg/String"]}],
            "publishers": [{"name": "/horus/chatter", "types": ["builtin_interfaces/msg/Time"]}],
            "service_servers": [{"name": "/set_flag", "types": ["std_srvs/srv/SetBool"]}],
            "service_clients": [{"name": "/add_two_ints", "types": ["example_interfaces/srv/AddTwoInts"]}],
            "action_servers": [{"name": "/fib", "types": ["test_msgs/action/Fibonacci"]}],
            "action_clients": [{"name": "/other", "types": ["test_msgs/action/Fibonacci"]}],
        })
    );
    expect_failure(
        D,
        &["--json", "node", "info", "/nope"],
        "Unable to find node '/nope'\n",
    );
}

#[test]
fn topic_verbs() {
    const D: u32 = 103;
    let hash = string_hash();
    let (_peer, peer) = rclpy_node(D, "/peer_ns", "cyclone_node", true, None);
    let ctx = context(D);
    let node = ctx.create_node("horus_node", "/").expect("node");
    let publisher = node
        .create_publisher::<StringMsg>("/peer_ns/chatter", &Qos::default().transient_local())
        .expect("publisher");
    let subscription = node
        .create_subscription::<StringMsg>("/peer_ns/chatter", &Qos::default().best_effort())
        .expect("subscription");
    let _hidden = node
        .create_publisher::<Time>("/_internal/clock", &Qos::default())
        .expect("hidden publisher");

    // The rclpy node's /parameter_events publisher is there too.
    expect(
        D,
        &["topic", "list"],
        "/parameter_events\n/peer_ns/chatter\n/peer_ns/echo\n",
    );
    expect(
        D,
        &["topic", "list", "-t"],
        "/parameter_events [rcl_interfaces/msg/ParameterEvent]\n\
         /peer_ns/chatter [std_msgs/msg/String]\n/peer_ns/echo [std_msgs/msg/String]\n",
    );
    expect(D, &["topic", "list", "-c"], "3\n");
    expect(
        D,
        &["topic", "list", "--include-hidden-topics"],
        "/_internal/clock\n/parameter_events\n/peer_ns/chatter\n/peer_ns/echo\n",
    );
    expect(
        D,
        &["topic", "list", "-v"],
        "Published topics:\n \
         * /parameter_events [rcl_interfaces/msg/ParameterEvent] 1 publisher\n \
         * /peer_ns/chatter [std_msgs/msg/String] 2 publishers\n\
         \n\
         Subscribed topics:\n \
         * /peer_ns/chatter [std_msgs/msg/String] 1 subscriber\n \
         * /peer_ns/echo [std_msgs/msg/String] 1 subscriber\n\
         \n",
    );
    expect(
        D,
        &["topic", "list", "-v", "--include-hidden-topics"],
        "Published topics:\n \
         * /_internal/clock [builtin_interfaces/msg/Time] 1 publisher\n \
         * /parameter_events [rcl_interfaces/msg/ParameterEvent] 1 publisher\n \
         * /peer_ns/chatter [std_msgs/msg/String] 2 publishers\n\
         \n\
         Subscribed topics:\n \
         * /peer_ns/chatter [std_msgs/msg/String] 1 subscriber\n \
         * /peer_ns/echo [std_msgs/msg/String] 1 subscriber\n\
         \n",
    );

    expect(
        D,
        &["topic", "info", "/peer_ns/chatter"],
        "Type: std_msgs/msg/String\nPublisher count: 2\nSubscription count: 1\n",
    );
    // Hidden topics are found without any flag, as in ros2cli.
    expect(
        D,
        &["topic", "info", "/_internal/clock"],
        "Type: builtin_interfaces/msg/Time\nPublisher count: 1\nSubscription count: 0\n",
    );
    expect_failure(D, &["topic", "info", "/nope"], "Unknown topic '/nope'\n");
    expect_failure(
        D,
        &["topic", "info", "peer_ns/chatter"],
        "Unknown topic 'peer_ns/chatter'\n",
    );

    // -v: publishers in GID order (ours and the peer's), then the subscription.
    let theirs_gid = peer[0].clone();
    let theirs = format!(
        "Node name: cyclone_node\nNode namespace: /peer_ns\nTopic type: std_msgs/msg/String\n\
         Topic type hash: {hash}\nEndpoint type: PUBLISHER\nGID: {theirs_gid}\n{}",
        topic_qos(
            "RELIABLE",
            &seen_history(&ctx, PEER_DEPTH, false),
            "VOLATILE"
        )
    );
    // Our endpoints' hash: announced in USER_DATA on Cyclone, absent (INVALID) on rustdds.
    let ours_hash = ours_hash_text(&ctx, &hash);
    let ours = format!(
        "Node name: horus_node\nNode namespace: /\nTopic type: std_msgs/msg/String\n\
         Topic type hash: {ours_hash}\nEndpoint type: PUBLISHER\nGID: {}\n{}",
        publisher.gid(),
        topic_qos(
            "RELIABLE",
            &seen_history(&ctx, OUR_TOPIC_DEPTH, false),
            "TRANSIENT_LOCAL"
        )
    );
    let mut publishers = [
        (theirs_gid.clone(), theirs),
        (publisher.gid().to_string(), ours),
    ];
    publishers.sort();
    let verbose = format!(
        "Type: std_msgs/msg/String\n\nPublisher count: 2\n\n{}\n{}\nSubscription count: 1\n\n\
         Node name: horus_node\nNode namespace: /\nTopic type: std_msgs/msg/String\n\
         Topic type hash: {ours_hash}\nEndpoint type: SUBSCRIPTION\nGID: {}\n{}\n",
        publishers[0].1,
        publishers[1].1,
        subscription.gid(),
        topic_qos(
            "BEST_EFFORT",
            &seen_history(&ctx, OUR_TOPIC_DEPTH, false),
            "VOLATILE"
        ),
    );
    expect(D, &["topic", "info", "/peer_ns/chatter", "-v"], &verbose);

    let list = expect_json(D, &["--json", "topic", "list"], |doc| {
        doc.as_array().is_some_and(|a| a.len() == 3)
    });
    assert_eq!(
        list,
        json!([
            {"name": "/parameter_events", "types": ["rcl_interfaces/msg/ParameterEvent"],
             "publisher_count": 1, "subscription_count": 0},
            {"name": "/peer_ns/chatter", "types": ["std_msgs/msg/String"],
             "publisher_count": 2, "subscription_count": 1},
            {"name": "/peer_ns/echo", "types": ["std_msgs/msg/String"],
             "publisher_count": 0, "subscription_count": 1},
        ])
    );
    assert_eq!(
        expect_json(
            D,
            &["--json", "topic", "list", "-c", "--include-hidden-topics"],
            |_| true
        ),
        json!({"count": 4})
    );
    let info = expect_json(D, &["--json", "topic", "info", "/peer_ns/chatter"], |doc| {
        doc["publishers"].as_array().is_some_and(|a| a.len() == 2)
            && doc["subscriptions"]
                .as_array()
                .is_some_and(|a| a.len() == 1)
    });
    assert_eq!(info["name"], "/peer_ns/chatter");
    assert_eq!(info["types"], json!(["std_msgs/msg/String"]));
    assert_eq!(
        (
            info["publisher_count"].as_u64(),
            info["subscription_count"].as_u64()
        ),
        (Some(2), Some(1))
    );
    let find = |list: &Value, gid: &str| -> Value {
        list.as_array()
            .and_then(|a| a.iter().find(|e| e["gid"] == gid))
            .cloned()
            .unwrap_or(Value::Null)
    };
    assert_eq!(
        find(&info["publishers"], &theirs_gid),
        json!({
            "node_name": "cyclone_node",
            "node_namespace": "/peer_ns",
            "type": "std_msgs/msg/String",
            "type_hash": hash,
            "endpoint_type": "PUBLISHER",
            "gid": theirs_gid,
            "qos": {
                "reliability": "RELIABLE", "history": seen_history_json(&ctx, PEER_DEPTH).0,
                "depth": seen_history_json(&ctx, PEER_DEPTH).1,
                "durability": "VOLATILE", "lifespan_ns": null, "deadline_ns": null,
                "liveliness": "AUTOMATIC", "liveliness_lease_duration_ns": null,
            },
        })
    );
    let sub = &info["subscriptions"][0];
    assert_eq!(sub["gid"], subscription.gid().to_string());
    assert_eq!(sub["node_name"], "horus_node");
    assert_eq!(sub["endpoint_type"], "SUBSCRIPTION");
    assert_eq!(sub["type_hash"], ours_hash_json(&ctx, &hash));
    assert_eq!(sub["qos"]["reliability"], "BEST_EFFORT");
    let ours = find(&info["publishers"], &publisher.gid().to_string());
    assert_eq!(ours["qos"]["durability"], "TRANSIENT_LOCAL");
    assert_eq!(ours["type_hash"], ours_hash_json(&ctx, &hash));
    expect_failure(
        D,
        &["--json", "topic", "info", "/nope"],
        "Unknown topic '/nope'\n",
    );
    // Nothing at all on an empty domain.
    let empty = horus(D + 10, &["topic", "list", "-v"]);
    assert_eq!((empty.code, empty.stdout.as_str()), (Some(0), ""));
}
