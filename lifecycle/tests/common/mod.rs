//! The rclpy peer of the lifecycle tests (`peers/jazzy_lifecycle.py`) and what the tests share.

#![allow(dead_code)]

use std::io::Write;
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_rmw::backend::Backend;
use horus_ros_rmw::{Context, Gid};
use horus_ros_test_support::jazzy::Rmw;
use serde_json::{json, Value};

/// The bound on every wait for the peer (its start includes importing rclpy).
pub const LIMIT: Duration = Duration::from_secs(30);
/// The bound on one of our service calls.
pub const CALL: Duration = Duration::from_secs(10);

/// A context in `domain` whose services reach the rclpy peers: on the backend the environment
/// chooses (HORUS_ROS_BACKEND), except where the peers' RMW correlates replies through
/// `related_sample_identity` (rmw_fastrtps), which that backend cannot carry (the Cyclone
/// backend, as rmw_cyclonedds cannot): then on the rustdds backend.
pub fn service_context(domain: u32) -> Context {
    let chosen = Backend::from_env_with(|name| std::env::var(name).ok()).expect("a backend");
    let backend = if !chosen
        .capabilities()
        .is_some_and(|c| c.carries_sample_identity)
        && Rmw::of_peers().needs_sample_identity()
    {
        Backend::RustDds
    } else {
        chosen
    };
    Context::builder()
        .domain_id(domain)
        .backend(backend)
        .build()
        .expect("context")
}

/// A context in `domain` on the backend the environment chooses (HORUS_ROS_BACKEND).
pub fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

/// A running `jazzy_lifecycle.py`; asked to leave (stdin closed) and reaped when dropped.
pub struct Peer {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: Receiver<String>,
    stderr: Receiver<String>,
    /// Every line printed so far, in order.
    pub printed: Vec<Value>,
    replies_taken: usize,
}

impl Peer {
    /// Starts the peer with `spec` and waits for its ready line.
    pub fn start(spec: &Value) -> Peer {
        let script =
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/jazzy_lifecycle.py");
        let mut child = Command::new(horus_ros_test_support::jazzy::python())
            .arg(script)
            .arg(spec.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start the rclpy peer (scripts/setup makes its environment)");
        let stdin = child.stdin.take();
        let lines = horus_ros_test_support::line_reader(child.stdout.take().expect("stdout"));
        let stderr = horus_ros_test_support::read_all(child.stderr.take().expect("stderr"));
        let mut peer = Peer {
            child,
            stdin,
            lines,
            stderr,
            printed: Vec::new(),
            replies_taken: 0,
        };
        peer.wait_for("the ready line", |p| {
            p.iter().find_map(|l| l.get("ready").cloned())
        });
        peer
    }

    /// Waits (at most [`LIMIT`]) until `found` gives something from the lines printed so far,
    /// checked at once and after every new line; panics with the peer's output past that.
    pub fn wait_for<T>(&mut self, what: &str, mut found: impl FnMut(&[Value]) -> Option<T>) -> T {
        let deadline = Instant::now() + LIMIT;
        loop {
            if let Some(t) = found(&self.printed) {
                return t;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => self
                    .printed
                    .push(serde_json::from_str(&line).unwrap_or(Value::String(line))),
                Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => {
                    let output = self.fail();
                    panic!("{what}: not within {LIMIT:?}\n{output}");
                }
            }
        }
    }

    /// Kills the peer and gives everything it printed.
    pub fn fail(&mut self) -> String {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let stderr = self.stderr.recv_timeout(LIMIT).unwrap_or_default();
        let stdout: Vec<String> = self.printed.iter().map(Value::to_string).collect();
        format!(
            "--- peer stdout:\n{}\n--- peer stderr:\n{stderr}",
            stdout.join("\n")
        )
    }

    /// Sends one command and waits for its reply.
    pub fn command(&mut self, command: Value) -> Value {
        let stdin = self.stdin.as_mut().expect("stdin open");
        writeln!(stdin, "{command}").expect("write to the peer");
        stdin.flush().expect("flush");
        let n = self.replies_taken;
        let reply = self.wait_for(&format!("the reply to {command}"), |p| {
            p.iter().filter_map(|l| l.get("reply")).nth(n).cloned()
        });
        self.replies_taken += 1;
        reply
    }

    /// Calls `service` (`get_state`, `change_state`, …) of `node` from rclpy.
    pub fn call(&mut self, node: &str, service: &str, extra: Value) -> Value {
        let mut command = json!({"call": service, "node": node});
        if let (Some(c), Some(e)) = (command.as_object_mut(), extra.as_object()) {
            c.extend(e.clone());
        }
        self.command(command)
    }

    /// Sets what the peer's lifecycle callbacks return next.
    pub fn behave(&mut self, behaviour: Value) {
        assert_eq!(self.command(json!({ "behave": behaviour })), json!("ok"));
    }

    /// The values of the lines with `key`, in order.
    pub fn all(&self, key: &str) -> Vec<Value> {
        self.printed
            .iter()
            .filter_map(|v| v.get(key).cloned())
            .collect()
    }

    /// Waits until the peer has printed `n` lines with `key`; returns them all.
    pub fn wait_count(&mut self, key: &str, n: usize) -> Vec<Value> {
        self.wait_for(&format!("{n} {key} lines"), |p| {
            let all: Vec<Value> = p.iter().filter_map(|v| v.get(key).cloned()).collect();
            (all.len() >= n).then_some(all)
        })
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        self.stdin = None;
        let _ = horus_ros_test_support::wait_exit(&mut self.child, LIMIT);
    }
}

/// Waits until our endpoint `local` is matched with an endpoint of `topic` (a subscription
/// when `ours_is_writer`, else a publisher) that is not ours; panics past [`LIMIT`].
pub fn wait_matched(graph: &Graph, local: Gid, topic: &str, ours_is_writer: bool) {
    let deadline = Instant::now() + LIMIT;
    let mut remote = None;
    assert!(
        graph.wait_until(LIMIT, |c| {
            let infos = if ours_is_writer {
                c.subscriptions_info_by_topic(topic, false)
            } else {
                c.publishers_info_by_topic(topic, false)
            };
            remote = infos
                .iter()
                .map(|i| i.endpoint_gid)
                .find(|g| *g != local && g.as_bytes()[..12] != local.as_bytes()[..12]);
            remote.is_some()
        }),
        "no peer endpoint on {topic}"
    );
    let remote = remote.expect("found above");
    let left = deadline.saturating_duration_since(Instant::now());
    assert!(
        graph.wait_for_match(local, remote, left),
        "{topic}: not matched"
    );
}

/// A `[id, label]` pair as the peer prints states and transitions.
pub fn pair(id: u8, label: &str) -> Value {
    json!([id, label])
}

/// A transition event as the peer prints it, and as rcl_lifecycle publishes it: only the start
/// and goal states are set (`rcl_lifecycle_com_interface_publish_notification`).
pub fn event(node: &str, start: (u8, &str), goal: (u8, &str)) -> Value {
    json!({"node": node, "timestamp": 0, "transition": [0, ""],
           "start": [start.0, start.1], "goal": [goal.0, goal.1]})
}

/// What a [`Scripted`] callback does next.
#[derive(Debug, Clone, Copy)]
pub enum Behave {
    /// Return this.
    Return(horus_ros_lifecycle::CallbackReturn),
    /// Panic.
    Panic,
}

/// Callbacks whose results the test sets, recording every call (name, previous state).
#[derive(Clone, Default)]
pub struct Scripted {
    next: std::sync::Arc<std::sync::Mutex<std::collections::HashMap<&'static str, Behave>>>,
    /// Every callback run, in order.
    pub calls: std::sync::Arc<std::sync::Mutex<Vec<(&'static str, horus_ros_lifecycle::State)>>>,
}

impl Scripted {
    /// What `callback` does from now on (until set again).
    pub fn set(&self, callback: &'static str, behave: Behave) {
        self.next.lock().expect("lock").insert(callback, behave);
    }

    /// Every callback run so far.
    pub fn calls(&self) -> Vec<(&'static str, horus_ros_lifecycle::State)> {
        self.calls.lock().expect("lock").clone()
    }

    fn run(
        &self,
        name: &'static str,
        previous: horus_ros_lifecycle::State,
    ) -> horus_ros_lifecycle::CallbackReturn {
        self.calls.lock().expect("lock").push((name, previous));
        let behave = self.next.lock().expect("lock").get(name).copied();
        match behave {
            Some(Behave::Return(r)) => r,
            Some(Behave::Panic) => panic!("{name} panicked on purpose"),
            None => horus_ros_lifecycle::CallbackReturn::Success,
        }
    }
}

impl horus_ros_lifecycle::LifecycleCallbacks for Scripted {
    fn on_configure(
        &mut self,
        p: horus_ros_lifecycle::State,
    ) -> horus_ros_lifecycle::CallbackReturn {
        self.run("on_configure", p)
    }
    fn on_cleanup(&mut self, p: horus_ros_lifecycle::State) -> horus_ros_lifecycle::CallbackReturn {
        self.run("on_cleanup", p)
    }
    fn on_shutdown(
        &mut self,
        p: horus_ros_lifecycle::State,
    ) -> horus_ros_lifecycle::CallbackReturn {
        self.run("on_shutdown", p)
    }
    fn on_activate(
        &mut self,
        p: horus_ros_lifecycle::State,
    ) -> horus_ros_lifecycle::CallbackReturn {
        self.run("on_activate", p)
    }
    fn on_deactivate(
        &mut self,
        p: horus_ros_lifecycle::State,
    ) -> horus_ros_lifecycle::CallbackReturn {
        self.run("on_deactivate", p)
    }
    fn on_error(&mut self, p: horus_ros_lifecycle::State) -> horus_ros_lifecycle::CallbackReturn {
        self.run("on_error", p)
    }
}
