//! What the zenoh tests share: a router of our own, `horus-ros --backend zenoh` joining it, a
//! real rclpy node on rmw_zenoh_cpp 0.2.10 joining it (`interop-tests/peers/jazzy_node.py`),
//! and processes read line by line.

#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use serde_json::Value;

/// How long a process may take to print an expected line.
pub const LIMIT: Duration = Duration::from_secs(20);

/// `ZENOH_CONFIG_OVERRIDE` of a session that joins the router on `port`.
pub fn session_override(port: u16) -> String {
    format!(r#"connect/endpoints=["tcp/127.0.0.1:{port}"];listen/endpoints=["tcp/127.0.0.1:0"]"#)
}

/// A process whose stdout is read line by line; killed when dropped.
pub struct Proc {
    /// The process.
    pub child: Child,
    lines: mpsc::Receiver<String>,
    /// Every line read so far.
    seen: Vec<String>,
    /// How many of them [`line_where`](Self::line_where) has gone past.
    cursor: usize,
    name: String,
}

impl Proc {
    pub fn spawn(mut command: Command, name: &str) -> Self {
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap_or_else(|e| panic!("start {name}: {e}"));
        let stdout = child.stdout.take().expect("piped stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Self {
            child,
            lines: rx,
            seen: Vec::new(),
            cursor: 0,
            name: name.to_owned(),
        }
    }

    /// Reads lines until one satisfies `want`, at most [`LIMIT`]; that line. Lines before it
    /// are passed over (but kept for [`any_line_where`](Self::any_line_where)).
    pub fn line_where(&mut self, what: &str, mut want: impl FnMut(&str) -> bool) -> String {
        let at = self.find_from(self.cursor, what, &mut want);
        self.cursor = at + 1;
        self.seen[at].clone()
    }

    /// The first line ever printed that satisfies `want` (waiting at most [`LIMIT`] for it),
    /// whatever [`line_where`](Self::line_where) passed over.
    pub fn any_line_where(&mut self, what: &str, mut want: impl FnMut(&str) -> bool) -> String {
        let at = self.find_from(0, what, &mut want);
        self.seen[at].clone()
    }

    /// The index of the first line from `from` on that satisfies `want`, reading more lines
    /// as needed (at most [`LIMIT`]).
    fn find_from(&mut self, from: usize, what: &str, want: &mut impl FnMut(&str) -> bool) -> usize {
        if let Some(i) = (from..self.seen.len()).find(|&i| want(&self.seen[i])) {
            return i;
        }
        let deadline = Instant::now() + LIMIT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    self.seen.push(line);
                    let i = self.seen.len() - 1;
                    if i >= from && want(&self.seen[i]) {
                        return i;
                    }
                }
                Err(_) => panic!(
                    "{}: no line {what} within {LIMIT:?}; it printed:\n{}",
                    self.name,
                    self.seen.join("\n")
                ),
            }
        }
    }

    /// Kills it now (SIGKILL: no goodbye, as a crash).
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        self.kill();
    }
}

/// `horus-ros router` listening on `127.0.0.1:<port>`, once it printed its ready line.
pub fn router(port: u16) -> Proc {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command.arg("router").env(
        "ZENOH_CONFIG_OVERRIDE",
        format!(r#"listen/endpoints=["tcp/127.0.0.1:{port}"]"#),
    );
    let mut router = Proc::spawn(command, "horus-ros router");
    router.line_where("'Started Zenoh router'", |l| {
        l.starts_with("Started Zenoh router with id ")
    });
    router
}

/// `horus-ros --backend zenoh <args>` joining the router on `port`, not yet waited for.
pub fn horus_command(port: u16, domain: u32, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command
        .args(["--backend", "zenoh", "--no-daemon", "--domain-id"])
        .arg(domain.to_string())
        .args(args)
        .env_remove("ROS_DOMAIN_ID")
        .env("RUST_LOG", "error")
        .env("ZENOH_CONFIG_OVERRIDE", session_override(port));
    command
}

/// Runs `horus-ros --backend zenoh <args>` to its end; its stdout.
pub fn horus(port: u16, domain: u32, args: &[&str]) -> String {
    let mut child = horus_command(port, domain, args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start horus-ros");
    let out = horus_ros_test_support::wait_with_output(&mut child, LIMIT).expect("output");
    assert_eq!(
        out.code(),
        Some(0),
        "horus-ros {args:?}: stdout {} stderr {}",
        out.stdout,
        out.stderr
    );
    out.stdout
}

/// A real rclpy node on rmw_zenoh_cpp joining the router on `port`, as `spec` describes it
/// (`interop-tests/peers/jazzy_node.py`: name, servers, clients, publishers, subscriptions,
/// `"graph": true` for rclpy's own view), once it printed its ready line.
pub fn rclpy_on_zenoh(port: u16, domain: u32, spec: &Value) -> Proc {
    let mut spec = spec.clone();
    spec["domain"] = Value::from(domain);
    let mut command = Command::new(crate::common::python());
    command
        .arg(crate::common::peer_script("jazzy_node.py"))
        .arg(spec.to_string())
        .env("RMW_IMPLEMENTATION", "rmw_zenoh_cpp")
        .env("ROS_DOMAIN_ID", domain.to_string())
        .env("ZENOH_CONFIG_OVERRIDE", session_override(port));
    let mut peer = Proc::spawn(command, "an rclpy node on rmw_zenoh_cpp");
    peer.line_where("'ready'", |l| l.starts_with("{\"ready\""));
    peer
}
