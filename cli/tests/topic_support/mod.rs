//! What the `topic echo | hz | bw | delay` tests share: the rclpy publisher peer and the CLI run
//! as a process whose lines are read as they come (hz, bw and delay never end by themselves).

#![allow(dead_code)]

use std::process::{Command, Stdio};
use std::time::Duration;

use crate::common::{cli_peer_script, Peer, Streaming};

/// How long a line of the CLI may take (discovery, a Python peer starting up, a loaded machine).
pub const LINE_WAIT: Duration = Duration::from_secs(30);

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
pub struct Cli(Streaming);

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
        Self(Streaming::spawn(&mut command).expect("start horus-ros"))
    }

    /// The next line, within [`LINE_WAIT`].
    pub fn line(&self) -> String {
        self.0.line(LINE_WAIT)
    }

    /// Every line up to the end of output, within `limit`, and the exit code.
    pub fn finish(self, limit: Duration) -> (String, Option<i32>) {
        self.0.finish(limit)
    }
}
