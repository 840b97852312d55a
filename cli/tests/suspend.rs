//! A process on the Cyclone backend survives being suspended and resumed (Ctrl-Z, `fg`:
//! SIGSTOP/SIGCONT): it is still on the graph afterwards, and a process that starts later still
//! discovers it. (The rustdds backend's threads end on such an interrupted wait: README,
//! "What the rustdds backend cannot do".)
//!
//! Domain 137. Run inside the private network namespace (`scripts/isolated`).

mod common;

use std::process::{Command, Stdio};
use std::time::Duration;

use common::{horus, RUN_LIMIT};
use horus_ros_test_support::wait_exit;

const D: u32 = 137;

/// Whether a new `node list -a` process on Cyclone shows `node`, in one of a few tries (each
/// waits for discovery itself: `--spin-time`).
fn listed(node: &str) -> bool {
    (0..5).any(|_| {
        let run = horus(
            D,
            &[
                "--backend",
                "cyclone",
                "--spin-time",
                "2",
                "node",
                "list",
                "-a",
            ],
        );
        run.stdout.lines().any(|l| l == node)
    })
}

fn signal(pid: u32, sig: &str) {
    let status = Command::new("kill")
        .args([sig, &pid.to_string()])
        .status()
        .expect("run kill");
    assert!(status.success(), "kill {sig} {pid}");
}

#[test]
fn a_suspended_and_resumed_process_stays_on_the_graph() {
    let mut watch = Command::new(env!("CARGO_BIN_EXE_horus-ros"))
        .args(["--backend", "cyclone", "--domain-id", &D.to_string()])
        .args(["graph", "--watch"])
        .env("RUST_LOG", "error")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start horus-ros graph --watch");
    let node = format!("/_horus_ros_{}", watch.id());
    let seen_before = listed(&node);

    signal(watch.id(), "-STOP");
    // The stimulus: suspended for a while, as by Ctrl-Z.
    std::thread::sleep(Duration::from_secs(2));
    signal(watch.id(), "-CONT");
    // Each `node list` is a new process: it must discover the resumed one from scratch.
    let seen_after = listed(&node);

    signal(watch.id(), "-TERM");
    let status = wait_exit(&mut watch, RUN_LIMIT).expect("wait for graph --watch");
    assert!(seen_before, "{node} never appeared");
    assert!(seen_after, "{node} left the graph after SIGSTOP/SIGCONT");
    let status = status.expect("graph --watch still running long after SIGTERM: killed");
    assert!(status.success(), "graph --watch ended with {status}");
}
