//! Helpers for tests against independent DDS implementations.
//!
//! The peers are Python programs (`peers/`): small DDS participants on the Eclipse Cyclone DDS
//! Python binding, and real ROS 2 Jazzy nodes on rclpy ([`rclpy`]), run with the interpreter
//! named by `HORUS_ROS_INTEROP_PYTHON` (set by `scripts/test` to the private virtual environment
//! that `scripts/setup` creates), else `python3`.

pub mod rclpy;

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// The Python interpreter that has the `cyclonedds` package and the ROS 2 wheels.
pub fn python() -> PathBuf {
    std::env::var_os("HORUS_ROS_INTEROP_PYTHON")
        .map_or_else(|| PathBuf::from("python3"), PathBuf::from)
}

/// A child's output, line by line as it is printed, read by a thread of its own (which ends at
/// the end of the output or when the receiver is dropped).
pub fn line_reader(
    output: impl std::io::Read + Send + 'static,
) -> std::sync::mpsc::Receiver<String> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::BufRead::lines(std::io::BufReader::new(output)) {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// The path of a peer script in `interop-tests/peers/`.
pub fn peer_script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("peers")
        .join(name)
}

/// What a finished peer printed.
#[derive(Debug)]
pub struct PeerOutput {
    /// Exit status code (`None` if killed at the deadline).
    pub code: Option<i32>,
    /// Everything it printed on stdout.
    pub stdout: String,
    /// Everything it printed on stderr.
    pub stderr: String,
}

/// A running peer process; killed when dropped.
#[derive(Debug)]
pub struct Peer {
    child: Child,
}

impl Peer {
    /// Starts `script` (in `peers/`) with `args`, capturing its output.
    pub fn start(script: &str, args: &[String]) -> std::io::Result<Self> {
        let child = Command::new(python())
            .arg(peer_script(script))
            .args(args)
            .env("CYCLONEDDS_URI", cyclone_config())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        Ok(Self { child })
    }

    /// The peer's standard output, line by line as it is printed (read by a thread of its own);
    /// `None` if already taken. [`wait`](Self::wait) then reports no standard output.
    pub fn stdout_lines(&mut self) -> Option<std::sync::mpsc::Receiver<String>> {
        Some(line_reader(self.child.stdout.take()?))
    }

    /// Waits for the peer to exit, at most `limit` (woken by its exit); kills it past that. Its
    /// output is read while it runs.
    pub fn wait(mut self, limit: Duration) -> std::io::Result<PeerOutput> {
        let out = horus_ros_test_support::wait_with_output(&mut self.child, limit)?;
        Ok(PeerOutput {
            code: out.code(),
            stdout: out.stdout,
            stderr: out.stderr,
        })
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Cyclone DDS configuration for the peers: loopback only, with multicast (the test namespace
/// routes multicast to `lo`), so they never use another interface.
pub fn cyclone_config() -> String {
    "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
     <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
     <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>"
        .to_owned()
}
