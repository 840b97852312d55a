//! `horus-ros action list | info | type | send_goal` against real rclpy action endpoints
//! (Jazzy, Fast DDS; `peers/jazzy_fibonacci.py`, test_msgs' Fibonacci): what ros2action 0.32
//! prints, line for line (the expected texts follow `ros2action/verb/*.py`), the goal sent to
//! rclpy's `ActionServer` accepted, its feedback in order, its result, a rejected goal, and a goal
//! canceled by an interrupt.
//!
//! Each test has its own DDS domain. Run inside the private network namespace
//! (`scripts/isolated`), on each backend (`HORUS_ROS_BACKEND`).

mod common;

use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::streaming::Streaming;
use common::{cli_peer_script, expect, expect_json, jazzy_prefix, Peer, Run};
use serde_json::Value;

/// Python start-up and rclpy's first discovery on a loaded machine.
const RCLPY_START: Duration = Duration::from_secs(60);
/// How long a line of `send_goal` may take (discovery, then one step of the goal).
const LINE: Duration = Duration::from_secs(30);

/// An rclpy action server (`server`) or client (`client`) of `/fibonacci`, steps `step` s apart.
fn peer(domain: u32, role: &str, node: &str, step: &str) -> Peer {
    Peer::start_path(
        &cli_peer_script("jazzy_fibonacci.py"),
        &[&domain.to_string(), role, node, "/fibonacci", step, "120"],
        RCLPY_START,
    )
}

/// `horus-ros --domain-id <domain> action send_goal <args…>`, started, its stdout read line
/// by line; with `AMENT_PREFIX_PATH` the Jazzy install when `installed`, else unset.
struct SendGoal {
    process: Streaming,
    /// Its stderr, read as it comes.
    stderr: mpsc::Receiver<String>,
    /// What it printed so far, each line with its newline.
    stdout: String,
}

impl SendGoal {
    /// To an rclpy server: rclpy's services speak rmw_fastrtps' request/reply convention,
    /// which only the rustdds backend speaks (a Cyclone DDS context reports the server
    /// unusable), so the goals go out on rustdds whatever HORUS_ROS_BACKEND says.
    fn start(domain: u32, args: &[&str], installed: bool) -> Self {
        Self::start_on(domain, args, installed, &["--backend", "rustdds"])
    }

    /// [`start`](Self::start) with these global options (none: the test's backend).
    fn start_on(domain: u32, args: &[&str], installed: bool, global: &[&str]) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
        command
            .args(global)
            .arg("--domain-id")
            .arg(domain.to_string())
            .args(["action", "send_goal"])
            .args(args)
            .env_remove("ROS_DOMAIN_ID")
            .env_remove("AMENT_PREFIX_PATH");
        if installed {
            command.env("AMENT_PREFIX_PATH", jazzy_prefix());
        }
        command
            .env("RUST_LOG", "error")
            .stdin(Stdio::null())
            .stderr(Stdio::piped());
        let mut process = Streaming::spawn(&mut command).expect("start horus-ros action send_goal");
        let stderr = process.child().stderr.take().expect("piped stderr");
        Self {
            process,
            stderr: horus_ros_test_support::read_all(stderr),
            stdout: String::new(),
        }
    }

    /// The next line, within [`LINE`].
    fn line(&mut self) -> String {
        let line = self.process.next_line(LINE).unwrap_or_else(|| {
            panic!(
                "send_goal printed no further line; so far:\n{}",
                self.stdout
            )
        });
        self.stdout.push_str(&line);
        self.stdout.push('\n');
        line
    }

    /// Its process id.
    fn pid(&mut self) -> u32 {
        self.process.child().id()
    }

    /// The remaining output and the exit code.
    fn finish(mut self) -> Run {
        let pid = self.pid();
        let (rest, code) = self.process.finish(common::RUN_LIMIT);
        Run {
            code,
            stdout: self.stdout + &rest,
            stderr: self.stderr.recv_timeout(LINE).unwrap_or_default(),
            pid,
        }
    }
}

/// The Fibonacci sequence of test_msgs' action for `order` (ros2 `action_tutorials`).
fn fibonacci(order: usize) -> Vec<i64> {
    let mut s = vec![0, 1];
    for i in 1..order {
        s.push(s[i] + s[i - 1]);
    }
    s
}

/// `message_to_yaml` of a message whose one field is the `int32[] sequence`: PyYAML's block
/// list at the indent of the key.
fn sequence_yaml(s: &[i64]) -> String {
    let mut out = "sequence:\n".to_owned();
    for v in s {
        out.push_str(&format!("- {v}\n"));
    }
    out
}

#[test]
fn list_info_and_type_show_rclpy_servers_and_clients() {
    let domain = 201;
    let _server = peer(domain, "server", "fibonacci_action_server", "0.1");
    let _client = peer(domain, "client", "fibonacci_action_client", "0.1");
    expect(domain, &["action", "list"], "/fibonacci\n");
    expect(
        domain,
        &["action", "list", "-t"],
        "/fibonacci [test_msgs/action/Fibonacci]\n",
    );
    expect(domain, &["action", "list", "-c"], "1\n");
    expect(
        domain,
        &["action", "type", "/fibonacci"],
        "test_msgs/action/Fibonacci\n",
    );
    expect(
        domain,
        &["action", "info", "/fibonacci"],
        "Action: /fibonacci\nAction clients: 1\n    /fibonacci_action_client\nAction servers: 1\n    \
         /fibonacci_action_server\n",
    );
    expect(
        domain,
        &["action", "info", "fibonacci", "-t"],
        "Action: fibonacci\nAction clients: 1\n    /fibonacci_action_client \
         [test_msgs/action/Fibonacci]\nAction servers: 1\n    /fibonacci_action_server \
         [test_msgs/action/Fibonacci]\n",
    );
    expect(
        domain,
        &["action", "info", "/fibonacci", "-c"],
        "Action: /fibonacci\nAction clients: 1\nAction servers: 1\n",
    );
    let doc = expect_json(domain, &["--json", "action", "info", "/fibonacci"], |d| {
        d["servers"].as_array().is_some_and(|s| s.len() == 1)
            && d["clients"].as_array().is_some_and(|c| c.len() == 1)
    });
    assert_eq!(doc["servers"][0]["node"], "/fibonacci_action_server");
    assert_eq!(doc["clients"][0]["types"][0], "test_msgs/action/Fibonacci");

    // An unknown action: nothing printed, exit 1 (type.py returns 1).
    let run = common::horus(domain, &["action", "type", "/nothing"]);
    assert_eq!((run.code, run.stdout.as_str()), (Some(1), ""), "{run:?}");

    // node info lists the action under the server's and the client's node.
    let server_info = common::horus(domain, &["node", "info", "/fibonacci_action_server"]);
    assert!(
        server_info
            .stdout
            .contains("  Action Servers:\n    /fibonacci: test_msgs/action/Fibonacci\n"),
        "{server_info:?}"
    );
    let client_info = common::horus(domain, &["node", "info", "/fibonacci_action_client"]);
    assert!(
        client_info
            .stdout
            .contains("  Action Clients:\n    /fibonacci: test_msgs/action/Fibonacci\n"),
        "{client_info:?}"
    );
}

/// The goal's output up to its id: ros2action's first lines.
fn goal_sent(send: &mut SendGoal, order: i64) -> String {
    assert_eq!(
        send.line(),
        "Waiting for an action server to become available..."
    );
    assert_eq!(send.line(), "Sending goal:");
    assert_eq!(send.line(), format!("     order: {order}"));
    assert_eq!(send.line(), "");
    let accepted = send.line();
    let id = accepted
        .strip_prefix("Goal accepted with ID: ")
        .unwrap_or_else(|| panic!("not an accepted goal: {accepted:?}\n{}", send.stdout))
        .to_owned();
    assert_eq!(id.len(), 32, "a UUID in hex: {id}");
    assert!(id.bytes().all(|b| b.is_ascii_hexdigit()));
    assert_eq!(send.line(), "");
    id
}

/// Runs one goal of `order` with `--feedback` and checks all it prints: each feedback a growing
/// prefix of the sequence, in order (a feedback sent before the server's writer matched our
/// reader may be lost: its topic is VOLATILE), then the result and SUCCEEDED.
fn goal_succeeds_with_feedback(domain: u32) {
    let order = 6;
    let mut send = SendGoal::start(
        domain,
        &[
            "/fibonacci",
            "test_msgs/action/Fibonacci",
            "{order: 6}",
            "-f",
        ],
        true,
    );
    goal_sent(&mut send, order);
    let full = fibonacci(order as usize);
    let mut last_len = 0;
    loop {
        let line = send.line();
        if line == "Result:" {
            break;
        }
        assert_eq!(line, "Feedback:", "{}", send.stdout);
        let first = send.line();
        assert_eq!(first, "    sequence:", "{}", send.stdout);
        let mut got = Vec::new();
        loop {
            let item = send.line();
            if item.is_empty() {
                break;
            }
            let v: i64 = item
                .strip_prefix("- ")
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("not a list item: {item:?}\n{}", send.stdout));
            got.push(v);
        }
        assert!(
            got.len() > last_len,
            "feedback out of order:\n{}",
            send.stdout
        );
        assert_eq!(got[..], full[..got.len()], "{}", send.stdout);
        last_len = got.len();
    }
    let run = send.finish();
    let tail = format!(
        "Result:\n    {}\nGoal finished with status: SUCCEEDED\n",
        sequence_yaml(&full)
    );
    assert!(run.stdout.ends_with(&tail), "{run:?}");
    assert!(last_len > 0, "no feedback at all:\n{}", run.stdout);
    assert_eq!(run.code, Some(0), "{run:?}");
}

#[test]
fn send_goal_to_an_rclpy_server_prints_feedback_and_result() {
    let domain = 202;
    let _server = peer(domain, "server", "fibonacci_action_server", "0.25");
    goal_succeeds_with_feedback(domain);
}

#[test]
fn send_goal_needs_the_type_installed() {
    // ros2action imports the type; without AMENT_PREFIX_PATH there is nothing to read it from.
    let domain = 203;
    let send = SendGoal::start(domain, &["/fibonacci", "test_msgs/action/Fibonacci"], false);
    let run = send.finish();
    assert_eq!(run.code, Some(1), "{run:?}");
    assert_eq!(
        run.stderr, "The passed action type is invalid\n",
        "ros2action's words: {run:?}"
    );
}

#[test]
fn a_rejected_goal_says_so() {
    let domain = 204;
    let _server = peer(domain, "server", "fibonacci_action_server", "0.1");
    let mut send = SendGoal::start(
        domain,
        &["/fibonacci", "test_msgs/Fibonacci", "{order: -1}"],
        true,
    );
    let run = {
        assert_eq!(
            send.line(),
            "Waiting for an action server to become available..."
        );
        send.finish()
    };
    assert_eq!(
        run.stdout,
        "Waiting for an action server to become available...\nSending goal:\n     order: -1\n\n\
         Goal was rejected.\n",
        "{run:?}"
    );
    assert_eq!(run.code, Some(0), "{run:?}");
}

#[test]
fn an_interrupt_cancels_the_goal() {
    let domain = 205;
    let mut server = peer(domain, "server", "fibonacci_action_server", "0.5");
    let mut send = SendGoal::start(
        domain,
        &[
            "/fibonacci",
            "test_msgs/action/Fibonacci",
            "{order: 40}",
            "-f",
        ],
        true,
    );
    goal_sent(&mut send, 40);
    // Executing: a feedback came, so the server has published the status EXECUTING.
    assert_eq!(send.line(), "Feedback:", "{}", send.stdout);
    let pid = nix::unistd::Pid::from_raw(send.pid() as i32);
    nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGINT).expect("SIGINT");
    let run = send.finish();
    assert!(
        run.stdout.ends_with("Canceling goal...\nGoal canceled.\n"),
        "{run:?}"
    );
    assert_eq!(run.code, Some(2), "{run:?}");
    let deadline = Instant::now() + LINE;
    let line = server
        .line_by(deadline)
        .expect("the server reports the cancel");
    let canceled: Value = serde_json::from_str(&line).expect("JSON");
    assert_eq!(canceled["canceled"], true);
}

#[test]
fn send_goal_to_a_horus_ros_server_on_this_backend() {
    // Our own action server, on the backend the suite runs (HORUS_ROS_BACKEND), so the CLI's
    // goal crosses in that backend's service convention (rmw_cyclonedds' on Cyclone DDS).
    let domain = 206;
    let context = horus_ros_rmw::Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let _server = common::fibonacci::fibonacci_server(&context);
    let mut send = SendGoal::start_on(
        domain,
        &["/fibonacci", "test_msgs/action/Fibonacci", "{order: 4}"],
        true,
        &[],
    );
    goal_sent(&mut send, 4);
    let run = send.finish();
    assert!(
        run.stdout.ends_with(&format!(
            "Result:\n    {}\nGoal finished with status: SUCCEEDED\n",
            sequence_yaml(&fibonacci(4))
        )),
        "{run:?}"
    );
    assert_eq!(run.code, Some(0), "{run:?}");
}
