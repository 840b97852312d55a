//! horus-ros actions against real ROS 2 Jazzy processes (rclpy 7.1 on the run's RMW,
//! `HORUS_ROS_PEER_RMW`: rmw_fastrtps_cpp by default, or rmw_cyclonedds_cpp;
//! `tests/peers/jazzy_fibonacci.py`), on test_msgs' Fibonacci:
//!
//! - our [`ActionClient`] drives rclpy's `ActionServer`: an accepted goal (feedback in order,
//!   result), a rejected goal, a cancel mid-goal, two goals at once, and the server process
//!   killed mid-goal (the client's waits end with `ServerGone`);
//! - rclpy's `ActionClient` drives our [`ActionServer`]: the same cases.
//!
//! With rmw_fastrtps peers the actions' services need `related_sample_identity` (rmw_fastrtps'
//! service convention), which only the rustdds backend speaks: on the Cyclone backend (like
//! rmw_cyclonedds itself) the tests check the refusal instead (our goal requests fail at once
//! with a transport error; rclpy's get no answer). rmw_cyclonedds peers are served and called on
//! both backends.
//!
//! Run inside `scripts/isolated`; each test has its own DDS domain.

mod common;

use std::process::{Child, Command, Stdio};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use common::{fibonacci, server_builder, WAIT};
use horus_ros_actions::interfaces::test_msgs::action::{Fibonacci, FibonacciGoal};
use horus_ros_actions::prelude::*;
use horus_ros_actions::{FeedbackError, GetResultError, SendGoalError};
use horus_ros_msgs::action_msgs::msg::GoalStatus;
use horus_ros_msgs::action_msgs::srv::CancelGoalResponse;
use horus_ros_services::TransportError;
use horus_ros_test_support::jazzy::Rmw;
use serde_json::Value;

/// How long the killed server may take to be noticed: its participant's lease (Fast DDS: 20 s,
/// Cyclone DDS: 10 s) and margin.
const LEASE_WAIT: Duration = Duration::from_secs(60);

/// An rclpy process, its JSON lines read as they come.
struct Peer {
    child: Child,
    lines: Receiver<String>,
    seen: Vec<Value>,
}

impl Peer {
    fn start(domain: u32, args: &[&str]) -> Self {
        let script = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/peers/jazzy_fibonacci.py"
        );
        let mut child = Command::new(horus_ros_test_support::jazzy::python())
            .arg(script)
            .args(args)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("RMW_IMPLEMENTATION", Rmw::of_peers().name())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("start the rclpy peer");
        let lines = horus_ros_test_support::line_reader(child.stdout.take().expect("stdout"));
        Self {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// The next line with `key`, waiting at most `limit` (lines before it are kept in `seen`).
    fn wait_for(&mut self, key: &str, limit: Duration) -> Value {
        let deadline = Instant::now() + limit;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let line = self
                .lines
                .recv_timeout(left)
                .unwrap_or_else(|e| panic!("no {key:?} from the peer ({e}); saw {:?}", self.seen));
            let Ok(value) = serde_json::from_str::<Value>(&line) else {
                continue;
            };
            self.seen.push(value.clone());
            if value.get(key).is_some() {
                return value;
            }
        }
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        self.kill();
    }
}

fn node(domain: u32, name: &str) -> Node {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    context.create_node(name, "/").expect("node")
}

/// Whether this backend cannot speak the peers' service convention (rmw_fastrtps').
fn refusing(node: &Node) -> bool {
    !node.context().capabilities().carries_sample_identity
        && Rmw::of_peers().needs_sample_identity()
}

fn rclpy_server(domain: u32, action: &str) -> Peer {
    let mut peer = Peer::start(domain, &["server", action, "0.2"]);
    peer.wait_for("ready", WAIT);
    peer
}

fn our_client(node: &Node, action: &str) -> ActionClient<Fibonacci> {
    ActionClient::<Fibonacci>::builder()
        .node(node)
        .name(action)
        .build()
        .expect("client")
}

/// On the Cyclone backend with rmw_fastrtps peers: the rclpy server shows up, and a goal is
/// refused at once.
fn check_refusal(client: &ActionClient<Fibonacci>) {
    let graph = horus_ros_graph::Graph::of(client.node().context()).expect("graph");
    let send_goal = format!("{}/_action/send_goal", client.action_name());
    assert!(
        graph.wait_until(WAIT, |c| c.service_is_available(&send_goal)),
        "the rclpy action server never showed up"
    );
    // A pending call keeps waiting for a usable server until its timeout, then says why none is.
    let err = client
        .send_goal(FibonacciGoal { order: 3 }, Duration::from_secs(3))
        .expect_err("refused");
    match err {
        SendGoalError::Transport(TransportError::NoUsableServer { service, cause }) => {
            assert!(service.ends_with("/_action/send_goal"), "{service}");
            assert!(cause.to_string().contains("rmw_fastrtps"), "{cause}");
        }
        other => panic!("not refused as unusable: {other:?}"),
    }
}

#[test]
fn our_client_drives_rclpy_server_goal_feedback_result() {
    const DOMAIN: u32 = 121;
    let node = node(DOMAIN, "horus_action_client");
    let _peer = rclpy_server(DOMAIN, "/jazzy_fib");
    let client = our_client(&node, "/jazzy_fib");
    if refusing(&node) {
        return check_refusal(&client);
    }
    assert!(client.wait_for_server(WAIT), "server never ready");
    let goal = client
        .send_goal(FibonacciGoal { order: 10 }, WAIT)
        .expect("accepted");
    let mut feedback = Vec::new();
    loop {
        match goal.recv_feedback(WAIT) {
            Ok(fb) => feedback.push(fb.sequence),
            Err(FeedbackError::GoalEnded) => break,
            Err(e) => panic!("feedback: {e}"),
        }
    }
    let (state, result) = goal.get_result(WAIT).expect("result");
    assert_eq!(state, GoalState::Succeeded);
    assert_eq!(result.sequence, fibonacci(10));
    // Every feedback, in order (rclpy publishes 9; a last one may trail the final status).
    assert!(feedback.len() >= 8, "{feedback:?}");
    for (i, fb) in feedback.iter().enumerate() {
        assert_eq!(fb[..], fibonacci(10)[..i + 3], "feedback {i}");
    }
}

#[test]
fn our_client_drives_rclpy_server_reject_and_cancel() {
    const DOMAIN: u32 = 122;
    let node = node(DOMAIN, "horus_action_client");
    let _peer = rclpy_server(DOMAIN, "/jazzy_fib");
    let client = our_client(&node, "/jazzy_fib");
    if refusing(&node) {
        return check_refusal(&client);
    }
    assert!(client.wait_for_server(WAIT), "server never ready");
    let rejected = client.send_goal(FibonacciGoal { order: 41 }, WAIT);
    assert_eq!(rejected.map(|_| ()), Err(SendGoalError::Rejected));

    let goal = client
        .send_goal(FibonacciGoal { order: 20 }, WAIT)
        .expect("accepted");
    let first = goal.recv_feedback(WAIT).expect("first feedback");
    assert_eq!(first.sequence, vec![0, 1, 1]);
    let canceling = goal.cancel(WAIT).expect("cancel accepted");
    assert_eq!(canceling.len(), 1);
    assert_eq!(canceling[0].goal_id.uuid, goal.goal_id().0);
    let (state, result) = goal.get_result(WAIT).expect("result");
    assert_eq!(state, GoalState::Canceled);
    assert!(result.sequence.len() < 21, "{:?}", result.sequence);
    assert_eq!(result.sequence[..], fibonacci(20)[..result.sequence.len()]);
    // The server goes on serving after a cancel.
    let other = client
        .send_goal(FibonacciGoal { order: 1 }, WAIT)
        .expect("accepted");
    assert_eq!(
        other.get_result(WAIT).expect("result").0,
        GoalState::Succeeded
    );
}

#[test]
fn our_client_drives_rclpy_server_two_goals_at_once() {
    const DOMAIN: u32 = 123;
    let node = node(DOMAIN, "horus_action_client");
    let _peer = rclpy_server(DOMAIN, "/jazzy_fib");
    let client = our_client(&node, "/jazzy_fib");
    if refusing(&node) {
        return check_refusal(&client);
    }
    assert!(client.wait_for_server(WAIT), "server never ready");
    let a = client.send_goal_pending(FibonacciGoal { order: 5 }, WAIT);
    let b = client.send_goal_pending(FibonacciGoal { order: 7 }, WAIT);
    let (a, b) = (a.wait().expect("a"), b.wait().expect("b"));
    let (ra, rb) = (a.get_result_pending(WAIT), b.get_result_pending(WAIT));
    assert_eq!(ra.wait().expect("a").1.sequence, fibonacci(5));
    assert_eq!(rb.wait().expect("b").1.sequence, fibonacci(7));
}

#[test]
fn our_client_learns_the_rclpy_server_was_killed() {
    const DOMAIN: u32 = 124;
    let node = node(DOMAIN, "horus_action_client");
    let mut peer = rclpy_server(DOMAIN, "/jazzy_fib");
    let client = our_client(&node, "/jazzy_fib");
    if refusing(&node) {
        return check_refusal(&client);
    }
    assert!(client.wait_for_server(WAIT), "server never ready");
    let goal = client
        .send_goal(FibonacciGoal { order: 40 }, WAIT)
        .expect("accepted");
    goal.recv_feedback(WAIT).expect("first feedback");
    let pending = goal.get_result_pending(LEASE_WAIT);
    peer.kill();
    let killed = Instant::now();
    assert_eq!(pending.wait().map(|_| ()), Err(GetResultError::ServerGone));
    // Feedback waits end too (after the feedback already held).
    loop {
        match goal.recv_feedback(LEASE_WAIT) {
            Ok(_) => continue,
            Err(e) => {
                assert_eq!(e, FeedbackError::ServerGone);
                break;
            }
        }
    }
    assert!(goal.server_gone());
    assert!(killed.elapsed() < LEASE_WAIT);
    assert!(!client.server_available());
}

/// Our server for the rclpy client, its steps released by the test.
fn our_server(
    node: &Node,
    action: &str,
) -> (ActionServer<Fibonacci>, std::sync::mpsc::SyncSender<()>) {
    let (builder, gate) = server_builder(true);
    let server = builder.node(node).name(action).build().expect("server");
    (server, gate.expect("gated"))
}

#[test]
fn rclpy_client_drives_our_server_goal_feedback_result() {
    const DOMAIN: u32 = 125;
    let node = node(DOMAIN, "horus_action_server");
    let (_server, gate) = our_server(&node, "/horus_fib");
    if refusing(&node) {
        for _ in 0..10 {
            gate.send(()).expect("step");
        }
        let mut peer = Peer::start(DOMAIN, &["client", "/horus_fib", "accept", "5"]);
        let done = peer.wait_for("done", WAIT);
        assert_eq!(done["ok"], false, "{:?}", peer.seen);
        return;
    }
    let mut peer = Peer::start(DOMAIN, &["client", "/horus_fib", "accept", "30"]);
    peer.wait_for("accepted", WAIT);
    // One step at a time, each released once the peer printed the feedback of the one before
    // (rclpy stops taking feedback once the result is in: steps run at once would outrun it).
    for i in 0..9 {
        gate.send(()).expect("step");
        let fb = peer.wait_for("feedback", WAIT);
        assert_eq!(
            fb["feedback"],
            serde_json::json!(fibonacci(10)[..i + 3]),
            "feedback {i}"
        );
    }
    let result = peer.wait_for("result", WAIT);
    assert_eq!(result["status"], i64::from(GoalStatus::STATUS_SUCCEEDED));
    assert_eq!(result["result"], serde_json::json!(fibonacci(10)));
    assert_eq!(peer.wait_for("done", WAIT)["ok"], true, "{:?}", peer.seen);
}

#[test]
fn rclpy_client_drives_our_server_reject() {
    const DOMAIN: u32 = 126;
    let node = node(DOMAIN, "horus_action_server");
    let (_server, _gate) = our_server(&node, "/horus_fib");
    if refusing(&node) {
        return;
    }
    let mut peer = Peer::start(DOMAIN, &["client", "/horus_fib", "reject", "30"]);
    let done = peer.wait_for("done", WAIT + WAIT);
    assert_eq!(done["ok"], true, "{:?}", peer.seen);
    assert!(
        peer.seen.iter().any(|v| v["accepted"] == false),
        "{:?}",
        peer.seen
    );
}

#[test]
fn rclpy_client_cancels_on_our_server() {
    const DOMAIN: u32 = 127;
    let node = node(DOMAIN, "horus_action_server");
    let (server, gate) = our_server(&node, "/horus_fib");
    if refusing(&node) {
        return;
    }
    let mut peer = Peer::start(DOMAIN, &["client", "/horus_fib", "cancel", "30"]);
    peer.wait_for("accepted", WAIT);
    gate.send(()).expect("first step");
    let cancel = peer.wait_for("cancel", WAIT);
    assert_eq!(cancel["cancel"], i64::from(CancelGoalResponse::ERROR_NONE));
    assert_eq!(cancel["canceling"], 1);
    assert!(server
        .goals()
        .iter()
        .all(|(_, s)| *s == GoalState::Canceling));
    gate.send(()).expect("next step");
    let result = peer.wait_for("result", WAIT);
    assert_eq!(result["status"], i64::from(GoalStatus::STATUS_CANCELED));
    assert_eq!(result["result"], serde_json::json!([0, 1, 1]));
    assert_eq!(peer.wait_for("done", WAIT)["ok"], true);
}

#[test]
fn rclpy_client_sends_two_goals_at_once_to_our_server() {
    const DOMAIN: u32 = 128;
    let node = node(DOMAIN, "horus_action_server");
    let (server, gate) = our_server(&node, "/horus_fib");
    if refusing(&node) {
        return;
    }
    let mut peer = Peer::start(DOMAIN, &["client", "/horus_fib", "two", "30"]);
    let differ = peer.wait_for("ids_differ", WAIT);
    assert_eq!(differ["ids_differ"], true);
    // Both goals are active at the server at once before any step is released.
    assert_eq!(server.goals().len(), 2);
    assert!(server.goals().iter().all(|(_, s)| s.is_active()));
    for _ in 0..12 {
        gate.send(()).expect("step");
    }
    assert_eq!(peer.wait_for("done", WAIT)["ok"], true, "{:?}", peer.seen);
    for (i, order) in [(0, 5), (1, 7)] {
        let r = peer.seen.iter().find(|v| v["goal"] == i).expect("result");
        assert_eq!(r["status"], i64::from(GoalStatus::STATUS_SUCCEEDED));
        assert_eq!(r["result"], serde_json::json!(fibonacci(order)));
    }
}
