//! A new user's first answers about a real ROS 2 Jazzy node — rclpy 7.1 on rmw_fastrtps_cpp
//! (Fast DDS 2.14), up for a few seconds before (`peers/jazzy_set_bool.py`) — with default
//! options: cold `service info -v` and `node list` (discovering directly with `--no-daemon`,
//! and as typed, which starts the daemon and asks it) and `service echo` are complete and say
//! nothing on stderr. And a DDS participant that is not a ROS participant
//! (`peers/bare_participant.py plain`, as Cyclone's `ddsperf pong`) neither holds the wait nor
//! is warned about.
//!
//! Needs the test venv's rclpy (`HORUS_ROS_INTEROP_PYTHON`, else `target/interop-venv`). Every
//! daemon a query starts is guarded and stopped (`common::daemon`). Domains 195–197. Run inside
//! the private network namespace: `scripts/isolated cargo test -p horus-ros-cli --test
//! first_contact`.

mod common;

use std::time::{Duration, Instant};

use common::daemon::{adopt_orphans, daemon_children, DaemonGuard};
use common::{cli_peer_script, horus_as_typed, Peer, Run};
use horus_ros_rmw::Context;

/// How long the rclpy peer may take to start (Python and rclpy's imports on a loaded machine).
const RCLPY_START: Duration = Duration::from_secs(60);
/// How long the peer runs before the first command, as in the issue: past Fast DDS' initial
/// announcements, so the command is a late joiner as a user's is.
const PEER_AGE: Duration = Duration::from_secs(4);
/// How long the peers stay up unless the test ends first.
const LINGER: &str = "120";

/// Starts the rclpy node `set_bool_server` serving `/set_bool` in `domain` (`extra`: its
/// options) and lets it age.
fn rclpy_peer(domain: u32, extra: &[&str]) -> Peer {
    let d = domain.to_string();
    let mut args = vec![d.as_str(), "set_bool_server", "/set_bool", LINGER];
    args.extend_from_slice(extra);
    let peer = Peer::start_path(&cli_peer_script("jazzy_set_bool.py"), &args, RCLPY_START);
    assert_eq!(peer.field("/node"), "/set_bool_server");
    // The scenario, not a synchronisation: the node has been up for a while when the user
    // asks (nothing of it is awaited here).
    std::thread::sleep(PEER_AGE);
    peer
}

/// Asserts a complete `service info -v /set_bool` of the peer's server: its type, one server,
/// its node's name on its endpoints, nothing on stderr.
fn assert_complete_service_info(run: &Run) {
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (Some(0), ""),
        "not a complete answer: {run:?}"
    );
    assert!(
        run.stdout.starts_with(
            "Type: std_srvs/srv/SetBool\nClients count: 0\n\nServices count: 1\n\n\
             Node name: set_bool_server\nNode namespace: /\nService type: std_srvs/srv/SetBool\n"
        ),
        "{run:?}"
    );
    assert!(
        run.stdout.contains("Endpoint type: SERVER\n")
            && !run.stdout.contains("_NODE_NAME_UNKNOWN_"),
        "{run:?}"
    );
}

#[test]
fn cold_answers_about_an_rclpy_node_are_complete() {
    const D: u32 = 195;
    adopt_orphans();
    let _peer = rclpy_peer(D, &[]);

    // Discovering directly: each command waits until the node has announced its nodes and its
    // endpoints are known, then answers.
    let info = horus_as_typed(D, &["--no-daemon", "service", "info", "-v", "/set_bool"]);
    assert_complete_service_info(&info);
    let list = horus_as_typed(D, &["--no-daemon", "node", "list"]);
    assert_eq!(
        (list.code, list.stdout.as_str(), list.stderr.as_str()),
        (Some(0), "/set_bool_server\n", ""),
        "{list:?}"
    );
    assert_eq!(
        daemon_children(D),
        Vec::<u32>::new(),
        "--no-daemon started one"
    );

    // As typed: the first query starts the daemon, which answers it completely; the next ones
    // are answered by the same daemon.
    let first = horus_as_typed(D, &["node", "list"]);
    let mut daemon = DaemonGuard::adopt(D);
    assert_eq!(
        (first.code, first.stdout.as_str(), first.stderr.as_str()),
        (Some(0), "/set_bool_server\n", ""),
        "{first:?}"
    );
    let info = horus_as_typed(D, &["service", "info", "-v", "/set_bool"]);
    assert_complete_service_info(&info);
    assert_eq!(
        daemon_children(D),
        vec![daemon.pid],
        "one daemon, the first"
    );
    let stop = horus_as_typed(D, &["daemon", "stop"]);
    assert_eq!(stop.stdout, "The daemon has been stopped\n", "{stop:?}");
    assert!(
        daemon.wait_exit(common::daemon::EXIT_LIMIT).is_some(),
        "the daemon did not exit"
    );
}

#[test]
fn service_echo_finds_the_type_of_an_rclpy_service() {
    const D: u32 = 196;
    adopt_orphans();
    // A server and a client with introspection (contents), the client calling every 0.2 s.
    let _peer = rclpy_peer(D, &["--client", "--introspection", "contents"]);
    let run = horus_as_typed(D, &["service", "echo", "/set_bool", "--count", "2"]);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""), "{run:?}");
    let events: Vec<&str> = run.stdout.split_terminator("---\n").collect();
    assert_eq!(events.len(), 2, "{run:?}");
    for event in events {
        assert!(event.starts_with("info:\n  event_type: "), "{run:?}");
        assert!(
            event.contains("\nrequest:") && event.contains("\nresponse:"),
            "{run:?}"
        );
    }
    // A set_bool request's contents: `data: true` or `data: false`.
    assert!(run.stdout.contains("- data: "), "{run:?}");
    assert_eq!(
        daemon_children(D),
        Vec::<u32>::new(),
        "service echo uses its own participant"
    );
}

/// A run that ended well before `--spin-time`: the wait was not held (a "did not hang" bound,
/// far from the 60 s asked for).
fn assert_not_held(run: &Run, took: Duration) {
    assert!(
        took < Duration::from_secs(30),
        "the wait was held: {took:?} {run:?}"
    );
}

#[test]
fn a_participant_that_is_not_ros_neither_holds_the_wait_nor_is_warned_about() {
    const D: u32 = 197;
    adopt_orphans();
    let d = D.to_string();
    let _bare = Peer::start_path(
        &cli_peer_script("bare_participant.py"),
        &[&d, "plain", LINGER],
        common::PEER_START,
    );
    // A ROS node next to it: still waited for.
    let context = Context::builder().domain_id(D).build().expect("context");
    let _node = context.create_node("here", "/").expect("node");

    let timed = |args: &[&str]| {
        let start = Instant::now();
        let run = horus_as_typed(D, args);
        (run, start.elapsed())
    };
    // However long --spin-time, the wait ends once the ROS node is complete.
    let (run, took) = timed(&["--no-daemon", "--spin-time", "60", "node", "list"]);
    assert_eq!(
        (run.code, run.stdout.as_str(), run.stderr.as_str()),
        (Some(0), "/here\n", ""),
        "{run:?}"
    );
    assert_not_held(&run, took);
    // The same through the daemon the first query starts, and its later answers.
    let (run, took) = timed(&["--spin-time", "60", "node", "list"]);
    let _daemon = DaemonGuard::adopt(D);
    assert_eq!(
        (run.code, run.stdout.as_str(), run.stderr.as_str()),
        (Some(0), "/here\n", ""),
        "{run:?}"
    );
    assert_not_held(&run, took);
    let (run, took) = timed(&["--spin-time", "60", "--json", "graph"]);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""), "{run:?}");
    assert_not_held(&run, took);
    let stop = horus_as_typed(D, &["daemon", "stop"]);
    assert_eq!(stop.stdout, "The daemon has been stopped\n", "{stop:?}");
}
