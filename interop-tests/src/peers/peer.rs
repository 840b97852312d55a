//! One rclpy node as a peer process: `peers/jazzy_node.py`, given a JSON spec (see that file),
//! read line by line as it prints.

use std::io::Read;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use horus_ros_test_support::jazzy::Rmw;
use serde_json::Value;

/// How long a peer asked to leave (standard input closed) may take to exit before it is killed.
const LEAVE_LIMIT: Duration = Duration::from_secs(10);
/// The most stderr lines kept for failure messages (the last ones).
const STDERR_LINES: usize = 200;

/// A line from the peer, or a wake-up for whoever waits on its lines.
pub(crate) enum Line {
    /// A line the peer printed on standard output.
    Printed(String),
    /// Something else may have changed (e.g. our graph): look again.
    Wake,
    /// Its standard output ended.
    End,
}

/// A running rclpy node; asked to leave (standard input closed) and reaped when dropped.
pub struct RclpyPeer {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: Receiver<Line>,
    waker: Sender<Line>,
    /// Every JSON line printed so far, in order.
    printed: Vec<Value>,
    /// Its last stderr lines.
    stderr: Arc<Mutex<Vec<String>>>,
    /// Whether its standard output has ended.
    ended: bool,
}

impl std::fmt::Debug for RclpyPeer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RclpyPeer")
            .field("pid", &self.child.id())
            .field("printed", &self.printed.len())
            .finish()
    }
}

impl RclpyPeer {
    /// Starts a node as `spec` describes (`domain`, `namespace`, `name`, and what it has), with
    /// the interpreter of [`crate::python`], on this run's RMW ([`Rmw::of_peers`]).
    pub fn start(spec: &Value) -> Result<Self, String> {
        Self::spawn(spec, None)
    }

    /// Starts a node as [`start`](Self::start) does, on `rmw` whatever the run's peers use (for
    /// tests of one RMW's conventions).
    pub fn start_on(rmw: Rmw, spec: &Value) -> Result<Self, String> {
        Self::spawn(spec, Some(rmw))
    }

    fn spawn(spec: &Value, rmw: Option<Rmw>) -> Result<Self, String> {
        let mut command = Command::new(crate::python());
        if let Some(rmw) = rmw {
            command.env("RMW_IMPLEMENTATION", rmw.name());
        }
        let mut child = command
            .arg(crate::peer_script("jazzy_node.py"))
            .arg(spec.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| {
                format!(
                    "starting {} (scripts/setup makes the environment with rclpy): {e}",
                    crate::python().display()
                )
            })?;
        let stdin = child.stdin.take();
        let stdout = child.stdout.take().ok_or("no piped stdout")?;
        let stderr_pipe = child.stderr.take().ok_or("no piped stderr")?;
        let (tx, lines) = std::sync::mpsc::channel();
        let waker = tx.clone();
        std::thread::spawn(move || {
            for line in std::io::BufRead::lines(std::io::BufReader::new(stdout)) {
                let Ok(line) = line else { break };
                if tx.send(Line::Printed(line)).is_err() {
                    return;
                }
            }
            let _ = tx.send(Line::End);
        });
        let stderr = Arc::new(Mutex::new(Vec::new()));
        let kept = Arc::clone(&stderr);
        std::thread::spawn(move || keep_last_lines(stderr_pipe, &kept));
        Ok(Self {
            child,
            stdin,
            lines,
            waker,
            printed: Vec::new(),
            stderr,
            ended: false,
        })
    }

    /// The peer's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// A sender that wakes [`wait_for`](Self::wait_for) (to look again at something else).
    pub(crate) fn waker(&self) -> Sender<Line> {
        self.waker.clone()
    }

    /// Every JSON line printed so far, in order.
    pub fn printed(&self) -> &[Value] {
        &self.printed
    }

    /// The values of every line printed so far that is an object with `key` (`"served"`, …).
    pub fn all(&self, key: &str) -> Vec<&Value> {
        self.printed.iter().filter_map(|v| v.get(key)).collect()
    }

    /// Everything it printed so far, stdout then its last stderr lines, for failure messages.
    pub fn output(&self) -> String {
        let stdout: Vec<String> = self.printed.iter().map(Value::to_string).collect();
        let stderr = self.stderr.lock().map(|s| s.join("\n")).unwrap_or_default();
        format!(
            "--- rclpy peer stdout:\n{}\n--- stderr:\n{stderr}",
            stdout.join("\n")
        )
    }

    /// Waits at most `limit` until `found` gives something from the lines printed so far
    /// (checked at once, then after every new line or wake-up). An error says what was printed.
    pub fn wait_for<T>(
        &mut self,
        limit: Duration,
        what: &str,
        mut found: impl FnMut(&[Value]) -> Option<T>,
    ) -> Result<T, String> {
        let deadline = Instant::now() + limit;
        loop {
            if let Some(t) = found(&self.printed) {
                return Ok(t);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() || self.ended {
                return Err(format!(
                    "{what}: not within {limit:?}{}\n{}",
                    if self.ended {
                        " (the peer's output ended)"
                    } else {
                        ""
                    },
                    self.output()
                ));
            }
            self.take_line(left);
        }
    }

    /// Waits at most `limit` until the node's subscriptions have heard at least `count`
    /// messages with a `data` string field; their `data`, in the order heard.
    pub fn wait_for_heard(&mut self, limit: Duration, count: usize) -> Result<Vec<String>, String> {
        self.wait_for(
            limit,
            &format!("{count} messages heard by the rclpy node"),
            |lines| {
                let heard: Vec<String> = lines
                    .iter()
                    .filter_map(|l| l.get("heard")?["data"].as_str().map(str::to_owned))
                    .collect();
                (heard.len() >= count).then_some(heard)
            },
        )
    }

    /// Receives one line or wake-up within `limit`; false if none came.
    fn take_line(&mut self, limit: Duration) -> bool {
        match self.lines.recv_timeout(limit) {
            Ok(Line::Printed(line)) => {
                // Lines that are not JSON (none are expected) are kept as strings.
                let value = serde_json::from_str(&line).unwrap_or(Value::String(line));
                self.printed.push(value);
                true
            }
            Ok(Line::Wake) => true,
            Ok(Line::End) => {
                self.ended = true;
                true
            }
            // The peer's own sender (its waker) keeps the channel open.
            Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => false,
        }
    }

    /// Waits at most `limit` for the `{"ready": …}` line (every entity created); returns it.
    pub fn ready(&mut self, limit: Duration) -> Result<Value, String> {
        self.wait_for(limit, "the peer's ready line", |lines| {
            lines.iter().find_map(|l| l.get("ready").cloned())
        })
    }

    /// Asks the peer to leave (closes its standard input): it destroys its node and context,
    /// so that its node, endpoints and participant leave the graph.
    pub fn leave(&mut self) {
        self.stdin = None;
    }

    /// Asks the peer to leave, waits at most `limit` for it to exit (killing it past that),
    /// and reads what it printed until then. Returns its exit code (`None` if killed).
    pub fn finish(&mut self, limit: Duration) -> Result<Option<i32>, String> {
        self.leave();
        self.wait_exit(limit)
    }

    /// Waits at most `limit` for the peer to exit by itself ("leave_when_done" in its spec),
    /// killing it past that, and reads what it printed until then. Returns its exit code
    /// (`None` if killed).
    pub fn wait_exit(&mut self, limit: Duration) -> Result<Option<i32>, String> {
        let status = horus_ros_test_support::wait_exit(&mut self.child, limit)
            .map_err(|e| format!("waiting for the peer: {e}"))?;
        // Its stdout reader ends at the end of the output, just after the exit.
        let drained = Instant::now() + Duration::from_secs(5);
        while !self.ended {
            let left = drained.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            self.take_line(left);
        }
        Ok(status.and_then(|s| s.code()))
    }
}

impl Drop for RclpyPeer {
    fn drop(&mut self) {
        self.leave();
        if !matches!(
            horus_ros_test_support::wait_exit(&mut self.child, LEAVE_LIMIT),
            Ok(Some(_))
        ) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Keeps the last [`STDERR_LINES`] lines of `pipe` in `kept` until it ends.
fn keep_last_lines(pipe: impl Read, kept: &Mutex<Vec<String>>) {
    for line in std::io::BufRead::lines(std::io::BufReader::new(pipe)) {
        let Ok(line) = line else { break };
        if let Ok(mut kept) = kept.lock() {
            if kept.len() == STDERR_LINES {
                kept.remove(0);
            }
            kept.push(line);
        }
    }
}
