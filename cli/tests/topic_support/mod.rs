//! What the `topic echo | hz | bw | delay` tests share: the rclpy publisher peer and the CLI run
//! as a process whose lines are read as they come (hz, bw and delay never end by themselves).

#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::common::{self, cli_peer_script, Peer};

/// How long a line of the CLI may take (discovery, a Python peer starting up, a loaded machine).
pub const LINE_WAIT: Duration = Duration::from_secs(30);

/// The install prefix of the Jazzy wheels (the venv of [`common::python`]): an
/// `AMENT_PREFIX_PATH` with every Jazzy message package.
pub fn jazzy_prefix() -> PathBuf {
    let python = common::python();
    python
        .parent()
        .and_then(|bin| bin.parent())
        .map(PathBuf::from)
        .unwrap_or_default()
}

/// `cli/tests/peers/jazzy_topic_publisher.py`: an rclpy node publishing `type_name` on `topic`
/// at `rate` Hz, filled from `settings` (JSON list of `[path, value]`), stamping `header.stamp`
/// when `stamp`.
pub fn publisher(
    domain: u32,
    node: &str,
    topic: &str,
    type_name: &str,
    rate: f64,
    settings: &str,
    stamp: bool,
) -> Peer {
    Peer::start_path(
        &cli_peer_script("jazzy_topic_publisher.py"),
        &[
            &domain.to_string(),
            node,
            topic,
            type_name,
            &rate.to_string(),
            settings,
            if stamp { "stamp" } else { "none" },
            "60",
        ],
        Duration::from_secs(20),
    )
}

/// How the CLI is run.
#[derive(Clone, Copy)]
pub enum Ament<'a> {
    /// The environment's `AMENT_PREFIX_PATH`, as it is.
    Inherit,
    /// Unset.
    Unset,
    /// Set to this prefix.
    Prefix(&'a std::path::Path),
}

/// A running `horus-ros --domain-id <d> --no-daemon <args>`, its stdout lines on a channel;
/// killed when dropped.
pub struct Cli {
    child: Child,
    lines: mpsc::Receiver<String>,
}

impl Cli {
    /// Starts the CLI.
    pub fn start(domain: u32, args: &[&str], ament: Ament<'_>) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
        command
            .arg("--domain-id")
            .arg(domain.to_string())
            .arg("--no-daemon")
            .args(args)
            .env_remove("ROS_DOMAIN_ID")
            .env("RUST_LOG", "error")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit());
        match ament {
            Ament::Inherit => {}
            Ament::Unset => {
                command.env_remove("AMENT_PREFIX_PATH");
            }
            Ament::Prefix(p) => {
                command.env("AMENT_PREFIX_PATH", p);
            }
        }
        let mut child = command.spawn().expect("start horus-ros");
        let stdout = child.stdout.take().expect("piped");
        let (tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Self { child, lines }
    }

    /// The next line, within [`LINE_WAIT`].
    pub fn line(&self) -> String {
        self.lines
            .recv_timeout(LINE_WAIT)
            .expect("horus-ros printed a line in time")
    }

    /// Every line up to the end of output, within `limit`, and the exit code.
    pub fn finish(mut self, limit: Duration) -> (String, Option<i32>) {
        let deadline = Instant::now() + limit;
        let mut out = String::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    out.push_str(&line);
                    out.push('\n');
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
                Err(mpsc::RecvTimeoutError::Timeout) => panic!("horus-ros did not end:\n{out}"),
            }
        }
        let code = self.child.wait().ok().and_then(|s| s.code());
        (out, code)
    }
}

impl Drop for Cli {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
