//! Time to a complete graph: how long after it starts `horus-ros node list` answers with a
//! peer's node complete (its name on every endpoint, no "discovery incomplete" warning), for a
//! real ROS 2 Jazzy node on Fast DDS (rclpy 7.1.6 on rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5,
//! interop-tests' rclpy peer) and one on rmw_cyclonedds_cpp 2.2.2 / Cyclone DDS 0.10, that were
//! up before, on each of our backends.
//!
//! Each series starts the peer, waits until it has created everything, lets it run for
//! `HORUS_ROS_BENCH_PEER_AGE_MS` (default 1500 ms: past Fast DDS' initial announcements, so the
//! CLI is a late joiner as a user's is), then times `HORUS_ROS_BENCH_RUNS` (default 10) cold
//! runs of the release binary with `--spin-time 10`, end to end (spawn to exit; the CLI exits as
//! soon as its graph is consistent and quiet). Printed: p50, max, and how many answers were
//! complete; then the same through `horus-ros daemon` (the first complete answer after
//! `daemon start`, then warm answers), and what a fresh rclpy process on rmw_cyclonedds_cpp
//! takes to list the node and its service (`cli/tests/peers/jazzy_graph_probe.py`, Python
//! start-up included).
//! Against the same-run baseline of a run next to a peer-less domain (the CLI's own
//! start-up and quiet wait), so the figures read as "discovery cost".
//!
//! Joins DDS domains, so it must run inside the private network namespace:
//!
//! ```text
//! cargo bench -p horus-ros-cli --bench graph_complete --no-run
//! scripts/isolated cargo bench -p horus-ros-cli --bench graph_complete
//! ```

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use interop_tests::peers::RclpyPeer;

mod common;

use common::{env_number, interfaces_up, CYCLONE_LOOPBACK};

const DOMAIN: u32 = 150;
const WARNING: &str = "WARNING: discovery incomplete";

/// The release `horus-ros` next to this bench binary (`target/release/deps/…`).
fn cli_binary() -> PathBuf {
    let exe = std::env::current_exe().unwrap_or_default();
    let release = exe
        .parent()
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .unwrap_or_default();
    release.join("horus-ros")
}

/// One cold `node list`: its wall time and whether `node` was listed with no warning.
fn cold_run(backend: &str, domain: u32, node: &str) -> (Duration, bool) {
    node_list_run(backend, domain, node, &["--no-daemon"])
}

/// One `node list` through a running daemon.
fn daemon_run(backend: &str, domain: u32, node: &str) -> (Duration, bool) {
    node_list_run(backend, domain, node, &[])
}

/// `horus-ros daemon <verb>` for `backend` and `domain`; whether it succeeded.
fn daemon(verb: &str, backend: &str, domain: u32) -> bool {
    Command::new(cli_binary())
        .args(["--domain-id", &domain.to_string(), "daemon", verb])
        .env("HORUS_ROS_BACKEND", backend)
        .env("CYCLONEDDS_URI", CYCLONE_LOOPBACK)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Starts a daemon and times the first complete answer through it (from the daemon's start:
/// what a user sees who starts it next to a running robot), then `runs` warm answers.
fn daemon_series(label: &str, backend: &str, domain: u32, node: &str, runs: u64) {
    let started = Instant::now();
    if !daemon("start", backend, domain) {
        eprintln!("bench: could not start the daemon");
        return;
    }
    let first = loop {
        let (_, ok) = daemon_run(backend, domain, node);
        if ok || started.elapsed() > Duration::from_secs(20) {
            break ok.then(|| started.elapsed());
        }
    };
    match first {
        Some(t) => println!(
            "{label:<34} {backend:<8} first complete answer {:>7.1} ms after `daemon start`",
            t.as_secs_f64() * 1e3
        ),
        None => println!("{label:<34} {backend:<8} no complete answer within 20 s"),
    }
    timed_series(label, backend, runs, || daemon_run(backend, domain, node));
    daemon("stop", backend, domain);
}

/// One `node list` with `extra` global options.
fn node_list_run(backend: &str, domain: u32, node: &str, extra: &[&str]) -> (Duration, bool) {
    let started = Instant::now();
    let out = Command::new(cli_binary())
        .args(extra)
        .args([
            "--domain-id",
            &domain.to_string(),
            "--spin-time",
            "10",
            "node",
            "list",
        ])
        .env("HORUS_ROS_BACKEND", backend)
        .env("CYCLONEDDS_URI", CYCLONE_LOOPBACK)
        .env("RUST_LOG", "error")
        .stdin(Stdio::null())
        .output();
    let elapsed = started.elapsed();
    match out {
        Ok(out) => {
            let stdout = String::from_utf8_lossy(&out.stdout);
            let stderr = String::from_utf8_lossy(&out.stderr);
            let complete = out.status.success()
                && stdout.lines().any(|l| l == node)
                && !stderr.contains(WARNING);
            (elapsed, complete || node.is_empty() && out.status.success())
        }
        Err(e) => {
            eprintln!("bench: cannot run {}: {e}", cli_binary().display());
            (elapsed, false)
        }
    }
}

use horus_ros_test_support::jazzy::{python, Rmw};

/// A script of `cli/tests/peers/`.
fn cli_peer_script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/peers")
        .join(name)
}

/// A real rclpy node `/NAMESPACE/NAME` on `rmw` with a std_srvs/SetBool server and client of
/// `/NAMESPACE/set`, started and ready.
fn rclpy_peer(rmw: Rmw, domain: u32, namespace: &str, name: &str) -> Option<RclpyPeer> {
    let spec = serde_json::json!({
        "domain": domain, "namespace": namespace, "name": name,
        "servers": [{"service": format!("{namespace}/set"), "type": "std_srvs/srv/SetBool"}],
        "clients": [{"service": format!("{namespace}/set"), "type": "std_srvs/srv/SetBool"}],
    });
    let started = RclpyPeer::start_on(rmw, &spec).and_then(|mut peer| {
        peer.ready(Duration::from_secs(30))?;
        Ok(peer)
    });
    started
        .map_err(|e| eprintln!("bench: rclpy peer on {}: {e}", rmw.name()))
        .ok()
}

/// One run of a fresh rclpy process on rmw_cyclonedds_cpp (`jazzy_graph_probe.py`) until its
/// graph lists `node` and `service`: what an rmw_cyclonedds_cpp tool would see. Its wall time
/// includes Python's start-up.
fn rclpy_probe_run(domain: u32, node: &str, service: &str) -> (Duration, bool) {
    let started = Instant::now();
    let status = Command::new(python())
        .arg(cli_peer_script("jazzy_graph_probe.py"))
        .args([&domain.to_string(), node, service, "10"])
        .env("RMW_IMPLEMENTATION", Rmw::CycloneDds.name())
        .env("CYCLONEDDS_URI", CYCLONE_LOOPBACK)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    (started.elapsed(), status.is_ok_and(|s| s.success()))
}

/// Python's own start-up with rclpy imported, for reading the probe's figures.
fn python_startup_run() -> (Duration, bool) {
    let started = Instant::now();
    let status = Command::new(python())
        .args(["-c", "import rclpy"])
        .env("RMW_IMPLEMENTATION", Rmw::CycloneDds.name())
        .status();
    (started.elapsed(), status.is_ok_and(|s| s.success()))
}

/// Prints one series of cold runs.
fn series(label: &str, backend: &str, domain: u32, node: &str, runs: u64) -> Option<Duration> {
    timed_series(label, backend, runs, || cold_run(backend, domain, node))
}

/// Runs `run` `runs` times and prints p50, max and how many were complete.
fn timed_series(
    label: &str,
    backend: &str,
    runs: u64,
    mut run: impl FnMut() -> (Duration, bool),
) -> Option<Duration> {
    let mut times = Vec::new();
    let mut complete = 0;
    for _ in 0..runs {
        let (t, ok) = run();
        times.push(t);
        complete += u64::from(ok);
    }
    times.sort();
    let p50 = *times.get(times.len() / 2)?;
    let max = *times.last()?;
    println!(
        "{label:<34} {backend:<8} p50 {:>7.1} ms  max {:>7.1} ms  complete {complete}/{runs}",
        p50.as_secs_f64() * 1e3,
        max.as_secs_f64() * 1e3
    );
    Some(p50)
}

fn main() -> ExitCode {
    if std::env::args().any(|a| a == "--list") {
        return ExitCode::SUCCESS;
    }
    let up = interfaces_up();
    if !up.is_empty() {
        eprintln!("bench: network interfaces {up:?} are up; run inside scripts/isolated");
        return ExitCode::from(2);
    }
    if !cli_binary().exists() {
        eprintln!(
            "bench: {} is missing: cargo build --release -p horus-ros-cli",
            cli_binary().display()
        );
        return ExitCode::from(2);
    }
    let runs = env_number("HORUS_ROS_BENCH_RUNS", 10);
    let age = Duration::from_millis(env_number("HORUS_ROS_BENCH_PEER_AGE_MS", 1500));
    println!("time to a complete graph: cold `horus-ros --no-daemon --spin-time 10 node list`, {runs} runs each, peers {age:?} old");
    timed_series(
        "python + rclpy import (start-up)",
        "python",
        runs,
        python_startup_run,
    );
    for (i, backend) in ["rustdds", "cyclone"].into_iter().enumerate() {
        let domain = DOMAIN + 3 * i as u32;
        let baseline = series("no peer (baseline)", backend, domain, "", runs);

        for (rmw, label, namespace, name, peer_domain) in [
            (
                Rmw::FastRtps,
                "rclpy node (Fast DDS 2.14)",
                "/fast_ns",
                "fast_node",
                domain + 1,
            ),
            (
                Rmw::CycloneDds,
                "rclpy node (Cyclone DDS 0.10)",
                "/cyc_ns",
                "cyc_node",
                domain + 2,
            ),
        ] {
            let Some(peer) = rclpy_peer(rmw, peer_domain, namespace, name) else {
                continue;
            };
            let node = format!("{namespace}/{name}");
            wait_out(age);
            let p50 = series(label, backend, peer_domain, &node, runs);
            ratio(p50, baseline);
            daemon_series("  through the daemon", backend, peer_domain, &node, runs);
            if i == 0 {
                let service = format!("{namespace}/set");
                timed_series("  rclpy on rmw_cyclonedds_cpp", "python", runs, || {
                    rclpy_probe_run(peer_domain, &node, &service)
                });
            }
            drop(peer);
        }
    }
    ExitCode::SUCCESS
}

/// Lets a peer age (a benchmark's set-up, not synchronisation: the peer is already up).
fn wait_out(age: Duration) {
    std::thread::sleep(age);
}

fn ratio(p50: Option<Duration>, baseline: Option<Duration>) {
    if let (Some(p), Some(b)) = (p50, baseline) {
        println!(
            "{:<34} discovery cost over the baseline: {:+.1} ms",
            "",
            (p.as_secs_f64() - b.as_secs_f64()) * 1e3
        );
    }
}
