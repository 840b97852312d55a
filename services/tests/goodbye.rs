//! A clean goodbye: a horus-ros program stopped by SIGINT or SIGTERM leaves a long-lived rclpy
//! process's graph at once (within a fraction of a second; without the goodbye it would stay
//! there until its DDS lease ends, 10 s and more), whether it handles shutdown itself
//! (`add_two_ints_server` waits for its context's shutdown) or never looks at it
//! (`plain_server`, which then ends as signalled). With the signal handlers turned off, SIGINT
//! ends a program the default way: on DDS rclpy keeps the node (a ghost until the lease ends);
//! on Zenoh it does not, as liveliness tokens live as long as the session's links, which the
//! kernel closes with the process (the router and rclpy's session drop a closed session's
//! tokens at once).
//!
//! On Zenoh the goodbye is the session's close, which undeclares the node's and its entities'
//! liveliness tokens: rclpy (rmw_zenoh_cpp 0.2.10's graph cache, fed by those tokens) sees the
//! node and its service go.
//!
//! The peer is real rclpy (`tests/peers/jazzy_graph_watcher.py`) on the run's RMW
//! (`HORUS_ROS_PEER_RMW`: rmw_fastrtps_cpp by default, rmw_cyclonedds_cpp, or rmw_zenoh_cpp
//! beside the run's router), run in the real peers' environment
//! (`horus_ros_test_support::jazzy::python`). Run on any backend (`HORUS_ROS_BACKEND`), inside
//! the test network namespace.

use std::io::Write;
use std::os::unix::process::ExitStatusExt;
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use horus_ros_test_support::jazzy::Rmw;
use horus_ros_test_support::{line_reader, read_all, wait_exit};
use nix::sys::signal::{kill, Signal};
use nix::unistd::Pid;

mod common;

/// The longest a node may take to show up in rclpy's graph (discovery on a loaded machine).
const APPEAR: Duration = Duration::from_secs(30);
/// The longest rclpy may take to see a stopped program's node go: a "did not hang" bound far
/// below any DDS lease (the measured time is printed).
const GONE: Duration = Duration::from_secs(5);
/// The longest a stopped program may take to exit.
const EXIT: Duration = Duration::from_secs(10);

fn backend() -> String {
    std::env::var("HORUS_ROS_BACKEND").unwrap_or_else(|_| "rustdds".to_owned())
}

/// Waits for a line `wanted` (each line wakes it), at most `limit`; how long it took.
fn expect_line(
    lines: &Receiver<String>,
    seen: &mut Vec<String>,
    what: &str,
    limit: Duration,
    wanted: impl Fn(&str) -> bool,
) -> Result<(String, Duration), String> {
    let start = Instant::now();
    let end = start + limit;
    loop {
        match lines.recv_timeout(end.saturating_duration_since(Instant::now())) {
            Ok(line) => {
                seen.push(line.clone());
                if wanted(&line) {
                    return Ok((line, start.elapsed()));
                }
            }
            Err(_) => return Err(format!("no {what} within {limit:?}; saw {seen:#?}")),
        }
    }
}

/// The long-lived rclpy process: reports the nodes that appear and disappear.
struct Watcher {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: Receiver<String>,
    stderr: Option<Receiver<String>>,
    seen: Vec<String>,
}

impl Watcher {
    fn start(domain: u32) -> Self {
        let python = horus_ros_test_support::jazzy::python();
        let script = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/peers/jazzy_graph_watcher.py"
        );
        let mut child = Command::new(&python)
            .arg(script)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("start {python:?} {script}: {e}"));
        let mut watcher = Self {
            stdin: child.stdin.take(),
            lines: line_reader(child.stdout.take().expect("stdout")),
            stderr: Some(read_all(child.stderr.take().expect("stderr"))),
            child,
            seen: Vec::new(),
        };
        watcher.expect("its start", APPEAR, |l| l == "ready");
        watcher
    }

    fn expect(&mut self, what: &str, limit: Duration, wanted: impl Fn(&str) -> bool) -> Duration {
        match expect_line(&self.lines, &mut self.seen, what, limit, wanted) {
            Ok((_, took)) => took,
            Err(e) => panic!("rclpy watcher: {e}; stderr: {}", self.stderr_text()),
        }
    }

    /// Waits for every line of `wanted`, in any order, at most `limit` in all; how long each
    /// took.
    fn expect_all(&mut self, wanted: &[String], limit: Duration) -> Vec<Duration> {
        let start = Instant::now();
        let mut took = vec![None; wanted.len()];
        while let Some(i) = took.iter().position(Option::is_none) {
            let left = limit.saturating_sub(start.elapsed());
            let what = &wanted[i];
            self.expect(what, left, |l| wanted.iter().any(|w| w == l));
            let line = self.seen.last().cloned().unwrap_or_default();
            if let Some(j) = wanted.iter().position(|w| *w == line) {
                took[j].get_or_insert(start.elapsed());
            }
        }
        took.into_iter().flatten().collect()
    }

    /// The nodes rclpy sees now.
    fn list(&mut self) -> Vec<String> {
        let stdin = self.stdin.as_mut().expect("stdin");
        writeln!(stdin, "list")
            .and_then(|()| stdin.flush())
            .expect("ask the watcher");
        let (line, _) = expect_line(&self.lines, &mut self.seen, "list", APPEAR, |l| {
            l.starts_with("list")
        })
        .unwrap_or_else(|e| panic!("rclpy watcher: {e}"));
        line.split_whitespace().skip(1).map(str::to_owned).collect()
    }

    fn stderr_text(&mut self) -> String {
        let _ = self.child.kill();
        self.stderr
            .take()
            .and_then(|rx| rx.recv_timeout(EXIT).ok())
            .unwrap_or_default()
    }
}

impl Drop for Watcher {
    /// Closing its standard input ends it; killed if it does not end.
    fn drop(&mut self) {
        drop(self.stdin.take());
        let _ = wait_exit(&mut self.child, EXIT);
    }
}

/// A horus-ros example in a process of its own.
struct Program {
    name: &'static str,
    child: Child,
    lines: Receiver<String>,
    seen: Vec<String>,
}

impl Program {
    fn start(name: &'static str, args: &[&str], domain: u32) -> Self {
        let mut child = Command::new(common::example_path(name))
            .args(args)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap_or_else(|e| panic!("spawn {name}: {e}"));
        let lines = line_reader(child.stdout.take().expect("stdout"));
        Self {
            name,
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// The node `plain_server` prints it serves on.
    fn served_node(&mut self) -> String {
        let (line, _) = expect_line(&self.lines, &mut self.seen, "serving", APPEAR, |l| {
            l.starts_with("serving ")
        })
        .unwrap_or_else(|e| panic!("{}: {e}", self.name));
        line.rsplit(' ').next().expect("node name").to_owned()
    }

    fn signal(&self, signal: Signal) {
        let pid = Pid::from_raw(i32::try_from(self.child.id()).expect("pid"));
        kill(pid, signal).unwrap_or_else(|e| panic!("{signal} to {}: {e}", self.name));
    }

    fn exit_status(mut self) -> ExitStatus {
        wait_exit(&mut self.child, EXIT)
            .expect("wait")
            .unwrap_or_else(|| panic!("{} still running {EXIT:?} after the signal", self.name))
    }
}

impl Drop for Program {
    /// A test that failed leaves no program behind.
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Stops `program` by `signal` once rclpy sees its `node` and its `service`, and waits until
/// rclpy sees them go. The service not on the rustdds backend with rmw_fastrtps peers: rustdds
/// 0.15 sends its disposes without a key hash, which Fast DDS ignores, so its endpoints stay
/// until its lease ends (the node goes at once all the same: it is withdrawn on
/// `ros_discovery_info`); Cyclone DDS (rmw_cyclonedds peers) takes those disposes, and on Zenoh
/// the server's token goes with the session.
fn stop_and_time(
    watcher: &mut Watcher,
    program: &Program,
    node: &str,
    service: &str,
    signal: Signal,
) {
    let mut appear = vec![format!("+ {node}")];
    let mut gone = vec![format!("- {node}")];
    if backend() == "cyclone" || matches!(Rmw::of_peers(), Rmw::CycloneDds | Rmw::Zenoh) {
        appear.push(format!("+service {service}"));
        gone.push(format!("-service {service}"));
    }
    watcher.expect_all(&appear, APPEAR);
    program.signal(signal);
    let took = watcher.expect_all(&gone, GONE);
    let ms = |d: &Duration| format!("{:.0} ms", d.as_secs_f64() * 1e3);
    println!(
        "{}: after {signal} to {}, rclpy saw {node} leave in {}{}",
        backend(),
        program.name,
        ms(&took[0]),
        took.get(1)
            .map(|d| format!(", {service} in {}", ms(d)))
            .unwrap_or_default()
    );
}

#[test]
fn add_two_ints_server_leaves_rclpys_graph_at_once_on_sigint_and_on_sigterm() {
    let domain = 221;
    let mut watcher = Watcher::start(domain);
    for signal in [Signal::SIGINT, Signal::SIGTERM] {
        let server = Program::start("add_two_ints_server", &[], domain);
        stop_and_time(
            &mut watcher,
            &server,
            "/add_two_ints_server",
            "/add_two_ints",
            signal,
        );
        let status = server.exit_status();
        // It exits 0 once it waits for its context's shutdown; a signal that comes while it is
        // still starting (before that wait) ends it as signalled, after the goodbye all the same.
        assert!(
            status.success() || status.signal() == Some(signal as i32),
            "add_two_ints_server after {signal}: {status}"
        );
    }
}

#[test]
fn a_program_that_never_looks_at_shutdown_says_goodbye_then_ends_as_signalled() {
    let domain = 222;
    let mut watcher = Watcher::start(domain);
    for signal in [Signal::SIGINT, Signal::SIGTERM] {
        let mut program = Program::start("plain_server", &[], domain);
        let node = program.served_node();
        stop_and_time(&mut watcher, &program, &node, "/plain_add", signal);
        let status = program.exit_status();
        assert_eq!(
            status.signal(),
            Some(signal as i32),
            "plain_server after {signal}: {status}"
        );
    }
}

#[test]
fn without_signal_handlers_sigint_ends_a_program_the_default_way() {
    let domain = 223;
    let mut watcher = Watcher::start(domain);
    let mut program = Program::start("plain_server", &["--no-signal-handlers"], domain);
    let node = program.served_node();
    let appeared = format!("+ {node}");
    watcher.expect(&appeared, APPEAR, |l| l == appeared);
    program.signal(Signal::SIGINT);
    let status = program.exit_status();
    assert_eq!(status.signal(), Some(Signal::SIGINT as i32), "{status}");
    if Rmw::of_peers() == Rmw::Zenoh {
        // No goodbye, but the kernel closed the process's links: its session's tokens go with
        // them (no lease to wait for), so rclpy drops the node all the same.
        let gone = format!("- {node}");
        let took = watcher.expect(&gone, GONE, |l| l == gone);
        println!(
            "zenoh: without the goodbye, rclpy saw {node} leave {:.0} ms after the exit",
            took.as_secs_f64() * 1e3
        );
        return;
    }
    // No goodbye: the participant is gone, unannounced, so rclpy keeps the node until its DDS
    // lease ends (10 s and more), long after the process.
    let nodes = watcher.list();
    assert!(
        nodes.contains(&node),
        "rclpy no longer lists {node} right after its process was killed: {nodes:?}"
    );
}
