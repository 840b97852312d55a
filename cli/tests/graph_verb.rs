//! `horus-ros graph`, `graph --watch` and `completions`, run as the binary against a live graph:
//! our own nodes (in this process) and a real rmw_cyclonedds_cpp node (rclpy 7.1.6 on
//! rmw_cyclonedds_cpp 2.2.2, whatever the run's peers use: `interop-tests/peers/jazzy_node.py`).
//!
//! Every test joins its own domain (131-139), so they run in parallel; run them inside the
//! private network namespace (`scripts/test`, or `scripts/isolated cargo test …`).

mod common;

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::Streaming;

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Backend, Context, Gid};
use horus_ros_services::prelude::*;
use horus_ros_test_support::jazzy::Rmw;
use horus_ros_test_support::{wait_exit, wait_with_output};
use interop_tests::peers::RclpyPeer;
use serde_json::{json, Value};

/// The longest wait for anything to appear.
const WAIT: Duration = Duration::from_secs(20);
/// `--spin-time` given to the CLI (it stops earlier once the graph is quiet).
const SPIN_TIME: &str = "3";

// ---------------------------------------------------------------------------------------------
// Helpers.

/// A real rmw_cyclonedds_cpp node NAMESPACE/NODE, bare (no parameter services, no
/// `~/get_type_description`, no /rosout; rclpy's /parameter_events publisher stays), with a
/// publisher of `NAMESPACE/chatter` and a subscription of `NAMESPACE/echo` (std_msgs/msg/String,
/// KEEP_LAST 10, RELIABLE, VOLATILE) and an AddTwoInts server of `service`. Returned with the
/// GIDs rmw gave its endpoints, as rclpy lists them: the chatter writer, the echo reader, the
/// server's request reader and reply writer, the /parameter_events writer. It leaves when
/// dropped.
fn rclpy_peer(domain: u32, namespace: &str, node: &str, service: &str) -> (RclpyPeer, Vec<String>) {
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({
            "domain": domain, "namespace": namespace, "name": node, "bare": true,
            "publishers": [{"topic": format!("{namespace}/chatter"),
                            "type": "std_msgs/msg/String", "period_s": 1.0}],
            "subscriptions": [{"topic": format!("{namespace}/echo"),
                               "type": "std_msgs/msg/String"}],
            "servers": [{"service": service, "type": "example_interfaces/srv/AddTwoInts"}],
            "graph": true,
        }),
    )
    .expect("start the rclpy peer");
    let (chatter, echo) = (
        format!("rt{namespace}/chatter"),
        format!("rt{namespace}/echo"),
    );
    let (request, reply) = (format!("rq{service}Request"), format!("rr{service}Reply"));
    let gids = peer
        .own_gids(
            node,
            &[
                (&chatter, "publishers"),
                (&echo, "subscriptions"),
                (&request, "subscriptions"),
                (&reply, "publishers"),
                ("rt/parameter_events", "publishers"),
            ],
            WAIT,
        )
        .unwrap_or_else(|e| panic!("{e}"));
    (peer, gids.iter().map(ToString::to_string).collect())
}

fn horus_ros() -> Command {
    Command::new(env!("CARGO_BIN_EXE_horus-ros"))
}

/// What a finished run of the CLI printed.
#[derive(Debug)]
struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs `horus-ros --domain-id DOMAIN --spin-time 3 ARGS…`, killed if it runs past [`WAIT`].
fn run(domain: u32, args: &[&str]) -> Run {
    let mut command = horus_ros();
    command
        .args(["--domain-id", &domain.to_string(), "--spin-time", SPIN_TIME])
        // Its own discovery: no daemon used or started.
        .arg("--no-daemon")
        .args(args);
    run_command(command)
}

fn run_command(mut command: Command) -> Run {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start horus-ros");
    let out = wait_with_output(&mut child, WAIT).expect("wait for horus-ros");
    Run {
        code: out.code(),
        stdout: out.stdout,
        stderr: out.stderr,
    }
}

/// Waits for `child` at most `limit` (then kills it): its exit code, `None` if killed.
fn wait_bounded(child: &mut Child, limit: Duration) -> Option<i32> {
    wait_exit(child, limit)
        .expect("wait")
        .and_then(|s| s.code())
}

/// Runs the CLI until its stdout is `expected` (discovery by a fresh process may need a few
/// tries), at most [`WAIT`]; returns the last run.
fn run_until(domain: u32, args: &[&str], mut done: impl FnMut(&Run) -> bool) -> Run {
    let deadline = Instant::now() + WAIT;
    loop {
        let out = run(domain, args);
        if done(&out) || Instant::now() >= deadline {
            return out;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

/// The history line value of an endpoint keeping `depth` samples as another process sees it: on
/// the Cyclone backend the history Cyclone DDS announces (as rmw_cyclonedds), on rustdds none
/// (as rmw_fastrtps).
fn seen_history(ctx: &Context, depth: u32) -> String {
    if ctx.backend() == Some(Backend::Cyclone) {
        format!("KEEP_LAST ({depth})")
    } else {
        "UNKNOWN".to_owned()
    }
}

/// The JSON `type_hash` of an endpoint of ours of type Time: announced in USER_DATA by a backend
/// that announces it (Cyclone), else none (rustdds: null).
fn ours_time_hash(ctx: &Context) -> Value {
    if ctx.capabilities().announces_user_data {
        Value::from(Time::type_hash().to_string())
    } else {
        Value::Null
    }
}

fn strings(v: &Value) -> Vec<String> {
    v.as_array()
        .unwrap_or_else(|| panic!("an array: {v}"))
        .iter()
        .map(|s| {
            s.as_str()
                .unwrap_or_else(|| panic!("a string: {s}"))
                .to_owned()
        })
        .collect()
}

/// Asserts every field of the QoS schema is there with its JSON type.
fn check_qos(qos: &Value, reliability: &str, durability: &str) {
    assert_eq!(qos["reliability"], reliability, "{qos}");
    assert_eq!(qos["durability"], durability, "{qos}");
    assert!(qos["history"].is_string(), "{qos}");
    assert!(qos["depth"].is_u64(), "{qos}");
    assert!(qos["liveliness"].is_string(), "{qos}");
    for key in ["lifespan_ns", "deadline_ns", "liveliness_lease_duration_ns"] {
        assert!(qos[key].is_null() || qos[key].is_i64(), "{key}: {qos}");
    }
    assert_eq!(qos.as_object().map(|o| o.len()), Some(8), "{qos}");
}

// ---------------------------------------------------------------------------------------------
// graph, graph --json.

#[test]
fn graph_prints_the_whole_live_graph_as_text_and_json() {
    const DOMAIN: u32 = 131;
    let ctx = context(DOMAIN);
    let talker = ctx.create_node("talker", "/graph_test").expect("node");
    let chatter = talker
        .create_publisher::<Time>("chatter", &Qos::default())
        .expect("publisher");
    let echo = talker
        .create_subscription::<Time>("echo", &Qos::default())
        .expect("subscription");
    let hidden = talker
        .create_publisher::<Time>("_hidden", &Qos::default())
        .expect("hidden publisher");
    let adder = ctx.create_node("adder", "/graph_test").expect("node");
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&adder)
        .name("add")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let caller = ctx.create_node("caller", "/graph_test").expect("node");
    let client = ServiceClient::<AddTwoInts>::builder()
        .node(&caller)
        .name("add")
        .build()
        .expect("client");
    let (peer, peer_gids) = rclpy_peer(DOMAIN, "/cyc", "peer", "/cyc/add");

    let (server_reader, server_writer) = server.gids();
    let (client_writer, client_reader) = client.gids();
    let g = |gid: Gid| gid.to_string();
    let expected = format!(
        "\
Domain 131: 4 nodes, 5 topics, 2 services

Nodes:
  /cyc/peer
    Subscribers:
      /cyc/echo: std_msgs/msg/String
    Publishers:
      /cyc/chatter: std_msgs/msg/String
      /parameter_events: rcl_interfaces/msg/ParameterEvent
    Service Servers:
      /cyc/add: example_interfaces/srv/AddTwoInts
  /graph_test/adder
    Service Servers:
      /graph_test/add: example_interfaces/srv/AddTwoInts
  /graph_test/caller
    Service Clients:
      /graph_test/add: example_interfaces/srv/AddTwoInts
  /graph_test/talker
    Subscribers:
      /graph_test/echo: builtin_interfaces/msg/Time
    Publishers:
      /graph_test/chatter: builtin_interfaces/msg/Time

Topics:
  /cyc/chatter: std_msgs/msg/String
    Publishers (1):
      /cyc/peer  gid {peer_writer}  RELIABLE, VOLATILE, {history}
    Subscriptions (0):
  /cyc/echo: std_msgs/msg/String
    Publishers (0):
    Subscriptions (1):
      /cyc/peer  gid {peer_reader}  RELIABLE, VOLATILE, {history}
  /graph_test/chatter: builtin_interfaces/msg/Time
    Publishers (1):
      /graph_test/talker  gid {chatter}  RELIABLE, VOLATILE, {history}
    Subscriptions (0):
  /graph_test/echo: builtin_interfaces/msg/Time
    Publishers (0):
    Subscriptions (1):
      /graph_test/talker  gid {echo}  RELIABLE, VOLATILE, {history}
  /parameter_events: rcl_interfaces/msg/ParameterEvent
    Publishers (1):
      /cyc/peer  gid {peer_events}  RELIABLE, VOLATILE, {events_history}
    Subscriptions (0):

Services:
  /cyc/add: example_interfaces/srv/AddTwoInts
    Servers (1):
      /cyc/peer  gids {peer_request_reader}, {peer_reply_writer}
    Clients (0):
  /graph_test/add: example_interfaces/srv/AddTwoInts
    Servers (1):
      /graph_test/adder  gids {server_reader}, {server_writer}
    Clients (1):
      /graph_test/caller  gids {client_reader}, {client_writer}
",
        // Every endpoint here keeps 10 samples but rclpy's /parameter_events writer (1000,
        // qos_profile_parameter_events); the Cyclone backend reports the history Cyclone DDS
        // announces (as rmw_cyclonedds), rustdds none (as rmw_fastrtps).
        history = seen_history(&ctx, 10),
        events_history = seen_history(&ctx, 1000),
        peer_writer = peer_gids[0],
        peer_reader = peer_gids[1],
        peer_request_reader = peer_gids[2],
        peer_reply_writer = peer_gids[3],
        peer_events = peer_gids[4],
        chatter = g(chatter.gid()),
        echo = g(echo.gid()),
        server_reader = g(server_reader),
        server_writer = g(server_writer),
        client_reader = g(client_reader),
        client_writer = g(client_writer),
    );

    // Text: the whole stdout, line for line.
    let text = run_until(DOMAIN, &["graph"], |r| r.stdout == expected);
    assert_eq!(text.code, Some(0), "stderr: {}", text.stderr);
    assert_eq!(text.stdout, expected);

    // JSON: parsed back and checked against the same graph.
    let json = run_until(DOMAIN, &["--json", "graph"], |r| {
        // Complete once every node, endpoint, server and client is there (as in the text).
        let len = |v: &Value| v.as_array().map_or(0, Vec::len);
        serde_json::from_str::<Value>(&r.stdout).is_ok_and(|v| {
            len(&v["nodes"]) == 4
                && len(&v["topics"]) == 5
                && v["topics"].as_array().is_some_and(|topics| {
                    topics
                        .iter()
                        .all(|t| len(&t["publishers"]) + len(&t["subscriptions"]) == 1)
                })
                && len(&v["services"]) == 2
                && len(&v["services"][0]["servers"]) == 1
                && len(&v["services"][1]["servers"]) == 1
                && len(&v["services"][1]["clients"]) == 1
        })
    });
    assert_eq!(json.code, Some(0), "stderr: {}", json.stderr);
    let doc: Value = serde_json::from_str(&json.stdout).expect("graph --json is JSON");
    assert_eq!(doc["domain_id"], DOMAIN);
    let nodes = doc["nodes"].as_array().expect("nodes");
    let full_names: Vec<&str> = nodes
        .iter()
        .map(|n| n["full_name"].as_str().unwrap_or(""))
        .collect();
    assert_eq!(
        full_names,
        [
            "/cyc/peer",
            "/graph_test/adder",
            "/graph_test/caller",
            "/graph_test/talker"
        ]
    );
    let talker_doc = &nodes[3];
    assert_eq!(talker_doc["name"], "talker");
    assert_eq!(talker_doc["namespace"], "/graph_test");
    // Enclaves come from participant USER_DATA: ours is announced and read on Cyclone (the CLI
    // runs on the same backend, from HORUS_ROS_BACKEND), neither on rustdds; rmw_cyclonedds
    // announces its own (`enclave=/;`), read on Cyclone only.
    let enclave = if ctx.capabilities().announces_user_data {
        Value::from("/")
    } else {
        Value::Null
    };
    assert_eq!(talker_doc["enclave"], enclave, "{talker_doc}");
    assert_eq!(nodes[0]["enclave"], enclave, "{}", nodes[0]);
    assert_eq!(talker_doc["publishers"][0]["name"], "/graph_test/chatter");
    assert_eq!(
        strings(&talker_doc["publishers"][0]["types"]),
        ["builtin_interfaces/msg/Time"]
    );
    assert_eq!(talker_doc["publishers"].as_array().map(Vec::len), Some(1));
    assert_eq!(talker_doc["subscribers"][0]["name"], "/graph_test/echo");
    for key in [
        "service_servers",
        "service_clients",
        "action_servers",
        "action_clients",
    ] {
        assert_eq!(talker_doc[key], Value::Array(Vec::new()), "{key}");
    }
    assert_eq!(nodes[1]["service_servers"][0]["name"], "/graph_test/add");
    assert_eq!(nodes[2]["service_clients"][0]["name"], "/graph_test/add");

    let topics = doc["topics"].as_array().expect("topics");
    let chatter_doc = &topics[2];
    assert_eq!(chatter_doc["name"], "/graph_test/chatter");
    assert_eq!(
        strings(&chatter_doc["types"]),
        ["builtin_interfaces/msg/Time"]
    );
    assert_eq!(chatter_doc["publisher_count"], 1);
    assert_eq!(chatter_doc["subscription_count"], 0);
    let publisher = &chatter_doc["publishers"][0];
    assert_eq!(publisher["node_name"], "talker");
    assert_eq!(publisher["node_namespace"], "/graph_test");
    assert_eq!(publisher["type"], "builtin_interfaces/msg/Time");
    // Our endpoints carry the hash in USER_DATA only on a backend that announces it; the
    // peer's always do.
    assert_eq!(publisher["type_hash"], ours_time_hash(&ctx), "{publisher}");
    assert_eq!(publisher["endpoint_type"], "PUBLISHER");
    assert_eq!(publisher["gid"], g(chatter.gid()));
    check_qos(&publisher["qos"], "RELIABLE", "VOLATILE");
    let peer_publisher = &topics[0]["publishers"][0];
    assert_eq!(peer_publisher["node_name"], "peer");
    assert_eq!(peer_publisher["node_namespace"], "/cyc");
    assert_eq!(peer_publisher["gid"], peer_gids[0]);
    assert_eq!(
        peer_publisher["type_hash"],
        StringMsg::type_hash().to_string()
    );
    let subscription = &topics[3]["subscriptions"][0];
    assert_eq!(subscription["endpoint_type"], "SUBSCRIPTION");
    assert_eq!(subscription["gid"], g(echo.gid()));
    check_qos(&subscription["qos"], "RELIABLE", "VOLATILE");

    let services = doc["services"].as_array().expect("services");
    let add = &services[1];
    assert_eq!(add["name"], "/graph_test/add");
    assert_eq!(
        strings(&add["types"]),
        ["example_interfaces/srv/AddTwoInts"]
    );
    assert_eq!(add["services_count"], 1);
    assert_eq!(add["clients_count"], 1);
    let server_doc = &add["servers"][0];
    assert_eq!(server_doc["node_name"], "adder");
    assert_eq!(server_doc["node_namespace"], "/graph_test");
    assert_eq!(server_doc["type"], "example_interfaces/srv/AddTwoInts");
    assert_eq!(server_doc["endpoint_type"], "SERVER");
    assert_eq!(
        strings(&server_doc["gids"]),
        [g(server_reader), g(server_writer)]
    );
    let server_qos = server_doc["qos"].as_array().expect("qos list");
    assert_eq!(server_qos.len(), 2);
    for qos in server_qos {
        check_qos(qos, "RELIABLE", "VOLATILE");
    }
    let client_doc = &add["clients"][0];
    assert_eq!(client_doc["node_name"], "caller");
    assert_eq!(client_doc["endpoint_type"], "CLIENT");
    assert_eq!(
        strings(&client_doc["gids"]),
        [g(client_reader), g(client_writer)]
    );
    let peer_server = &services[0]["servers"][0];
    assert_eq!(peer_server["node_name"], "peer");
    assert_eq!(
        strings(&peer_server["gids"]),
        [peer_gids[2].clone(), peer_gids[3].clone()]
    );

    // -a: hidden names too, our own CLI node among them.
    let all = run_until(DOMAIN, &["--json", "graph", "-a"], |r| {
        r.stdout.contains("/graph_test/_hidden") && r.stdout.contains("_horus_ros_")
    });
    let all: Value = serde_json::from_str(&all.stdout).expect("graph -a --json is JSON");
    let hidden_topic = all["topics"]
        .as_array()
        .expect("topics")
        .iter()
        .find(|t| t["name"] == "/graph_test/_hidden")
        .expect("the hidden topic with -a");
    assert_eq!(hidden_topic["publishers"][0]["gid"], g(hidden.gid()));
    assert!(all["nodes"]
        .as_array()
        .expect("nodes")
        .iter()
        .any(|n| n["name"]
            .as_str()
            .is_some_and(|n| n.starts_with("_horus_ros_"))));
    drop(peer);
}

#[test]
fn graph_of_an_empty_domain() {
    const DOMAIN: u32 = 134;
    let text = run(DOMAIN, &["graph"]);
    assert_eq!(text.code, Some(0), "stderr: {}", text.stderr);
    assert_eq!(
        text.stdout,
        "Domain 134: 0 nodes, 0 topics, 0 services\n\nNodes:\n\nTopics:\n\nServices:\n"
    );
    let json = run(DOMAIN, &["graph", "--json"]);
    assert_eq!(json.code, Some(0), "stderr: {}", json.stderr);
    let doc: Value = serde_json::from_str(&json.stdout).expect("JSON");
    assert_eq!(
        doc,
        serde_json::json!({"domain_id": 134, "nodes": [], "topics": [], "services": []})
    );
}

// ---------------------------------------------------------------------------------------------
// graph --watch.

/// A running `graph --watch`, its stdout lines arriving on a channel.
struct Watch {
    process: Streaming,
    seen: Vec<String>,
}

impl Watch {
    fn start(domain: u32, json: bool) -> Self {
        let mut command = horus_ros();
        command.args(["--domain-id", &domain.to_string(), "--spin-time", "1"]);
        if json {
            command.arg("--json");
        }
        let process = Streaming::spawn(command.args(["graph", "--watch"]).stderr(Stdio::inherit()))
            .expect("start graph --watch");
        Self {
            process,
            seen: Vec::new(),
        }
    }

    /// Waits for a line `matches` accepts (at most [`WAIT`]) and returns it.
    fn expect(&mut self, what: &str, matches: impl Fn(&str) -> bool) -> String {
        if let Some(line) = self.seen.iter().find(|l| matches(l)) {
            return line.clone();
        }
        let deadline = Instant::now() + WAIT;
        while let Some(left) = deadline.checked_duration_since(Instant::now()) {
            let Some(line) = self.process.next_line(left) else {
                break;
            };
            self.seen.push(line.clone());
            if matches(&line) {
                return line;
            }
        }
        panic!(
            "no line {what} within {WAIT:?}; got:\n{}",
            self.seen.join("\n")
        );
    }

    /// Sends `signal` (`INT`, `TERM`) and returns the exit code and how long the exit took.
    fn stop(mut self, signal: &str) -> (Option<i32>, Duration) {
        let start = Instant::now();
        let status = Command::new("kill")
            .args([
                &format!("-{signal}"),
                &self.process.child().id().to_string(),
            ])
            .status()
            .expect("kill");
        assert!(status.success(), "kill -{signal}");
        let code = wait_bounded(self.process.child(), Duration::from_secs(10));
        (code, start.elapsed())
    }
}

/// The text line's parts after the timestamp, checking the timestamp is RFC 3339 UTC with
/// milliseconds (`2026-11-22T01:23:45.678Z`).
fn after_timestamp(line: &str) -> &str {
    let (time, rest) = line.split_once(' ').unwrap_or_else(|| panic!("{line}"));
    check_timestamp(time);
    rest
}

fn check_timestamp(time: &str) {
    let b = time.as_bytes();
    assert_eq!(b.len(), 24, "{time}");
    for (i, c) in b.iter().enumerate() {
        match i {
            4 | 7 => assert_eq!(*c, b'-', "{time}"),
            10 => assert_eq!(*c, b'T', "{time}"),
            13 | 16 => assert_eq!(*c, b':', "{time}"),
            19 => assert_eq!(*c, b'.', "{time}"),
            23 => assert_eq!(*c, b'Z', "{time}"),
            _ => assert!(c.is_ascii_digit(), "{time}"),
        }
    }
}

#[test]
fn graph_watch_prints_the_graph_then_each_change_and_exits_0_on_sigint_or_sigterm() {
    const DOMAIN: u32 = 132;
    let ctx = context(DOMAIN);
    let steady = ctx.create_node("steady", "/watch_test").expect("node");
    let steady_pub = steady
        .create_publisher::<Time>("steady_topic", &Qos::default())
        .expect("publisher");
    let mut text = Watch::start(DOMAIN, false);
    let mut json = Watch::start(DOMAIN, true);

    // The snapshot (or, if discovery was late, the live change) of what was already there.
    let line = text.expect("+ node /watch_test/steady", |l| {
        l.ends_with(" + node /watch_test/steady")
    });
    after_timestamp(&line);
    let line = text.expect("+ publisher /watch_test/steady_topic", |l| {
        l.contains(" + publisher /watch_test/steady_topic ")
    });
    assert_eq!(
        after_timestamp(&line),
        format!(
            "+ publisher /watch_test/steady_topic [builtin_interfaces/msg/Time] gid {}",
            steady_pub.gid()
        )
    );

    // Both watchers are subscribed once they have printed a line.
    json.expect("the JSON snapshot", |l| {
        l.contains("\"/watch_test/steady\"")
    });

    // A node comes and goes.
    let transient = ctx.create_node("transient", "/watch_test").expect("node");
    let blip = transient
        .create_publisher::<Time>("blip", &Qos::default())
        .expect("publisher");
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&transient)
        .name("sum")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let blip_gid = blip.gid();
    let (request_reader, reply_writer) = server.gids();
    let added = [
        "+ node /watch_test/transient".to_owned(),
        format!("+ publisher /watch_test/blip [builtin_interfaces/msg/Time] gid {blip_gid}"),
        format!(
            "+ service server /watch_test/sum [example_interfaces/srv/AddTwoInts] \
             request reader gid {request_reader}"
        ),
        format!(
            "+ service server /watch_test/sum [example_interfaces/srv/AddTwoInts] \
             response writer gid {reply_writer}"
        ),
    ];
    // Both watchers see every addition before anything goes: a DDS reader that falls behind
    // may see an endpoint only in its last state, gone (built-in topics keep the last sample).
    for want in &added {
        text.expect(want, |l| after_timestamp(l) == want);
    }
    let parse = |l: &str| serde_json::from_str::<Value>(l).unwrap_or_else(|e| panic!("{e}: {l}"));
    let node_added = json.expect("node added", |l| {
        let v = parse(l);
        v["kind"] == "node" && v["change"] == "added" && v["full_name"] == "/watch_test/transient"
    });
    let v = parse(&node_added);
    check_timestamp(v["time"].as_str().expect("time"));
    assert_eq!(v["name"], "transient");
    assert_eq!(v["namespace"], "/watch_test");
    let server_line = json.expect("service server added", |l| {
        let v = parse(l);
        v["kind"] == "service_server"
            && v["change"] == "added"
            && v["part"] == "response_writer"
            && v["service"] == "/watch_test/sum"
    });
    let v = parse(&server_line);
    assert_eq!(v["service"], "/watch_test/sum");
    assert_eq!(v["gid"], reply_writer.to_string());
    assert_eq!(v["type"], "example_interfaces/srv/AddTwoInts");
    assert_eq!(v["dds_topic"], "rr/watch_test/sumReply");
    json.expect("publisher added", |l| {
        let v = parse(l);
        v["kind"] == "publisher" && v["change"] == "added" && v["topic"] == "/watch_test/blip"
    });
    json.expect("service server request reader added", |l| {
        let v = parse(l);
        v["kind"] == "service_server"
            && v["change"] == "added"
            && v["part"] == "request_reader"
            && v["service"] == "/watch_test/sum"
    });
    drop(server);
    drop(blip);
    drop(transient);
    // A vanished endpoint keeps the type it was shown with.
    for want in &added {
        let want = want.replacen('+', "-", 1);
        text.expect(&want, |l| after_timestamp(l) == want);
    }

    // The JSON watcher saw the same, one object per line.
    let removed = json.expect("publisher removed", |l| {
        let v = parse(l);
        v["kind"] == "publisher" && v["change"] == "removed" && v["topic"] == "/watch_test/blip"
    });
    let v = parse(&removed);
    assert_eq!(v["gid"], blip_gid.to_string());
    assert_eq!(v["type"], "builtin_interfaces/msg/Time");
    assert_eq!(v["type_hash"], ours_time_hash(&ctx), "{v}");
    assert_eq!(v["dds_topic"], "rt/watch_test/blip");
    assert_eq!(v["dds_endpoint"], "writer");
    json.expect("node removed", |l| {
        let v = parse(l);
        v["kind"] == "node" && v["change"] == "removed" && v["full_name"] == "/watch_test/transient"
    });

    // Every line printed, text or JSON, is well-formed.
    for line in &text.seen {
        let rest = after_timestamp(line);
        assert!(rest.starts_with("+ ") || rest.starts_with("- "), "{line}");
    }
    for line in &json.seen {
        check_timestamp(parse(line)["time"].as_str().expect("time"));
    }

    let (code, took) = text.stop("INT");
    assert_eq!(code, Some(0), "graph --watch after SIGINT");
    assert!(took < Duration::from_secs(2), "SIGINT took {took:?}");
    let (code, took) = json.stop("TERM");
    assert_eq!(code, Some(0), "graph --watch --json after SIGTERM");
    assert!(took < Duration::from_secs(2), "SIGTERM took {took:?}");
    drop(steady_pub);
}

// ---------------------------------------------------------------------------------------------
// completions.

#[test]
fn completions_for_every_shell() {
    let mut command = horus_ros();
    command.args(["completions", "bash"]);
    let bash = run_command(command);
    assert_eq!(bash.code, Some(0), "stderr: {}", bash.stderr);
    assert!(bash.stdout.contains("horus-ros"), "{}", bash.stdout);
    assert!(
        bash.stdout.contains("complete -F _horus__ros"),
        "{}",
        bash.stdout
    );
    for verb in ["service", "node", "topic", "graph", "demo", "completions"] {
        assert!(bash.stdout.contains(verb), "bash script lacks {verb}");
    }
    assert!(bash.stdout.contains("--watch") && bash.stdout.contains("--domain-id"));
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let mut command = horus_ros();
        command.args(["completions", shell]);
        let out = run_command(command);
        assert_eq!(out.code, Some(0), "{shell}: {}", out.stderr);
        assert!(
            out.stdout.contains("horus-ros") && out.stdout.contains("graph"),
            "{shell}"
        );
    }

    let mut command = horus_ros();
    command.args(["completions", "tcsh"]);
    let bad = run_command(command);
    assert_eq!(bad.code, Some(2), "a usage error");
    assert!(bad.stdout.is_empty());
    assert!(
        bad.stderr
            .starts_with("error: invalid value 'tcsh' for '<SHELL>'"),
        "{}",
        bad.stderr
    );
    assert!(bad.stderr.contains("bash, elvish, fish, powershell, zsh"));
}
