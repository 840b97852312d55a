//! Startup-to-answer time of `horus-ros service list` on a warm graph, against ros2cli's
//! documented default (`--spin-time 0.5` s of discovery wait, plus starting Python), and of
//! `horus-ros node list` with its own discovery (`--no-daemon`, "cold") against the same through
//! the daemon (`horus-ros daemon start`), on each backend built in: rustdds (domain 139) and
//! Cyclone DDS (domain 140). Each backend gets its own warm graph on that backend, and the CLI is
//! chosen with `HORUS_ROS_BACKEND` in its environment. Then `node list` cold and through the
//! daemon once more on a graph whose only node is a Fast DDS one (interop-tests' rclpy peer:
//! rclpy 7.1.6 on rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5, domains 141 and 142): Fast DDS
//! answers a new participant's discovery slowly,
//! so a cold answer is often incomplete. Cyclone DDS runs with the environment's
//! `CYCLONEDDS_URI`, else a loopback-only configuration.
//!
//! Joins DDS domains, so it must run inside the private network namespace:
//!
//! ```text
//! cargo bench -p horus-ros-cli --bench startup --no-run
//! scripts/isolated cargo bench -p horus-ros-cli --bench startup
//! ```
//!
//! It refuses to run where a network interface other than loopback is up. The warm graph is
//! a child process (this bench re-run): one context with four nodes (three AddTwoInts servers
//! and a publisher). Each
//! run is timed end to end, from spawning the release binary to its exit, and its stdout is
//! checked against the services (nodes) the graph has; a complete answer is a correct one with
//! nothing on stderr (no "discovery incomplete" warning). `HORUS_ROS_BENCH_RUNS` sets the number
//! of runs (default 30); `HORUS_ROS_BENCH_DEBUG=1` prints the first wrong answer of each series.
//! Every daemon the bench starts is stopped, and killed by its pid if it does not stop.
//!
//! The warm graph is another process, as it is for a user running the CLI next to a robot. (Held
//! in this process, which spawns many fast-exiting children, it used to lose its participants:
//! rustdds' threads ended on the SIGCHLD-interrupted wait. The context now starts them with
//! signals blocked; see rmw/tests/signals.rs.)

use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Backend, BACKEND_ENV};
use horus_ros_services::prelude::*;
use interop_tests::peers::RclpyPeer;

mod common;

use common::{interfaces_up, ms, CYCLONE_LOOPBACK};

/// The domain of the first backend; the next ones use the following domains.
const DOMAIN: u32 = 139;
const SERVICES: [&str; 3] = ["/bench/add_a", "/bench/add_b", "/bench/add_c"];
/// ros2cli's documented default `--spin-time` (ros2cli `node/strategy.py`, `DirectNode`).
const ROS2CLI_SPIN_TIME: Duration = Duration::from_millis(500);
/// The issue's goal for `service list`'s startup-to-answer time on a warm graph.
const GOAL: Duration = Duration::from_millis(300);
/// The goal for a complete `node list` when the daemon runs.
const DAEMON_GOAL: Duration = Duration::from_millis(20);
/// The first domain of the Fast DDS series (one per backend).
const FAST_DDS_DOMAIN: u32 = 141;
/// The node of the Fast DDS (rclpy) peer.
const FAST_DDS_NODE: &str = "/fast_ns/fast_node";

/// Times in a sorted list.
struct Stats(Vec<Duration>);

impl Stats {
    fn new(mut times: Vec<Duration>) -> Self {
        times.sort();
        Self(times)
    }

    /// The nearest-rank percentile `p` (0-100).
    fn percentile(&self, p: usize) -> Duration {
        if self.0.is_empty() {
            return Duration::ZERO;
        }
        let rank = (p * self.0.len()).div_ceil(100).max(1);
        self.0[rank - 1]
    }

    fn median(&self) -> Duration {
        self.percentile(50)
    }

    fn line(&self) -> String {
        format!(
            "median {:>6.1} ms  p90 {:>6.1} ms  min {:>6.1} ms  max {:>6.1} ms",
            ms(self.median()),
            ms(self.percentile(90)),
            ms(self.0.first().copied().unwrap_or_default()),
            ms(self.0.last().copied().unwrap_or_default()),
        )
    }
}

/// A timed series of runs.
struct Series {
    /// Their times.
    stats: Stats,
    /// How many printed the expected stdout (any counts when none is expected) and exited 0.
    correct: usize,
    /// How many of those printed nothing on stderr (no "discovery incomplete" warning).
    complete: usize,
}

/// Runs `program args` `runs` times (with `HORUS_ROS_BACKEND=backend`), timing each run.
fn time_runs(
    program: &Path,
    args: &[&str],
    backend: Backend,
    runs: usize,
    expected: Option<&str>,
) -> Series {
    let mut times = Vec::with_capacity(runs);
    let (mut correct, mut complete) = (0, 0);
    for _ in 0..runs {
        let start = Instant::now();
        let out = Command::new(program)
            .args(args)
            .env(BACKEND_ENV, backend.name())
            .stdin(Stdio::null())
            .output();
        times.push(start.elapsed());
        if let Ok(out) = out {
            let stdout = String::from_utf8_lossy(&out.stdout);
            let ok = out.status.success() && expected.is_none_or(|e| stdout == e);
            if !ok && correct == 0 && std::env::var_os("HORUS_ROS_BENCH_DEBUG").is_some() {
                eprintln!("wrong answer ({}): {stdout:?}", out.status);
            }
            correct += usize::from(ok);
            complete += usize::from(ok && out.stderr.is_empty());
        }
    }
    Series {
        stats: Stats::new(times),
        correct,
        complete,
    }
}

/// Runs `args` until one run is correct and complete, at most `limit`.
fn until_complete(
    bin: &Path,
    args: &[&str],
    backend: Backend,
    expected: &str,
    limit: Duration,
) -> bool {
    let deadline = Instant::now() + limit;
    while time_runs(bin, args, backend, 1, Some(expected)).complete != 1 {
        if Instant::now() >= deadline {
            return false;
        }
    }
    true
}

/// A daemon started by the bench: stopped when dropped (`daemon stop`), else killed by its pid.
/// The bench reaps orphans (`PR_SET_CHILD_SUBREAPER`), so the daemon is its child and its pid
/// cannot be reused before it is reaped here.
struct Daemon {
    bin: std::path::PathBuf,
    backend: Backend,
    domain: String,
    pid: i32,
}

impl Daemon {
    fn start(bin: &Path, backend: Backend, domain: &str) -> Result<Self, String> {
        let out = Command::new(bin)
            .args(["--domain-id", domain, "--json", "daemon", "start"])
            .env(BACKEND_ENV, backend.name())
            .stdin(Stdio::null())
            .stderr(Stdio::inherit())
            .output()
            .map_err(|e| format!("could not run `daemon start`: {e}"))?;
        let doc: serde_json::Value = serde_json::from_slice(&out.stdout)
            .map_err(|e| format!("`daemon start` printed no JSON ({e})"))?;
        let pid = doc["pid"]
            .as_i64()
            .and_then(|p| i32::try_from(p).ok())
            .ok_or_else(|| format!("`daemon start` printed no pid: {doc}"))?;
        let daemon = Self {
            bin: bin.to_owned(),
            backend,
            domain: domain.to_owned(),
            pid,
        };
        if doc["started"] != serde_json::Value::Bool(true) {
            return Err(format!("a daemon was already running in domain {domain}"));
        }
        Ok(daemon)
    }
}

impl Drop for Daemon {
    fn drop(&mut self) {
        let stopped = Command::new(&self.bin)
            .args(["--domain-id", &self.domain, "daemon", "stop"])
            .env(BACKEND_ENV, self.backend.name())
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        let pid = nix::unistd::Pid::from_raw(self.pid);
        if !stopped {
            let _ = nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGKILL);
        }
        let _ = nix::sys::wait::waitpid(pid, None);
    }
}

/// `node list`, cold then through the daemon: (cold, daemon).
fn node_list_series(
    bin: &Path,
    backend: Backend,
    domain: &str,
    runs: usize,
    expected: &str,
    warm_up: Duration,
) -> Result<(Series, Series), String> {
    let list = ["--domain-id", domain, "node", "list"];
    let cold_args = ["--domain-id", domain, "--no-daemon", "node", "list"];
    let cold = time_runs(bin, &cold_args, backend, runs, Some(expected));
    let _daemon = Daemon::start(bin, backend, domain)?;
    if !until_complete(bin, &list, backend, expected, warm_up) {
        return Err(format!(
            "the daemon's `node list` was never complete within {warm_up:?}"
        ));
    }
    let through_daemon = time_runs(bin, &list, backend, runs, Some(expected));
    Ok((cold, through_daemon))
}

/// Set in the environment of the bench's own child process that holds the warm graph.
const WARM_GRAPH_ENV: &str = "HORUS_ROS_BENCH_WARM_GRAPH";

/// The warm graph's process: the bench binary itself, re-run with [`WARM_GRAPH_ENV`].
struct WarmGraph {
    child: Child,
}

impl WarmGraph {
    /// Starts it on `backend` in `domain` and waits until its nodes, servers and publisher exist.
    fn start(backend: Backend, domain: u32) -> std::io::Result<Self> {
        let mut child = Command::new(std::env::current_exe()?)
            .env(WARM_GRAPH_ENV, domain.to_string())
            .env(BACKEND_ENV, backend.name())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()?;
        let mut line = String::new();
        if let Some(stdout) = child.stdout.take() {
            BufReader::new(stdout).read_line(&mut line)?;
        }
        if line.trim() != "ready" {
            let _ = child.kill();
            let _ = child.wait();
            return Err(std::io::Error::other(
                "the warm graph process did not start",
            ));
        }
        Ok(Self { child })
    }

    /// Closes its stdin (it leaves cleanly) and waits for it.
    fn stop(&mut self) {
        drop(self.child.stdin.take());
        let _ = self.child.wait();
    }

    /// The child's side: one context (in the domain [`WARM_GRAPH_ENV`] gives, on the backend
    /// `HORUS_ROS_BACKEND` names) with four nodes (three AddTwoInts servers and a publisher),
    /// kept until stdin closes.
    fn serve() -> ExitCode {
        let domain = std::env::var(WARM_GRAPH_ENV)
            .ok()
            .and_then(|d| d.parse().ok())
            .unwrap_or(DOMAIN);
        let context = match Context::builder().domain_id(domain).build() {
            Ok(c) => c,
            Err(e) => {
                eprintln!("startup bench: no context: {e}");
                return ExitCode::FAILURE;
            }
        };
        let mut servers = Vec::new();
        let mut nodes = Vec::new();
        for (i, service) in SERVICES.iter().enumerate() {
            let node = context
                .create_node(&format!("bench_server_{i}"), "/bench")
                .expect("node");
            let server = ServiceServer::<AddTwoInts>::builder()
                .node(&node)
                .name(*service)
                .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
                .build()
                .expect("server");
            servers.push(server);
            nodes.push(node);
        }
        let talker = context.create_node("bench_talker", "/bench").expect("node");
        let _publisher = talker
            .create_publisher::<Time>("chatter", &Qos::default())
            .expect("publisher");
        println!("ready");
        let _ = std::io::stdout().flush();
        let _ = std::io::stdin().read_to_end(&mut Vec::new());
        drop(servers);
        ExitCode::SUCCESS
    }
}

impl Drop for WarmGraph {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// The figures of one backend.
struct BackendRun {
    /// `service list --spin-time 0`.
    no_wait: Series,
    /// `service list`.
    list: Series,
    /// `node list --no-daemon` and `node list` through the daemon.
    nodes: Result<(Series, Series), String>,
}

/// Starts a warm graph on `backend` in `domain`, waits until the CLI on that backend sees it,
/// then times the `service list` series.
fn run_backend(
    bin: &Path,
    backend: Backend,
    domain: u32,
    runs: usize,
) -> Result<BackendRun, String> {
    let mut warm = WarmGraph::start(backend, domain)
        .map_err(|e| format!("could not start the warm graph: {e}"))?;
    let expected: String = SERVICES.iter().map(|s| format!("{s}\n")).collect();
    let domain = domain.to_string();
    // Cold: discovery of its own, no daemon used or started.
    let list = [
        "--domain-id",
        domain.as_str(),
        "--no-daemon",
        "service",
        "list",
    ];

    // Warm: wait until a run sees the whole graph (at most 20 s).
    let deadline = Instant::now() + Duration::from_secs(20);
    while time_runs(bin, &list, backend, 1, Some(&expected)).correct != 1 {
        if Instant::now() >= deadline {
            return Err("`horus-ros service list` never showed the warm graph".to_owned());
        }
    }
    let no_wait_args = [
        "--domain-id",
        domain.as_str(),
        "--no-daemon",
        "--spin-time",
        "0",
        "service",
        "list",
    ];
    let no_wait = time_runs(bin, &no_wait_args, backend, runs, Some(&expected));
    let list = time_runs(bin, &list, backend, runs, Some(&expected));
    let nodes = node_list_series(
        bin,
        backend,
        &domain,
        runs,
        "/bench/bench_server_0\n/bench/bench_server_1\n/bench/bench_server_2\n/bench/bench_talker\n",
        Duration::from_secs(20),
    );
    warm.stop();
    Ok(BackendRun {
        no_wait,
        list,
        nodes,
    })
}

/// `node list` cold and through the daemon on a graph whose only node is a Fast DDS peer's.
fn run_fast_dds(
    bin: &Path,
    backend: Backend,
    domain: u32,
    runs: usize,
) -> Result<(Series, Series), String> {
    let mut peer = RclpyPeer::start(&serde_json::json!({
        "domain": domain, "namespace": "/fast_ns", "name": "fast_node",
        "servers": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
        "clients": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
    }))?;
    peer.ready(Duration::from_secs(20))?;
    let expected = format!("{FAST_DDS_NODE}\n");
    // Fast DDS may take a few of its heartbeat periods to answer the daemon's participant.
    node_list_series(
        bin,
        backend,
        &domain.to_string(),
        runs,
        &expected,
        Duration::from_secs(30),
    )
}

/// The lines of a cold / daemon `node list` pair, and the daemon goal's line.
fn print_node_lists(
    what: &str,
    backend: Backend,
    runs: usize,
    series: &(Series, Series),
) -> String {
    let (cold, daemon) = series;
    println!(
        "  {what}, cold (`--no-daemon`):  {}  complete answers {}/{runs}",
        cold.stats.line(),
        cold.complete
    );
    println!(
        "  {what}, through the daemon:    {}  complete answers {}/{runs}",
        daemon.stats.line(),
        daemon.complete
    );
    let median = daemon.stats.median();
    let met = median < DAEMON_GOAL && daemon.complete == runs;
    format!(
        "goal: complete `node list` through the daemon < 20 ms ({what}) — {} on {backend} \
         (median {:.1} ms, p90 {:.1} ms, {}/{runs} complete; cold median {:.1} ms, {}/{runs} complete)",
        if met { "MET" } else { "NOT MET" },
        ms(median),
        ms(daemon.stats.percentile(90)),
        daemon.complete,
        ms(cold.stats.median()),
        cold.complete,
    )
}

fn main() -> ExitCode {
    if std::env::var_os(WARM_GRAPH_ENV).is_some() {
        return WarmGraph::serve();
    }
    let up = interfaces_up();
    if !up.is_empty() {
        eprintln!(
            "startup bench: refusing to join DDS with network interfaces up ({}). Run it inside \
             the private namespace:\n  cargo bench -p horus-ros-cli --bench startup --no-run\n  \
             scripts/isolated cargo bench -p horus-ros-cli --bench startup",
            up.join(", ")
        );
        return ExitCode::from(2);
    }
    // Inherited by the warm graphs and the CLI runs (read when a Cyclone context is created).
    let cyclone_uri_set = std::env::var_os("CYCLONEDDS_URI").is_some();
    if !cyclone_uri_set {
        std::env::set_var("CYCLONEDDS_URI", CYCLONE_LOOPBACK);
    }
    let runs: usize = std::env::var("HORUS_ROS_BENCH_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(30)
        .max(1);
    let bin = Path::new(env!("CARGO_BIN_EXE_horus-ros"));
    // Daemons left by `daemon start` become this process's children: reaped and killed by pid.
    if let Err(e) = nix::sys::prctl::set_child_subreaper(true) {
        eprintln!("startup bench: cannot reap the daemons it starts ({e}); refusing to start any");
        return ExitCode::FAILURE;
    }

    println!(
        "startup bench: `horus-ros service list` on a warm graph (4 nodes, 3 services, 1 topic, \
         on the same backend as the CLI), {runs} runs each, release build, end to end \
         (spawn → exit); Cyclone DDS configuration: {}",
        if cyclone_uri_set {
            "CYCLONEDDS_URI from the environment"
        } else {
            "loopback only (CYCLONEDDS_URI was unset)"
        }
    );
    let start_only = time_runs(bin, &["--version"], Backend::RustDds, runs, None);
    println!(
        "  process start only   (`horus-ros --version`):            {}",
        start_only.stats.line()
    );
    let python = time_runs(
        Path::new("python3"),
        &["-c", "import sys"],
        Backend::RustDds,
        runs,
        None,
    );
    let python_median = if python.correct == runs {
        println!(
            "  bare Python start    (`python3 -c 'import sys'`):        {}",
            python.stats.line()
        );
        Some(python.stats.median())
    } else {
        println!(
            "  bare Python start: python3 did not run ({}/{runs} runs ok)",
            python.correct
        );
        None
    };

    let mut failed = false;
    let mut goal_lines = Vec::new();
    for (i, backend) in Backend::ALL.into_iter().enumerate() {
        if backend == Backend::Zenoh {
            // Needs a router the bench does not start yet (issue 29).
            println!("backend {backend}: not measured yet");
            continue;
        }
        let domain = DOMAIN + i as u32;
        if !backend.is_available() {
            println!("backend {backend}: not built in (feature `cyclone`), not measured");
            continue;
        }
        println!("backend {backend} (HORUS_ROS_BACKEND={backend}, domain {domain}):");
        let run = match run_backend(bin, backend, domain, runs) {
            Ok(run) => run,
            Err(e) => {
                println!("  not measured: {e}");
                failed = true;
                continue;
            }
        };
        let (no_wait, no_wait_ok) = (&run.no_wait.stats, run.no_wait.correct);
        let (list_stats, list_ok) = (&run.list.stats, run.list.correct);
        println!(
            "  join, shortest wait  (`service list --spin-time 0`):     {}  complete answers {no_wait_ok}/{runs}",
            no_wait.line()
        );
        println!(
            "  service list         (default --spin-time 0.5):          {}  correct answers {list_ok}/{runs}",
            list_stats.line()
        );
        let median = list_stats.median();
        println!(
            "  of which discovery wait (median service list − median --spin-time 0): {:.1} ms",
            ms(median.saturating_sub(no_wait.median()))
        );
        let met = median < GOAL && list_ok == runs;
        goal_lines.push(format!(
            "goal: < 300 ms — {} on {backend} (median {:.1} ms, p90 {:.1} ms, {list_ok}/{runs} answers correct)",
            if met { "MET" } else { "NOT MET" },
            ms(median),
            ms(list_stats.percentile(90)),
        ));
        match &run.nodes {
            Ok(series) => goal_lines.push(print_node_lists(
                "node list (4 nodes)",
                backend,
                runs,
                series,
            )),
            Err(e) => {
                println!("  node list through the daemon: not measured: {e}");
                failed = true;
            }
        }
        let fast_domain = FAST_DDS_DOMAIN + i as u32;
        match run_fast_dds(bin, backend, fast_domain, runs) {
            Ok(series) => goal_lines.push(print_node_lists(
                "node list (Fast DDS node)",
                backend,
                runs,
                &series,
            )),
            Err(e) => {
                println!(
                    "  node list with a Fast DDS node (domain {fast_domain}): not measured: {e}"
                );
                failed = true;
            }
        }
    }

    match python_median {
        Some(p) => println!(
            "ros2cli reference (`ros2 service list`, no daemon): documented --spin-time 0.5 s + \
             bare Python start {:.1} ms = {:.1} ms — a lower bound: its rclpy/ros2cli imports \
             and node creation come on top and are not measured here (no ROS 2 on this machine)",
            ms(p),
            ms(ROS2CLI_SPIN_TIME + p)
        ),
        None => println!(
            "ros2cli reference (`ros2 service list`, no daemon): documented --spin-time 0.5 s \
             + Python start (not measured: no python3)"
        ),
    }
    for line in goal_lines {
        println!("{line}");
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
