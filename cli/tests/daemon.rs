//! `horus-ros daemon`: its lifecycle and messages (ros2cli's), answers through it equal to direct
//! discovery's (on a graph with real rmw_cyclonedds_cpp nodes), a Fast DDS node answered at once, nodes leaving, the idle timeout, the daemon's
//! settings keeping it to its own graph, a query starting it when none runs, and the fallback to
//! direct discovery when the daemon is dead or does not answer.
//!
//! Commands run as a user types them (a query uses the daemon, and starts one when none runs).
//! Every daemon a test starts, explicitly or by a query, becomes a child of the test process (it
//! is made the reaper of orphans), is found by its command line and guarded: it is killed by its
//! pid and reaped when the guard drops, whatever the test's outcome (`common::daemon`). Each test
//! has its own DDS domain. Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test daemon`.

mod common;

use std::time::{Duration, Instant};

use common::daemon::{adopt_orphans, daemon_children, DaemonGuard, EXIT_LIMIT};
use common::{
    expect_as_typed as expect, horus_as_typed as horus, horus_with_env, Peer, Run, LINGER, SETTLE,
};
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Context;
use horus_ros_services::{EndpointBuilder, ServiceServer};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use nix::sys::signal::Signal;
use nix::sys::wait::WaitStatus;
use nix::unistd::Pid;
use serde_json::Value;
/// How long a daemon's graph may take to show a Fast DDS peer's node.
const FAST_DDS_WARM_UP: Duration = Duration::from_secs(20);
/// The longest lease of a participant of ours: rustdds announces 50 s (10 s on Cyclone).
const PARTICIPANT_LEASE: Duration = Duration::from_secs(50);

/// Runs `daemon start <args…>` (with `env`), asserts its message, and guards the daemon.
fn start_daemon(domain: u32, env: &[(&str, &str)], args: &[&str]) -> DaemonGuard {
    adopt_orphans();
    let mut start = vec!["daemon", "start"];
    start.extend_from_slice(args);
    let run = horus_with_env(domain, env, &start);
    // Guarded first, so that it is stopped even if the message is wrong.
    let guard = (run.code == Some(0)).then(|| DaemonGuard::adopt(domain));
    assert_eq!(
        (run.code, run.stdout.as_str(), run.stderr.as_str()),
        (Some(0), "The daemon has been started\n", ""),
        "daemon start"
    );
    guard.expect("guarded")
}

/// `--json daemon status`, parsed.
fn status_json(domain: u32, env: &[(&str, &str)]) -> Value {
    let run = horus_with_env(domain, env, &["--json", "daemon", "status"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{e}: {run:?}"))
}

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

/// Runs `args` until stdout has a line equal to `line`, at most `limit`; returns the last run.
fn until_line(domain: u32, args: &[&str], line: &str, limit: Duration) -> Run {
    let deadline = Instant::now() + limit;
    loop {
        let run = horus(domain, args);
        if run.stdout.lines().any(|l| l == line) || Instant::now() >= deadline {
            return run;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn lifecycle_and_messages() {
    const D: u32 = 181;
    let plain = |args: &[&str], want: &str| {
        let run = horus(D, args);
        assert_eq!(
            (run.code, run.stdout.as_str(), run.stderr.as_str()),
            (Some(0), want, ""),
            "{args:?}"
        );
    };
    plain(&["daemon", "status"], "The daemon is not running\n");
    plain(&["daemon", "stop"], "The daemon is not running\n");
    let not_running = status_json(D, &[]);
    assert_eq!(not_running["running"], Value::Bool(false), "{not_running}");

    let mut daemon = start_daemon(D, &[], &[]);
    plain(&["daemon", "start"], "The daemon is already running\n");
    plain(&["daemon", "status"], "The daemon is running\n");
    let status = status_json(D, &[]);
    assert_eq!(status["running"], Value::Bool(true), "{status}");
    assert_eq!(status["pid"], Value::from(daemon.pid), "{status}");
    assert_eq!(status["domain_id"], Value::from(D), "{status}");
    // ros2cli's default: two hours.
    assert_eq!(status["idle_timeout_s"], Value::from(7200), "{status}");
    assert_eq!(status["socket"], not_running["socket"], "{status}");
    let backend = std::env::var("HORUS_ROS_BACKEND")
        .ok()
        .filter(|b| !b.is_empty())
        .unwrap_or_else(|| "rustdds".to_owned());
    assert_eq!(status["backend"], Value::from(backend), "{status}");
    let node = status["node_name"].as_str().expect("node_name").to_owned();
    assert!(
        node.starts_with(&format!("_horus_ros_daemon_{D}_")),
        "{node}"
    );
    let already = horus(D, &["--json", "daemon", "start"]);
    let already: Value = serde_json::from_str(&already.stdout).expect("json");
    assert_eq!(
        already,
        serde_json::json!({"started": false, "pid": daemon.pid})
    );

    // The daemon's own hidden node is what `node list -a` shows through it (no node of the
    // command's own, as with ros2cli's daemon).
    let run = until_line(D, &["node", "list", "-a"], &format!("/{node}"), SETTLE);
    assert_eq!(run.stdout, format!("/{node}\n"), "{run:?}");

    plain(&["daemon", "stop"], "The daemon has been stopped\n");
    // `stop` returns once the daemon has exited.
    assert_eq!(
        daemon.wait_exit(Duration::from_secs(2)),
        Some(WaitStatus::Exited(Pid::from_raw(daemon.pid as i32), 0))
    );
    plain(&["daemon", "status"], "The daemon is not running\n");
    let stopped = horus(D, &["--json", "daemon", "stop"]);
    assert_eq!(stopped.stdout, "{\n  \"stopped\": false\n}\n");

    // Started again, it is a new process.
    let second = start_daemon(D, &[], &["--idle-timeout", "60"]);
    assert_ne!(second.pid, daemon.pid);
    assert_eq!(status_json(D, &[])["idle_timeout_s"], Value::from(60));
    let stopped = horus(D, &["--json", "daemon", "stop"]);
    assert_eq!(stopped.stdout, "{\n  \"stopped\": true\n}\n");
}

#[test]
fn answers_equal_direct_discovery() {
    const D: u32 = 182;
    // Real rmw_cyclonedds_cpp nodes (bare: no parameter services, as few endpoints as rclpy
    // allows), whatever the run's peers use.
    let rclpy = |spec: serde_json::Value| {
        let mut peer = RclpyPeer::start_on(Rmw::CycloneDds, &spec).expect("start the rclpy peer");
        peer.ready(Duration::from_secs(20))
            .expect("the rclpy node is up");
        peer
    };
    let _peer = rclpy(serde_json::json!({
        "domain": D, "namespace": "/peer_ns", "name": "cyclone_node", "bare": true,
        "publishers": [{"topic": "/peer_ns/chatter", "type": "std_msgs/msg/String",
                        "period_s": 1.0}],
        "servers": [{"service": "/peer_add", "type": "example_interfaces/srv/AddTwoInts"}],
    }));
    let _server = rclpy(serde_json::json!({
        "domain": D, "namespace": "/", "name": "add_two_ints_server", "bare": true,
        "servers": [{"service": "/add_two_ints", "type": "example_interfaces/srv/AddTwoInts"}],
    }));
    let ctx = context(D);
    let node = ctx.create_node("horus_node", "/ours").expect("node");
    let _publisher = node
        .create_publisher::<Time>("stamps", &Qos::default())
        .expect("publisher");
    let _daemon = start_daemon(D, &[], &[]);

    let nodes = "/add_two_ints_server\n/ours/horus_node\n/peer_ns/cyclone_node\n";
    let through_daemon = expect(D, &["node", "list"], nodes);
    assert_eq!(through_daemon.stderr, "");
    for args in [
        &["node", "list"][..],
        &["node", "list", "-c"],
        &["node", "info", "/peer_ns/cyclone_node"],
        &["node", "info", "/ours/horus_node"],
        &["topic", "list", "-t"],
        &["topic", "list", "-v"],
        &["topic", "info", "/peer_ns/chatter", "-v"],
        &["topic", "info", "/ours/stamps", "-v"],
        &["service", "list", "-t"],
        &["service", "type", "/add_two_ints"],
        &["service", "find", "example_interfaces/srv/AddTwoInts"],
        &["service", "info", "/add_two_ints", "-v"],
        &["service", "info", "/peer_add", "-v"],
        &["graph"],
        &["--json", "node", "list"],
        &["--json", "graph"],
    ] {
        let mut direct_args = vec!["--no-daemon"];
        direct_args.extend_from_slice(args);
        // Direct discovery may need a few tries to see everything; the daemon's answer must then
        // be the same. The direct runs' own participants come and go in the daemon's graph: one
        // that has not announced its nodes yet (or is leaving) makes the daemon's answer honestly
        // incomplete (one line on stderr), so that too is tried again until the deadline. One
        // that left before the daemon heard its `ros_discovery_info` (a loaded machine) stays
        // there, unannounced, until its lease ends when its dispose is not taken: the deadline
        // allows for one such lease.
        let deadline = Instant::now() + SETTLE + PARTICIPANT_LEASE;
        loop {
            let daemon = horus(D, args);
            let direct = horus(D, &direct_args);
            assert_eq!(daemon.code, Some(0), "{args:?}: {daemon:?}");
            if daemon.stderr.is_empty() && daemon.stdout == direct.stdout {
                assert!(!daemon.stdout.is_empty(), "{args:?}");
                break;
            }
            assert!(
                Instant::now() < deadline,
                "`horus-ros {}` differs through the daemon\n--- daemon:\n{}{}\n--- direct:\n{}\n{}",
                args.join(" "),
                daemon.stdout,
                daemon.stderr,
                direct.stdout,
                direct.stderr
            );
        }
    }
    // The domain is the daemon's.
    assert!(horus(D, &["graph"])
        .stdout
        .starts_with(&format!("Domain {D}: 3 nodes")));
}

#[test]
fn fast_dds_node_is_answered_at_once() {
    const D: u32 = 183;
    let mut peer = RclpyPeer::start(&serde_json::json!({
        "domain": D, "namespace": "/fast_ns", "name": "fast_node",
        "servers": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
        "clients": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
    }))
    .expect("start the rclpy peer");
    peer.ready(Duration::from_secs(20))
        .expect("the rclpy node is up");
    let _daemon = start_daemon(D, &[], &[]);
    // The daemon's graph warms up: Fast DDS answers a new participant's discovery slowly (a
    // reader matched just after one of its heartbeats gets ros_discovery_info at the next).
    let run = until_line(D, &["node", "list"], "/fast_ns/fast_node", FAST_DDS_WARM_UP);
    assert_eq!(run.stdout, "/fast_ns/fast_node\n", "{run:?}");
    // Warm, every query answers completely at once, with the default --spin-time: no warning.
    for _ in 0..3 {
        let run = horus(D, &["node", "list"]);
        assert_eq!(
            (run.code, run.stdout.as_str(), run.stderr.as_str()),
            (Some(0), "/fast_ns/fast_node\n", "")
        );
    }
    let info = horus(D, &["node", "info", "/fast_ns/fast_node"]);
    assert_eq!(info.stderr, "");
    assert!(
        info.stdout
            .contains("  Service Servers:\n    /fast_ns/fast_node/describe_parameters: "),
        "{info:?}"
    );
    assert!(
        info.stdout.contains("    /fast_ns/set: std_srvs/srv/SetBool\n  Service Clients:\n    /fast_ns/set: std_srvs/srv/SetBool\n"),
        "{info:?}"
    );
    let servers = horus(D, &["service", "info", "/fast_ns/set"]);
    assert_eq!(
        servers.stdout,
        "Type: std_srvs/srv/SetBool\nClients count: 1\nServices count: 1\n"
    );
}

#[test]
fn node_that_leaves_is_gone() {
    const D: u32 = 184;
    let _daemon = start_daemon(D, &[], &[]);
    let ctx = context(D);
    let staying = ctx.create_node("staying", "/").expect("node");
    let leaving = ctx.create_node("leaving", "/").expect("node");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&leaving)
        .name("/leaving_add")
        .on_request(|r| {
            Ok(horus_ros_msgs::example_interfaces::srv::AddTwoIntsResponse { sum: r.a + r.b })
        })
        .build()
        .expect("server");
    expect(D, &["node", "list"], "/leaving\n/staying\n");
    expect(D, &["service", "list"], "/leaving_add\n");
    drop(_server);
    drop(leaving);
    expect(D, &["node", "list"], "/staying\n");
    expect(D, &["service", "list"], "");
    // A whole participant leaving.
    drop(staying);
    drop(ctx);
    expect(D, &["node", "list"], "");
}

#[test]
fn idle_timeout_ends_it() {
    const D: u32 = 185;
    let mut daemon = start_daemon(D, &[], &["--idle-timeout", "2"]);
    assert_eq!(status_json(D, &[])["idle_timeout_s"], Value::from(2));
    // A query is activity.
    let run = horus(D, &["node", "list"]);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""));
    // Then nothing: it exits by itself, cleanly.
    assert_eq!(
        daemon.wait_exit(EXIT_LIMIT),
        Some(WaitStatus::Exited(Pid::from_raw(daemon.pid as i32), 0)),
        "the daemon did not exit after its idle timeout"
    );
    let run = horus(D, &["daemon", "status"]);
    assert_eq!(run.stdout, "The daemon is not running\n");
}

#[test]
fn killed_daemon_is_replaced_by_the_next_query() {
    const D: u32 = 186;
    let ctx = context(D);
    let _node = ctx.create_node("here", "/").expect("node");
    let mut daemon = start_daemon(D, &[], &[]);
    expect(D, &["node", "list"], "/here\n");
    daemon.signal(Signal::SIGKILL);
    assert!(matches!(
        daemon.wait_exit(EXIT_LIMIT),
        Some(WaitStatus::Signaled(_, Signal::SIGKILL, _))
    ));
    // Its socket went with it: the daemon is simply not running, as if never started.
    assert_eq!(
        horus(D, &["daemon", "status"]).stdout,
        "The daemon is not running\n"
    );
    // `--no-daemon` discovers directly, says nothing more, and starts no daemon.
    let run = horus(D, &["--no-daemon", "node", "list", "-a"]);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""), "{run:?}");
    // Our own node in the list: this answer is our own discovery's.
    assert!(
        run.stdout
            .lines()
            .any(|l| l == format!("/_horus_ros_{}", run.pid)),
        "{run:?}"
    );
    assert_eq!(
        daemon_children(D),
        Vec::<u32>::new(),
        "--no-daemon started one"
    );
    // The next query starts a new daemon (as ros2cli does on first use) and is answered by it,
    // completely: the new daemon waited for its graph before answering.
    let run = horus(D, &["node", "list", "-a"]);
    let again = DaemonGuard::adopt(D);
    assert_ne!(again.pid, daemon.pid);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""), "{run:?}");
    let node = status_json(D, &[])["node_name"]
        .as_str()
        .expect("node_name")
        .to_owned();
    assert_eq!(run.stdout, format!("/{node}\n/here\n"), "{run:?}");
    assert_eq!(status_json(D, &[])["pid"], Value::from(again.pid));
    assert_eq!(
        horus(D, &["daemon", "stop"]).stdout,
        "The daemon has been stopped\n"
    );
}

/// The one warning line of a daemon that did not answer, then the direct answer.
fn assert_fell_back(run: &Run, pid: u32) {
    assert_eq!(run.code, Some(0), "{run:?}");
    let prefix = format!("WARNING: the daemon (pid {pid}) did not answer: ");
    assert!(
        run.stderr.starts_with(&prefix)
            && run.stderr.ends_with("; discovering the graph directly\n")
            && run.stderr.lines().count() == 1,
        "{run:?}"
    );
    assert!(
        run.stdout
            .lines()
            .any(|l| l == format!("/_horus_ros_{}", run.pid)),
        "not the direct answer: {run:?}"
    );
}

#[test]
fn stopped_daemon_means_a_warning_and_direct_discovery() {
    const D: u32 = 187;
    let ctx = context(D);
    let _node = ctx.create_node("here", "/").expect("node");
    let daemon = start_daemon(D, &[], &[]);
    expect(D, &["node", "list"], "/here\n");
    daemon.signal(Signal::SIGSTOP);
    let run = horus(D, &["--spin-time", "0.3", "node", "list", "-a"]);
    assert_fell_back(&run, daemon.pid);
    assert!(run.stdout.lines().any(|l| l == "/here"), "{run:?}");
    // The verbs that need the daemon say what is wrong, and fail.
    for verb in ["status", "start"] {
        let run = horus(D, &["daemon", verb]);
        assert_eq!(run.code, Some(1), "{verb}: {run:?}");
        assert!(
            run.stderr
                .starts_with(&format!("the daemon (pid {}) did not answer", daemon.pid)),
            "{verb}: {run:?}"
        );
    }
    daemon.signal(Signal::SIGCONT);
    let run = horus(D, &["daemon", "stop"]);
    assert_eq!(run.stdout, "The daemon has been stopped\n", "{run:?}");
}

#[test]
fn socket_held_by_something_else_means_a_warning_and_direct_discovery() {
    const D: u32 = 188;
    use std::os::linux::net::SocketAddrExt;
    let ctx = context(D);
    let _node = ctx.create_node("here", "/").expect("node");
    // Something that is not a daemon holds the daemon's socket name and never answers.
    let name = status_json(D, &[])["socket"]
        .as_str()
        .expect("socket name")
        .to_owned();
    let address = std::os::unix::net::SocketAddr::from_abstract_name(name.as_bytes())
        .expect("abstract address");
    let squatter = std::os::unix::net::UnixListener::bind_addr(&address).expect("bind");
    let run = horus(D, &["--spin-time", "0.3", "node", "list", "-a"]);
    assert_fell_back(&run, std::process::id());
    assert!(run.stdout.lines().any(|l| l == "/here"), "{run:?}");
    // `--no-daemon` does not even try (no warning). Retried while discovery settles: on a loaded
    // machine our participant can take longer than the CLI's shortest wait to be discovered.
    let run = expect(D, &["--no-daemon", "node", "list"], "/here\n");
    assert_eq!(run.stderr, "", "{run:?}");
    drop(squatter);
    let run = horus(D, &["daemon", "status"]);
    assert_eq!(run.stdout, "The daemon is not running\n");
}

#[test]
fn daemon_serves_only_its_discovery_settings() {
    const D: u32 = 189;
    // Whatever range the environment sets (scripts/test may set LOCALHOST), static peers make
    // another graph.
    let peers = [("ROS_STATIC_PEERS", "127.0.0.1")];
    let daemon = start_daemon(D, &peers, &[]);
    let status = status_json(D, &peers);
    assert_eq!(
        status["static_peers"],
        serde_json::json!(["127.0.0.1"]),
        "{status}"
    );
    // The same settings use it.
    let node = status["node_name"].as_str().expect("node_name").to_owned();
    let run = horus_with_env(D, &peers, &["node", "list", "-a"]);
    assert_eq!(run.stdout, format!("/{node}\n"), "{run:?}");
    // Other discovery settings are another graph: that daemon is not this command's.
    let run = horus(D, &["daemon", "status"]);
    assert_eq!(run.stdout, "The daemon is not running\n");
    // A query with them starts a daemon of their own, which answers it.
    let run = horus(D, &["node", "list", "-a"]);
    let other = DaemonGuard::adopt_except(D, &[daemon.pid]);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""), "{run:?}");
    let other_status = status_json(D, &[]);
    assert_eq!(
        other_status["pid"],
        Value::from(other.pid),
        "{other_status}"
    );
    assert_eq!(other_status["static_peers"], serde_json::json!([]));
    let other_node = other_status["node_name"].as_str().expect("node_name");
    assert!(
        run.stdout.lines().any(|l| l == format!("/{other_node}")),
        "not answered by its own daemon: {run:?}"
    );
    for env in [&[][..], &peers[..]] {
        let run = horus_with_env(D, env, &["daemon", "stop"]);
        assert_eq!(run.stdout, "The daemon has been stopped\n", "{env:?}");
    }
}

/// The warning of an answer given before a ROS participant announced its nodes, after the
/// wait's bound (`--spin-time 0.2` is shorter: the bound is what the protocol needs).
fn is_unannounced_warning(stderr: &str, gid: &str) -> bool {
    stderr
        == format!(
            "WARNING: discovery incomplete after 4.605 s: participant {gid} has not announced \
             its nodes (ros_discovery_info); the answer may be incomplete (raise --spin-time)\n"
        )
}

#[test]
fn incomplete_daemon_graph_gives_the_same_warning() {
    const D: u32 = 180;
    let _daemon = start_daemon(D, &[], &[]);
    // It says it is a ROS participant (enclave, ros_discovery_info writer) but never announces
    // its nodes, so the graph cannot become complete.
    let d = D.to_string();
    let silent = Peer::start_path(
        &common::cli_peer_script("bare_participant.py"),
        &[&d, "silent_ros", LINGER],
        common::PEER_START,
    );
    let gid = silent.field("/gid");
    // Once the daemon has seen it, its answer waits for it up to the bound, then says so.
    let deadline = Instant::now() + SETTLE.saturating_mul(3);
    let run = loop {
        let run = horus(D, &["--spin-time", "0.2", "node", "list"]);
        if !run.stderr.is_empty() || Instant::now() >= deadline {
            break run;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(is_unannounced_warning(&run.stderr, &gid), "{run:?}");
    // Past its bound the participant no longer holds the daemon's answers; each still says it
    // is incomplete.
    let run = horus(D, &["node", "list"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(is_unannounced_warning(&run.stderr, &gid), "{run:?}");
    // The same wait and warning without the daemon.
    let run = horus(D, &["--no-daemon", "--spin-time", "0.2", "node", "list"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(is_unannounced_warning(&run.stderr, &gid), "{run:?}");
}
