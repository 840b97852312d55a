//! Time to a complete graph: how long after it starts `horus-ros node list` answers with a
//! peer's node complete (its name on every endpoint, no "discovery incomplete" warning), for a
//! real ROS 2 Jazzy node on Fast DDS (rclpy 7.1.6 on rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5,
//! interop-tests' rclpy peer) and a Cyclone DDS ROS participant (the DDS of rmw_cyclonedds_cpp)
//! that were up before, on each of our backends.
//!
//! Each series starts the peer, waits until it has created everything, lets it run for
//! `HORUS_ROS_BENCH_PEER_AGE_MS` (default 1500 ms: past Fast DDS' initial announcements, so the
//! CLI is a late joiner as a user's is), then times `HORUS_ROS_BENCH_RUNS` (default 10) cold
//! runs of the release binary with `--spin-time 10`, end to end (spawn to exit; the CLI exits as
//! soon as its graph is consistent and quiet). Printed: p50, max, and how many answers were
//! complete; then the same through `horus-ros daemon` (the first complete answer after
//! `daemon start`, then warm answers), and Cyclone DDS's own view (interop-tests'
//! `cyclone_discovery_info.py`: Cyclone DDS discovery plus `ros_discovery_info` read as
//! rmw_dds_common does, Python start-up included; ros2cli is not installable here).
//! Against the same-run baseline of a run next to a peer-less domain (the CLI's own
//! start-up and quiet wait), so the figures read as "discovery cost".
//!
//! Joins DDS domains, so it must run inside the private network namespace:
//!
//! ```text
//! cargo bench -p horus-ros-cli --bench graph_complete --no-run
//! scripts/isolated cargo bench -p horus-ros-cli --bench graph_complete
//! ```

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
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

/// The type hash the Cyclone peer announces for its topics (builtin_interfaces/msg/Time's: any
/// valid RIHS01 will do for discovery).
fn time_hash() -> String {
    use horus_ros_msgs::Message;
    horus_ros_msgs::builtin_interfaces::msg::Time::type_hash().to_string()
}

use horus_ros_test_support::jazzy::python;

/// `interop-tests/peers/<name>`.
fn peer_script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../interop-tests/peers")
        .join(name)
}

/// The Cyclone DDS Python ROS participant of interop-tests, started and ready.
fn cyclone_peer(domain: u32) -> Option<Child> {
    let python = python();
    let mut child = Command::new(&python)
        .arg(peer_script("cyclone_ros_participant.py"))
        .args([
            &domain.to_string(),
            "/cyc_ns",
            "cyc_node",
            &time_hash(),
            "600",
        ])
        .env("CYCLONEDDS_URI", CYCLONE_LOOPBACK)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(|e| eprintln!("bench: cannot start the Cyclone DDS peer with {python:?}: {e}"))
        .ok()?;
    let stdout = child.stdout.take()?;
    let mut line = String::new();
    // The peer prints its line once everything is created (bounded by its own start-up).
    if BufReader::new(stdout).read_line(&mut line).ok()? == 0 {
        let _ = child.kill();
        let _ = child.wait();
        return None;
    }
    Some(child)
}

/// One run of interop-tests' Cyclone DDS graph watcher (`cyclone_discovery_info.py`): Cyclone
/// DDS's own discovery plus `ros_discovery_info` read as rmw_dds_common reads it, i.e. what an
/// rmw_cyclonedds_cpp tool would see. It exits 0 once `node` is announced with `readers`
/// readers and `writers` writers all discovered. Its wall time includes Python's start-up.
fn cyclone_watcher_run(domain: u32, node: &str, readers: u32, writers: u32) -> (Duration, bool) {
    let (namespace, name) = node.rsplit_once('/').unwrap_or(("/", node));
    let namespace = if namespace.is_empty() { "/" } else { namespace };
    let started = Instant::now();
    let status = Command::new(python())
        .arg(peer_script("cyclone_discovery_info.py"))
        .args([
            &domain.to_string(),
            namespace,
            name,
            &readers.to_string(),
            &writers.to_string(),
            "10",
        ])
        .env("CYCLONEDDS_URI", CYCLONE_LOOPBACK)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    (started.elapsed(), status.is_ok_and(|s| s.success()))
}

/// Python's own start-up, for reading the watcher's figures.
fn python_startup_run() -> (Duration, bool) {
    let started = Instant::now();
    let status = Command::new(python())
        .args(["-c", "import cyclonedds.domain"])
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
        "python + cyclonedds import (start-up)",
        "python",
        runs,
        python_startup_run,
    );
    for (i, backend) in ["rustdds", "cyclone"].into_iter().enumerate() {
        let domain = DOMAIN + 3 * i as u32;
        let baseline = series("no peer (baseline)", backend, domain, "", runs);

        match RclpyPeer::start(&serde_json::json!({
            "domain": domain + 1, "namespace": "/fast_ns", "name": "fast_node",
            "servers": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
            "clients": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
        })) {
            Ok(mut peer) => {
                if let Err(e) = peer.ready(Duration::from_secs(30)) {
                    eprintln!("bench: rclpy peer: {e}");
                } else {
                    wait_out(age);
                    let p50 = series(
                        "rclpy node (Fast DDS 2.14)",
                        backend,
                        domain + 1,
                        "/fast_ns/fast_node",
                        runs,
                    );
                    ratio(p50, baseline);
                    daemon_series(
                        "  through the daemon",
                        backend,
                        domain + 1,
                        "/fast_ns/fast_node",
                        runs,
                    );
                    if i == 0 {
                        timed_series("  Cyclone DDS's own view of it", "python", runs, || {
                            cyclone_watcher_run(domain + 1, "/fast_ns/fast_node", 2, 2)
                        });
                    }
                }
            }
            Err(e) => eprintln!("bench: rclpy peer: {e}"),
        }
        if let Some(mut peer) = cyclone_peer(domain + 2) {
            wait_out(age);
            let p50 = series(
                "Cyclone DDS node",
                backend,
                domain + 2,
                "/cyc_ns/cyc_node",
                runs,
            );
            ratio(p50, baseline);
            daemon_series(
                "  through the daemon",
                backend,
                domain + 2,
                "/cyc_ns/cyc_node",
                runs,
            );
            if i == 0 {
                timed_series("  Cyclone DDS's own view of it", "python", runs, || {
                    cyclone_watcher_run(domain + 2, "/cyc_ns/cyc_node", 1, 1)
                });
            }
            let _ = peer.kill();
            let _ = peer.wait();
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
