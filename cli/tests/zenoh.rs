//! The zenoh backend against real ROS 2 Jazzy on rmw_zenoh_cpp 0.2.10: an rclpy node
//! (`interop-tests/peers/jazzy_node.py` with `RMW_IMPLEMENTATION=rmw_zenoh_cpp`) through our
//! router (`horus-ros router`; the suite's Zenoh run also drives every Jazzy-peer test through
//! rmw_zenohd itself), and our own publisher and subscription in two processes.
//!
//! Run inside the private network namespace: `scripts/isolated cargo test -p horus-ros-cli --test
//! zenoh`. Each test has a router of its own on its own port, so they run in parallel. Waits are
//! bounded and woken by the processes' output (`graph --watch` lines, the peer's lines), never
//! polled.

mod common;
mod zenoh_common;

use std::time::Duration;

use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolRequest, SetBoolResponse};
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::Context;
use horus_ros_services::{
    EndpointBuilder, NodeServices, ServiceClient, ServiceError, ServiceServer, TransportError,
};
use serde_json::{json, Value};
use zenoh_common::{horus, horus_command, rclpy_on_zenoh, router, Proc, LIMIT};

/// A Zenoh context in this process joined to the router on `port`.
fn zenoh_context(port: u16, domain: u32) -> Context {
    let get =
        |k: &str| (k == config::CONFIG_OVERRIDE_ENV).then(|| zenoh_common::session_override(port));
    let session = config::config(ConfigKind::Session, get).expect("session config");
    Context::builder()
        .domain_id(domain)
        .implementation(horus_ros_rmw::zenoh::implementation(session))
        .build()
        .expect("context")
}

/// The GID rclpy's graph API gives the endpoint of `node` of `kind` (`PUBLISHER`,
/// `SUBSCRIPTION`) on `topic`, from the peer's `{"graph": …}` lines, once one lists it.
fn rclpy_sees(peer: &mut Proc, topic: &str, node: &str, kind: &str) -> String {
    let find = |line: &str| -> Option<String> {
        let view: Value = serde_json::from_str(line).ok()?;
        let key = if kind == "PUBLISHER" {
            "publishers"
        } else {
            "subscriptions"
        };
        view["graph"]["endpoints"][topic][key]
            .as_array()?
            .iter()
            .filter_map(Value::as_str)
            .find(|e| {
                e.contains(&format!("Node name: {node}\n"))
                    && e.contains(&format!("Endpoint type: {kind}"))
            })?
            .lines()
            .find_map(|l| l.strip_prefix("GID: ").map(str::to_owned))
    };
    let line = peer.any_line_where(
        &format!("of rclpy's graph with {node}'s {kind} on {topic}"),
        |l| find(l).is_some(),
    );
    find(&line).unwrap_or_default()
}

/// An rclpy node on rmw_zenoh_cpp and ours, through our router: each sees the other's node,
/// topics, services and GIDs as rclpy's graph API gives them; samples and calls go both ways
/// (`topic echo`, `topic pub`, `service call`, our typed client, rclpy's client of our server,
/// `param list` of our node); killed, the peer leaves our graph and our client finds no server.
#[test]
fn an_rclpy_node_on_rmw_zenoh_through_our_router() {
    let (port, domain) = (17447, 0);
    let _router = router(port);
    let context = zenoh_context(port, domain);
    let node = context.create_node("horus_server", "/").expect("node");
    let _node_services = NodeServices::start(&node).expect("node services");
    let _server = ServiceServer::<SetBool>::builder()
        .node(&node)
        .name("/horus_set")
        .on_request(|r: SetBoolRequest| {
            Ok(SetBoolResponse {
                success: r.data,
                message: format!("horus got {}", r.data),
            })
        })
        .build()
        .expect("server");
    let mut watch = Proc::spawn(
        horus_command(port, domain, &["graph", "--watch"]),
        "horus-ros graph --watch",
    );
    let mut peer = rclpy_on_zenoh(
        port,
        domain,
        &json!({
            "namespace": "/", "name": "talker", "graph": true,
            "publishers": [{"topic": "/chatter", "type": "std_msgs/msg/String", "period_s": 0.1}],
            "subscriptions": [{"topic": "/back", "type": "std_msgs/msg/String"}],
            "servers": [{"service": "/set_flag", "type": "std_srvs/srv/SetBool"}],
            "clients": [{"service": "/horus_set", "type": "std_srvs/srv/SetBool",
                         "calls": [{"data": true}], "wait_s": 20, "timeout_s": 10}],
        }),
    );
    let pub_gid = rclpy_sees(&mut peer, "/chatter", "talker", "PUBLISHER");
    watch.line_where("'+ node /talker'", |l| l.ends_with("+ node /talker"));
    watch.line_where("'+ publisher /chatter … gid <the peer's>'", |l| {
        l.contains("+ publisher /chatter [std_msgs/msg/String]") && l.contains(&pub_gid)
    });

    // The graph verbs, unchanged on the zenoh backend.
    let nodes = horus(port, domain, &["node", "list"]);
    assert!(nodes.lines().any(|l| l == "/talker"), "{nodes}");
    let topics = horus(port, domain, &["topic", "list", "-t"]);
    assert!(
        topics
            .lines()
            .any(|l| l == "/chatter [std_msgs/msg/String]")
            && topics.lines().any(|l| l == "/back [std_msgs/msg/String]"),
        "{topics}"
    );
    let info = horus(port, domain, &["topic", "info", "-v", "/chatter"]);
    assert!(info.contains("Publisher count: 1"), "{info}");
    assert!(info.contains("Node name: talker"), "{info}");
    assert!(info.contains(&format!("GID: {pub_gid}")), "{info}");
    assert!(info.contains("History (Depth): KEEP_LAST (10)"), "{info}");
    let services = horus(port, domain, &["service", "list", "-t"]);
    for want in [
        "/set_flag [std_srvs/srv/SetBool]",
        "/horus_set [std_srvs/srv/SetBool]",
        "/horus_server/get_parameters [rcl_interfaces/srv/GetParameters]",
        "/talker/get_parameters [rcl_interfaces/srv/GetParameters]",
    ] {
        assert!(services.lines().any(|l| l == want), "{want}: {services}");
    }
    let service = horus(port, domain, &["service", "info", "-v", "/set_flag"]);
    assert!(service.contains("Services count: 1"), "{service}");
    assert!(service.contains("Node name: talker"), "{service}");
    let node_info = horus(port, domain, &["node", "info", "/talker"]);
    assert!(
        node_info.contains("/chatter: std_msgs/msg/String"),
        "{node_info}"
    );

    // Its samples reach our subscription.
    let echo = horus(port, domain, &["topic", "echo", "/chatter", "--once"]);
    assert!(echo.starts_with("data: 'Hello World: "), "{echo}");

    // Ours reach its subscription, and rclpy's graph has our publisher with the GID we give it.
    let _publisher = Proc::spawn(
        horus_command(
            port,
            domain,
            &[
                "topic",
                "pub",
                "-r",
                "10",
                "/back",
                "std_msgs/msg/String",
                "{data: from horus}",
            ],
        ),
        "horus-ros topic pub",
    );
    peer.line_where("of a sample of ours heard", |l| {
        l.contains("\"heard\"") && l.contains("from horus")
    });
    let ours = horus(port, domain, &["topic", "info", "-v", "/back"]);
    let our_gid = ours
        .split("Endpoint type: PUBLISHER\nGID: ")
        .nth(1)
        .and_then(|rest| rest.lines().next())
        .unwrap_or_else(|| panic!("our publisher's GID: {ours}"))
        .to_owned();
    let node_name = ours
        .split("Endpoint type: PUBLISHER")
        .next()
        .and_then(|block| block.rsplit("Node name: ").next())
        .and_then(|rest| rest.lines().next())
        .unwrap_or_default()
        .to_owned();
    assert_eq!(
        rclpy_sees(&mut peer, "/back", &node_name, "PUBLISHER"),
        our_gid
    );

    // rclpy's client calls our server; our `service call` calls rclpy's server.
    let reply = peer.any_line_where("of a reply from our server", |l| {
        l.contains("\"reply\"") && l.contains("/horus_set")
    });
    assert!(reply.contains("\"message\": \"horus got true\""), "{reply}");
    let call = horus(
        port,
        domain,
        &[
            "service",
            "call",
            "/set_flag",
            "std_srvs/srv/SetBool",
            "{data: true}",
        ],
    );
    assert!(
        call.ends_with(
            "response:\nstd_srvs.srv.SetBool_Response(success=True, message='set to True')\n\n"
        ),
        "{call}"
    );
    peer.any_line_where("of our request served", |l| l.contains("\"served\""));

    // Our node's parameter services answer.
    let params = horus(port, domain, &["param", "list", "/horus_server"]);
    assert!(params.lines().any(|l| l == "  use_sim_time"), "{params}");

    // Our typed client calls rclpy's server; the peer killed (no goodbye, as a crash), it
    // leaves the graph and the client finds no server.
    let mut client = ServiceClient::<SetBool>::builder()
        .node(&node)
        .name("/set_flag")
        .build()
        .expect("client");
    assert!(client.wait_for_service(LIMIT), "rclpy's server");
    let set = client
        .call(SetBoolRequest { data: false }, LIMIT)
        .expect("rclpy's answer");
    assert_eq!(set.message, "set to False");
    peer.kill();
    watch.line_where("'- node /talker'", |l| l.ends_with("- node /talker"));
    let nodes = horus(port, domain, &["node", "list"]);
    assert!(!nodes.lines().any(|l| l == "/talker"), "{nodes}");
    match client.call(SetBoolRequest { data: true }, Duration::from_secs(3)) {
        Err(ServiceError::NoServer | ServiceError::Transport(TransportError::ServerGone)) => {}
        other => panic!("expected NoServer or ServerGone, got {other:?}"),
    }
}

/// `horus-ros topic pub -r 10 /numbers std_msgs/msg/Int32 "{data: <data>}"` on Zenoh, once it
/// has published its first message.
fn numbers_at_10_hz(port: u16, domain: u32, data: i32) -> Proc {
    let value = format!("{{data: {data}}}");
    let args = [
        "topic",
        "pub",
        "-r",
        "10",
        "/numbers",
        "std_msgs/msg/Int32",
        &value,
    ];
    let mut publisher = Proc::spawn(horus_command(port, domain, &args), "horus-ros topic pub");
    publisher.line_where("'publishing #1'", |l| l.starts_with("publishing #1:"));
    publisher
}

/// Our own publisher and subscription, in two processes on the zenoh backend.
#[test]
fn our_pub_and_sub_across_two_processes() {
    let (port, domain) = (17448, 3);
    let _router = router(port);
    // Its token is declared before it publishes: a session opened from now on sees it.
    let _publisher = numbers_at_10_hz(port, domain, 42);
    let echo = horus(port, domain, &["topic", "echo", "/numbers", "--once"]);
    assert_eq!(echo, "data: 42\n---\n");
}

/// The router stops on SIGINT and on SIGTERM, with status 0 (as rmw_zenohd on Ctrl+C).
#[test]
fn the_router_stops_on_sigint_and_sigterm() {
    use nix::sys::signal::{kill, Signal};
    use nix::unistd::Pid;
    for (port, signal) in [(17449, Signal::SIGINT), (17450, Signal::SIGTERM)] {
        let mut router = router(port);
        let pid = Pid::from_raw(i32::try_from(router.child.id()).expect("pid"));
        kill(pid, signal).expect("signal the router");
        let status = horus_ros_test_support::wait_exit(&mut router.child, LIMIT)
            .expect("wait")
            .unwrap_or_else(|| panic!("the router did not stop on {signal}"));
        assert!(status.success(), "{signal}: {status}");
    }
}

/// The daemon on Zenoh: started for the Zenoh graph (`--backend zenoh daemon start`), it knows
/// the peer's node, and the CLI's answers through it equal direct discovery's.
#[test]
fn the_daemon_serves_the_zenoh_graph() {
    let (port, domain) = (17451, 4);
    let _router = router(port);
    let _peer = rclpy_on_zenoh(port, domain, &json!({"namespace": "/", "name": "talker"}));
    let direct = horus(port, domain, &["node", "list"]);
    assert!(direct.lines().any(|l| l == "/talker"), "{direct}");

    // `horus-ros --backend zenoh <args>` as a user types it: through the daemon.
    let through_daemon = |args: &[&str]| {
        let domain = domain.to_string();
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_horus-ros"));
        command
            .args(["--backend", "zenoh", "--domain-id", &domain])
            .args(args)
            .env_remove("ROS_DOMAIN_ID")
            .env("RUST_LOG", "error")
            .env(
                "ZENOH_CONFIG_OVERRIDE",
                zenoh_common::session_override(port),
            )
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped());
        let mut child = command.spawn().expect("start horus-ros");
        horus_ros_test_support::wait_with_output(&mut child, LIMIT).expect("output")
    };
    common::daemon::adopt_orphans();
    let start = through_daemon(&["daemon", "start"]);
    // Guarded first, so that it is stopped even if the message is wrong.
    let _guard = (start.code() == Some(0)).then(|| common::daemon::DaemonGuard::adopt(domain));
    assert_eq!(
        (start.code(), start.stdout.as_str()),
        (Some(0), "The daemon has been started\n"),
        "{}",
        start.stderr
    );
    let status = through_daemon(&["--json", "daemon", "status"]);
    let status: Value = serde_json::from_str(&status.stdout).expect("status JSON");
    assert_eq!(status["running"], Value::Bool(true), "{status}");
    assert_eq!(status["backend"], Value::from("zenoh"), "{status}");
    for args in [
        &["node", "list"][..],
        &["topic", "list", "-t"],
        &["node", "info", "/talker"],
    ] {
        let via = through_daemon(args);
        assert_eq!(via.code(), Some(0), "{args:?}: {}", via.stderr);
        assert_eq!(via.stdout, horus(port, domain, args), "{args:?}");
    }
}

/// The action verbs and `topic hz`/`bw` on Zenoh, against our own action server (in this
/// process, on a Zenoh context joined to the router) and a `topic pub` process: `action list`,
/// `action info`, a goal sent and its result, rates and sizes measured.
#[test]
fn action_and_rate_verbs_on_zenoh() {
    use horus_ros_rmw::zenoh::config::{self, ConfigKind};
    use horus_ros_rmw::Context;

    let (port, domain) = (17452, 5);
    let _router = router(port);
    let get =
        |k: &str| (k == config::CONFIG_OVERRIDE_ENV).then(|| zenoh_common::session_override(port));
    let session = config::config(ConfigKind::Session, get).expect("session config");
    let context = Context::builder()
        .domain_id(domain)
        .implementation(horus_ros_rmw::zenoh::implementation(session))
        .build()
        .expect("context");
    let _server = common::fibonacci::fibonacci_server(&context);

    assert_eq!(
        horus(port, domain, &["action", "list", "-t"]),
        "/fibonacci [test_msgs/action/Fibonacci]\n"
    );
    assert_eq!(
        horus(port, domain, &["action", "info", "/fibonacci"]),
        "Action: /fibonacci\nAction clients: 0\nAction servers: 1\n    /fibonacci_action_server\n"
    );
    // `action send_goal` reads the type's interface files, as ros2action imports it.
    let mut send_goal = horus_command(
        port,
        domain,
        &[
            "action",
            "send_goal",
            "/fibonacci",
            "test_msgs/action/Fibonacci",
            "{order: 4}",
        ],
    );
    let mut send_goal = send_goal
        .env("AMENT_PREFIX_PATH", common::jazzy_prefix())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start horus-ros action send_goal");
    let run = horus_ros_test_support::wait_with_output(&mut send_goal, LIMIT).expect("output");
    assert_eq!(run.code(), Some(0), "{}", run.stderr);
    let goal = run.stdout;
    assert!(goal.contains("\nGoal accepted with ID: "), "{goal}");
    assert!(
        goal.ends_with(
            "Result:\n    sequence:\n- 0\n- 1\n- 1\n- 2\n- 3\n\n\
             Goal finished with status: SUCCEEDED\n"
        ),
        "{goal}"
    );

    let _publisher = numbers_at_10_hz(port, domain, 7);
    let mut hz = Proc::spawn(
        horus_command(port, domain, &["topic", "hz", "/numbers"]),
        "horus-ros topic hz",
    );
    // The first report comes from few intervals: take the third.
    let mut rate = String::new();
    for _ in 0..3 {
        rate = hz.line_where("'average rate: …'", |l| l.starts_with("average rate: "));
    }
    let rate: f64 = rate["average rate: ".len()..].parse().expect("a rate");
    // A 10 Hz publisher, measured on a loaded machine: a wide tolerance.
    assert!((7.0..=13.0).contains(&rate), "rate {rate}");
    drop(hz);
    let mut bw = Proc::spawn(
        horus_command(port, domain, &["topic", "bw", "/numbers"]),
        "horus-ros topic bw",
    );
    // A 4-byte CDR header and the 4-byte int32.
    bw.line_where("'Message size mean: 8 B …'", |l| {
        l == "\tMessage size mean: 8 B min: 8 B max: 8 B"
    });
}

/// A command that succeeds on Zenoh prints no ERROR or WARN line at the default log level
/// (issue 36: each client's matching listener logged zenoh's "Unable to find MatchingListener"
/// at exit, and its querier, undeclared before the query's final, "Received ResponseFinal for
/// unknown Request"): `service call` and `param get` of our own server and node (in this
/// process), `demo`, `node list`/`info` and `topic echo --once`.
#[test]
fn succeeding_commands_log_no_error_or_warning() {
    use horus_ros_msgs::example_interfaces::srv::{
        AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse,
    };

    /// Zenoh's warning when a session's start conditions take longer than `scouting/delay`
    /// (500 ms) on a loaded machine: a timing report, not a failure.
    const SCOUTING_DELAY: &str = "Scouting delay elapsed before start conditions are met";

    let (port, domain) = (17453, 6);
    let _router = router(port);
    let context = zenoh_context(port, domain);
    let node = context.create_node("horus_server", "/").expect("node");
    let _node_services = NodeServices::start(&node).expect("node services");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name("/horus_add")
        .on_request(|r: AddTwoIntsRequest| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let _publisher = numbers_at_10_hz(port, domain, 5);

    let quiet = |args: &[&str], want: &str| {
        let mut child = horus_command(port, domain, args)
            .env_remove("RUST_LOG")
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("start horus-ros");
        let out = horus_ros_test_support::wait_with_output(&mut child, LIMIT).expect("output");
        assert_eq!(out.code(), Some(0), "{args:?}: {}", out.stderr);
        assert!(out.stdout.contains(want), "{args:?}: {}", out.stdout);
        let noisy: Vec<&str> = out
            .stderr
            .lines()
            .filter(|l| (l.contains("ERROR") || l.contains("WARN")) && !l.contains(SCOUTING_DELAY))
            .collect();
        assert!(noisy.is_empty(), "{args:?} logged:\n{}", noisy.join("\n"));
    };
    quiet(
        &[
            "service",
            "call",
            "/horus_add",
            "example_interfaces/srv/AddTwoInts",
            "{a: 1, b: 2}",
        ],
        "AddTwoInts_Response(sum=3)",
    );
    quiet(
        &["param", "get", "/horus_server", "use_sim_time"],
        "Boolean value is: False",
    );
    quiet(&["demo", "2", "3"], "AddTwoInts_Response(sum=5)");
    quiet(&["node", "list"], "/horus_server");
    quiet(
        &["node", "info", "/horus_server"],
        "/horus_add: example_interfaces/srv/AddTwoInts",
    );
    quiet(&["topic", "echo", "/numbers", "--once"], "data: 5");
}
