//! What the zenoh tests share: a router of our own, `horus-ros --backend zenoh` joining it, the
//! rmw_zenoh peer (`peers/zenoh_rmw_peer.py`), and processes read line by line.

#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use serde_json::Value;

/// How long a process may take to print an expected line.
pub const LIMIT: Duration = Duration::from_secs(20);

/// The interpreter with eclipse-zenoh and xxhash.
pub fn python() -> PathBuf {
    std::env::var_os("HORUS_ROS_ZENOH_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(crate::common::python)
}

/// `ZENOH_CONFIG_OVERRIDE` of a session that joins the router on `port`.
pub fn session_override(port: u16) -> String {
    format!(r#"connect/endpoints=["tcp/127.0.0.1:{port}"];listen/endpoints=["tcp/127.0.0.1:0"]"#)
}

/// A process whose stdout is read line by line; killed when dropped.
pub struct Proc {
    /// The process.
    pub child: Child,
    lines: mpsc::Receiver<String>,
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
            name: name.to_owned(),
        }
    }

    /// Reads lines until one satisfies `want`, at most [`LIMIT`]; that line.
    pub fn line_where(&mut self, what: &str, mut want: impl FnMut(&str) -> bool) -> String {
        let deadline = Instant::now() + LIMIT;
        let mut seen = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) if want(&line) => return line,
                Ok(line) => seen.push(line),
                Err(_) => panic!(
                    "{}: no line {what} within {LIMIT:?}; it printed:\n{}",
                    self.name,
                    seen.join("\n")
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

/// The peer, once it printed its tokens.
pub fn talker(port: u16, domain: u32, extra: &[&str]) -> (Proc, Value) {
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/zenoh_rmw_peer.py");
    let mut command = Command::new(python());
    command
        .arg(&script)
        .args([port.to_string(), domain.to_string(), "60".to_owned()])
        .args(extra);
    let mut peer = Proc::spawn(command, "zenoh_rmw_peer.py");
    let line = peer.line_where("of JSON", |l| l.starts_with('{'));
    let created: Value = serde_json::from_str(&line).expect("the peer's JSON line");
    (peer, created)
}

/// A GID as ros2cli prints it: dotted lower-case hex.
pub fn dotted(hex: &str) -> String {
    hex.as_bytes()
        .chunks(2)
        .map(|c| std::str::from_utf8(c).expect("hex"))
        .collect::<Vec<_>>()
        .join(".")
}

pub fn field<'a>(v: &'a Value, name: &str) -> &'a str {
    v[name]
        .as_str()
        .unwrap_or_else(|| panic!("no {name} in {v}"))
}
