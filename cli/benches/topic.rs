//! `topic echo` and `topic hz` on live topics, on each backend built in (or only the one
//! `HORUS_ROS_BACKEND` names), each figure beside a baseline measured in the same run.
//!
//! 1. Time to the first echoed message: a real ROS 2 Jazzy publisher (rclpy 7.1 on
//!    rmw_fastrtps_cpp, `cli/tests/peers/jazzy_topic_publisher.py`) of `std_msgs/msg/String` at
//!    10 Hz on `/chatter`, up for `HORUS_ROS_BENCH_PEER_AGE_MS` (default 2000) before the first
//!    run (started once: its own start-up is not in any figure). Timed from spawning
//!    `horus-ros topic echo --once /chatter` (release build) to the line `data: hello` on its
//!    stdout, and to its exit: cold (`--no-daemon`) and with the daemon running
//!    (`horus-ros daemon start` first), `HORUS_ROS_BENCH_RUNS` runs each (default 10). The
//!    baseline: a plain subscriber program on our rmw (this bench re-run as a child), type
//!    compiled in, reliable/volatile as echo chooses for this publisher, from its spawn to its
//!    first message. It pays what any new process pays (participant, discovery of the
//!    publisher, matching, the wait for the next publish, up to 100 ms at 10 Hz) and nothing of
//!    echo's own (graph settling, type lookup, printing), so echo / baseline is the CLI's cost.
//! 2. `topic hz` accuracy and CPU: a publisher on our rmw (this bench re-run as a child) of
//!    `std_msgs/msg/String` at `HORUS_ROS_BENCH_HZ_RATE` Hz (default 1000), then of
//!    `sensor_msgs/msg/Image` 1920×1080 `rgb8` (6 220 800 bytes of data) at 30 Hz, paced on
//!    absolute deadlines; it keeps the publish time of every message. Its own achieved rate over
//!    the span measured is the baseline of the rates. For each: first a plain subscriber program
//!    on our rmw (raw samples, never decoded, `sensor_data` QoS, as hz subscribes) for
//!    `HORUS_ROS_BENCH_HZ_SECS` (default 6), then `horus-ros topic hz` for as long. Printed: the
//!    publisher's rate over the span each one measured (its first to last message received), each
//!    one's rate and its ratio to the publisher's, messages counted against those published in
//!    that span, and the CPU time of each process (utime + stime from `/proc/<pid>/stat`, in
//!    USER_HZ = 100 ticks per second as on every Linux) per second of wall time over the
//!    measured seconds, from its first message (the plain subscriber) or first report (hz) on.
//!    The plain subscriber's CPU is the baseline of hz's CPU; the publisher's is printed too.
//!    hz's rate is the last `average rate:` it printed; its span is `window` intervals of
//!    1 / rate each (ros2topic's rate is 1 / mean interval over the window), which stays below
//!    the default window of 10000 at the default settings.
//!
//! Cyclone DDS runs with `CYCLONEDDS_URI`, else loopback with a 4 MB socket receive buffer (see
//! [`CYCLONE_CONFIG`]: without it no image arrives). `HORUS_ROS_BENCH_TOPIC_ONLY=echo|hz|image`
//! runs one part. Joins DDS domains (180 to 182, and
//! 190 to 192 for the second backend), so it must run inside the private network namespace:
//!
//! ```text
//! cargo bench -p horus-ros-cli --bench topic --no-run
//! scripts/isolated cargo bench -p horus-ros-cli --bench topic
//! ```
//!
//! Part 1 needs the test venv's rclpy (`HORUS_ROS_INTEROP_PYTHON`, else `target/interop-venv`).
//! Every daemon it starts is stopped, and killed by its pid if it does not stop (the bench reaps
//! orphans, so the daemons are its children).

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, ExitCode, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::sensor_msgs::msg::Image;
use horus_ros_msgs::std_msgs::msg::{Header, String as StringMsg};
use horus_ros_msgs::Message;
use horus_ros_rmw::args::Arguments;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::raw::RawEndpointSpec;
use horus_ros_rmw::{Backend, Context, Node, BACKEND_ENV};

mod common;

use common::{env_number, interfaces_up, ms};

/// The first domain of the first backend; the next backend's are 10 higher.
const DOMAIN: u32 = 180;
const ECHO_TOPIC: &str = "/chatter";
const HZ_TOPIC: &str = "/bench_hz";
const IMAGE_TOPIC: &str = "/bench_image";
/// The image topic's rate and size.
const IMAGE_RATE: f64 = 30.0;
const IMAGE_WIDTH: u32 = 1920;
const IMAGE_HEIGHT: u32 = 1080;
/// How long the rclpy peer, a helper or the CLI may take to start on a loaded machine.
const START_LIMIT: Duration = Duration::from_secs(60);
/// How long a subscriber may take to its first message (plain) or first report (hz).
const FIRST_LIMIT: Duration = Duration::from_secs(20);
/// How long one `topic echo --once` may take.
const ECHO_LIMIT: Duration = Duration::from_secs(30);

/// The Cyclone DDS configuration used when `CYCLONEDDS_URI` is unset: the benches' loopback one
/// (common::CYCLONE_LOOPBACK) with a 4 MB socket receive buffer. With Cyclone's default buffer
/// no 6.2 MB image reaches a best-effort (`sensor_data`) reader on loopback, the plain
/// subscriber's nor `topic hz`'s (nothing in 20 s, measured here): the burst of a sample's
/// fragments overflows it, and best effort repairs nothing.
const CYCLONE_CONFIG: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General><Internal>\
    <SocketReceiveBufferSize min=\"4MB\"/></Internal></Domain></CycloneDDS>";

/// Set in the environment of the bench's own child processes: `publish`, `first` or `count`.
const ROLE_ENV: &str = "HORUS_ROS_BENCH_TOPIC_ROLE";
/// The helper's domain, topic, message kind (`string` or `image`) and rate.
const DOMAIN_ENV: &str = "HORUS_ROS_BENCH_TOPIC_DOMAIN";
const TOPIC_ENV: &str = "HORUS_ROS_BENCH_TOPIC_NAME";
const KIND_ENV: &str = "HORUS_ROS_BENCH_TOPIC_KIND";
const RATE_ENV: &str = "HORUS_ROS_BENCH_TOPIC_RATE";

/// Nanoseconds since the epoch (the clock `topic hz` stamps messages with).
fn now_ns() -> i64 {
    epoch_ns(SystemTime::now())
}

fn epoch_ns(t: SystemTime) -> i64 {
    t.duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
}

use horus_ros_test_support::jazzy::python;

/// Median and p90 of timed runs, and how many failed.
struct Series {
    times: Vec<Duration>,
    failed: usize,
}

impl Series {
    fn new() -> Self {
        Self {
            times: Vec::new(),
            failed: 0,
        }
    }

    fn push(&mut self, took: Option<Duration>) {
        match took {
            Some(t) => self.times.push(t),
            None => self.failed += 1,
        }
    }

    /// The `q`-quantile (nearest rank).
    fn quantile(&self, q: f64) -> Duration {
        let mut t = self.times.clone();
        t.sort();
        if t.is_empty() {
            return Duration::ZERO;
        }
        let rank = ((q * t.len() as f64).ceil() as usize).clamp(1, t.len());
        t[rank - 1]
    }

    fn line(&self) -> String {
        format!(
            "median {:>7.1} ms  p90 {:>7.1} ms  ({} runs{})",
            ms(self.quantile(0.5)),
            ms(self.quantile(0.9)),
            self.times.len(),
            if self.failed > 0 {
                format!(", {} failed", self.failed)
            } else {
                String::new()
            }
        )
    }
}

fn ratio(a: f64, b: f64) -> String {
    if b == 0.0 {
        "-".to_owned()
    } else {
        format!("{:.3}", a / b)
    }
}

// ---------------------------------------------------------------------------------------------
// Process accounting.

/// CPU time (utime + stime, all threads) of process `pid`, from `/proc/<pid>/stat` (fields 14
/// and 15, in USER_HZ ticks of 10 ms).
fn cpu_time(pid: u32) -> Option<Duration> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it.
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: u64 = fields.get(11)?.parse().ok()?;
    let stime: u64 = fields.get(12)?.parse().ok()?;
    Some(Duration::from_millis((utime + stime) * 10))
}

/// Peak resident memory of process `pid` (`VmHWM`), in MiB.
fn peak_rss_mib(pid: u32) -> Option<f64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// A CPU reading of one process at one time.
#[derive(Clone, Copy)]
struct CpuMark {
    at: Instant,
    cpu: Duration,
}

impl CpuMark {
    fn of(pid: u32) -> Option<Self> {
        Some(Self {
            cpu: cpu_time(pid)?,
            at: Instant::now(),
        })
    }

    /// CPU seconds per wall second from `self` to `later`, in percent of one core.
    fn percent_to(&self, later: &CpuMark) -> f64 {
        let wall = later.at.duration_since(self.at).as_secs_f64();
        if wall <= 0.0 {
            return 0.0;
        }
        later.cpu.saturating_sub(self.cpu).as_secs_f64() / wall * 100.0
    }
}

// ---------------------------------------------------------------------------------------------
// Child processes.

/// A child whose stdout lines arrive on a channel, each with the wall-clock time it was read.
struct Piped {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: mpsc::Receiver<(SystemTime, String)>,
}

impl Piped {
    fn spawn(mut command: Command) -> std::io::Result<Self> {
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()?;
        let stdin = child.stdin.take();
        let (tx, lines) = mpsc::channel();
        if let Some(stdout) = child.stdout.take() {
            std::thread::spawn(move || {
                for line in BufReader::new(stdout).lines() {
                    let Ok(line) = line else { break };
                    if tx.send((SystemTime::now(), line)).is_err() {
                        break;
                    }
                }
            });
        }
        Ok(Self {
            child,
            stdin,
            lines,
        })
    }

    /// The next stdout line, at most `limit` from now.
    fn line(&self, limit: Duration) -> Option<(SystemTime, String)> {
        self.lines.recv_timeout(limit).ok()
    }

    /// The first stdout line satisfying `pred`, at most `limit` from now.
    fn line_where(
        &self,
        limit: Duration,
        pred: impl Fn(&str) -> bool,
    ) -> Option<(SystemTime, String)> {
        let deadline = Instant::now() + limit;
        loop {
            let left = deadline.checked_duration_since(Instant::now())?;
            let (at, line) = self.line(left)?;
            if pred(&line) {
                return Some((at, line));
            }
        }
    }

    fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Waits for its exit, at most `limit`; kills it after that. Returns when it exited.
    fn wait_exit(&mut self, limit: Duration) -> Option<Instant> {
        let deadline = Instant::now() + limit;
        loop {
            match self.child.try_wait() {
                Ok(Some(_)) => return Some(Instant::now()),
                Ok(None) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_micros(500));
                }
                _ => {
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    return None;
                }
            }
        }
    }

    /// Sends it SIGINT (as Ctrl-C does) and waits for it, killing it after 10 s.
    fn interrupt(&mut self) {
        if let Ok(pid) = i32::try_from(self.child.id()) {
            let _ = nix::sys::signal::kill(
                nix::unistd::Pid::from_raw(pid),
                nix::sys::signal::Signal::SIGINT,
            );
        }
        self.wait_exit(Duration::from_secs(10));
    }
}

impl Drop for Piped {
    fn drop(&mut self) {
        drop(self.stdin.take());
        if self.wait_exit(Duration::from_secs(5)).is_none() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// This bench re-run as a helper (`role`) on `backend`.
fn helper(
    role: &str,
    backend: Backend,
    domain: u32,
    topic: &str,
    kind: &str,
    rate: f64,
) -> Command {
    let mut c = Command::new(std::env::current_exe().unwrap_or_else(|_| "/proc/self/exe".into()));
    c.env(ROLE_ENV, role)
        .env(BACKEND_ENV, backend.name())
        .env(DOMAIN_ENV, domain.to_string())
        .env(TOPIC_ENV, topic)
        .env(KIND_ENV, kind)
        .env(RATE_ENV, rate.to_string())
        .env("RUST_LOG", "error");
    c
}

/// The CLI with `args` on `backend` in `domain`.
fn cli(backend: Backend, domain: u32, args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    c.args(["--domain-id", &domain.to_string()])
        .args(args)
        .env(BACKEND_ENV, backend.name())
        .env("RUST_LOG", "error");
    c
}

/// `horus-ros daemon <verb>` (`--json`); its output, if it ran.
fn daemon(verb: &str, backend: Backend, domain: u32) -> Option<serde_json::Value> {
    let out = cli(backend, domain, &["--json", "daemon", verb])
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .ok()?;
    serde_json::from_slice(&out.stdout).ok()
}

/// A daemon started by `horus-ros daemon start`: stopped when dropped, else killed by its pid
/// (it is this process's child: the bench reaps orphans).
struct Daemon {
    backend: Backend,
    domain: u32,
    pid: Option<i32>,
}

impl Daemon {
    fn start(backend: Backend, domain: u32) -> Result<Self, String> {
        let pid = daemon("start", backend, domain)
            .and_then(|s| s["pid"].as_i64())
            .and_then(|p| i32::try_from(p).ok());
        match pid {
            Some(_) => Ok(Self {
                backend,
                domain,
                pid,
            }),
            None => Err("`horus-ros daemon start` started no daemon".to_owned()),
        }
    }
}

impl Drop for Daemon {
    fn drop(&mut self) {
        let stopped = daemon("stop", self.backend, self.domain)
            .is_some_and(|s| s["stopped"] == serde_json::Value::Bool(true));
        if let Some(pid) = self.pid.map(nix::unistd::Pid::from_raw) {
            if !stopped {
                let _ = nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGKILL);
            }
            let _ = nix::sys::wait::waitpid(pid, None);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Part 1: time to the first echoed message.

/// What part 1 measured.
struct EchoFigures {
    cold_first: Series,
    cold_exit: Series,
    daemon_first: Series,
    daemon_exit: Series,
    plain_first: Series,
    plain_exit: Series,
}

/// One timed process: spawn → first stdout line satisfying `pred`, spawn → exit.
fn first_message(
    command: Command,
    pred: impl Fn(&str) -> bool,
) -> (Option<Duration>, Option<Duration>) {
    let started = Instant::now();
    let Ok(mut p) = Piped::spawn(command) else {
        return (None, None);
    };
    let first = p.line_where(ECHO_LIMIT, pred).map(|_| started.elapsed());
    if first.is_none() {
        let _ = p.child.kill();
    }
    drop(p.stdin.take());
    let exit = p.wait_exit(ECHO_LIMIT).map(|at| at.duration_since(started));
    (first, exit.filter(|_| first.is_some()))
}

fn echo_part(backend: Backend, domain: u32) -> Result<EchoFigures, String> {
    let peer_script =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/jazzy_topic_publisher.py");
    let mut command = Command::new(python());
    command.arg(peer_script).args([
        &domain.to_string(),
        "bench_talker",
        ECHO_TOPIC,
        "std_msgs/msg/String",
        "10",
        r#"[["data", "hello"]]"#,
        "nostamp",
        "3600",
    ]);
    let peer = Piped::spawn(command).map_err(|e| {
        format!(
            "could not start the rclpy publisher with {:?}: {e}",
            python()
        )
    })?;
    match peer.line(START_LIMIT) {
        Some((_, line)) if line.contains("bench_talker") => {}
        other => return Err(format!("the rclpy publisher did not start: {other:?}")),
    }
    std::thread::sleep(Duration::from_millis(env_number(
        "HORUS_ROS_BENCH_PEER_AGE_MS",
        2000,
    )));
    let runs = env_number("HORUS_ROS_BENCH_RUNS", 10);
    let mut f = EchoFigures {
        cold_first: Series::new(),
        cold_exit: Series::new(),
        daemon_first: Series::new(),
        daemon_exit: Series::new(),
        plain_first: Series::new(),
        plain_exit: Series::new(),
    };
    let echoed = |l: &str| l == "data: hello";
    let echo = |extra: &[&str]| {
        let mut args = extra.to_vec();
        args.extend(["topic", "echo", "--once", ECHO_TOPIC]);
        cli(backend, domain, &args)
    };
    // Interleaved, so that a slow phase of the machine does not fall on one series only.
    for _ in 0..runs {
        let (first, exit) = first_message(
            helper("first", backend, domain, ECHO_TOPIC, "string", 0.0),
            |l| l == "first",
        );
        f.plain_first.push(first);
        f.plain_exit.push(exit);
        let (first, exit) = first_message(echo(&["--no-daemon"]), echoed);
        f.cold_first.push(first);
        f.cold_exit.push(exit);
    }
    let daemon = Daemon::start(backend, domain)?;
    for _ in 0..runs {
        let (first, exit) = first_message(echo(&[]), echoed);
        f.daemon_first.push(first);
        f.daemon_exit.push(exit);
    }
    drop(daemon);
    drop(peer);
    Ok(f)
}

// ---------------------------------------------------------------------------------------------
// Part 2: `topic hz` accuracy and CPU.

/// What the publisher published in a span: count and rate over its first to last publish.
struct Published {
    count: u64,
    rate: f64,
}

/// The publisher helper: asked over stdin what it published in a span.
struct PublisherChild {
    p: Piped,
}

impl PublisherChild {
    fn start(
        backend: Backend,
        domain: u32,
        topic: &str,
        kind: &str,
        rate: f64,
    ) -> Result<Self, String> {
        let p = Piped::spawn(helper("publish", backend, domain, topic, kind, rate))
            .map_err(|e| format!("could not start the publisher: {e}"))?;
        match p.line(START_LIMIT) {
            Some((_, l)) if l == "ready" => Ok(Self { p }),
            other => Err(format!("the publisher did not start: {other:?}")),
        }
    }

    /// What it published in `[from, to]` (epoch ns).
    fn published(&mut self, from: i64, to: i64) -> Option<Published> {
        let stdin = self.p.stdin.as_mut()?;
        writeln!(stdin, "{from} {to}").ok()?;
        stdin.flush().ok()?;
        let (_, line) = self.p.line(Duration::from_secs(10))?;
        let doc: serde_json::Value = serde_json::from_str(&line).ok()?;
        Some(Published {
            count: doc["count"].as_u64()?,
            rate: doc["rate"].as_f64()?,
        })
    }

    /// Stops it; returns how many deadlines it missed in all.
    fn stop(mut self) -> Option<u64> {
        drop(self.p.stdin.take());
        let (_, line) = self.p.line(Duration::from_secs(10))?;
        let doc: serde_json::Value = serde_json::from_str(&line).ok()?;
        doc["skipped"].as_u64()
    }
}

/// One subscriber's figures against the publisher's.
struct Measured {
    /// Its rate, Hz.
    rate: f64,
    /// Messages it counted.
    counted: u64,
    /// The publisher in the span it measured.
    published: Published,
    /// CPU % of one core over the measured seconds.
    cpu: f64,
    /// CPU time in all (start-up included).
    cpu_total: Duration,
    /// Peak RSS, MiB.
    rss: f64,
    /// From spawn to its first message (plain) or first report (hz).
    started: Duration,
    /// hz only: the rates of its reports, in order.
    reports: Vec<f64>,
    /// Plain subscriber: its last message's latency (receive − publish), ns; hz: the shift
    /// applied to its span to find the messages published in it (the plain subscriber's).
    latency: i64,
}

/// The plain subscriber (raw samples, `sensor_data` QoS) for `secs`.
fn plain_count(
    backend: Backend,
    domain: u32,
    topic: &str,
    kind: &str,
    secs: Duration,
    publisher: &mut PublisherChild,
) -> Result<(Measured, f64), String> {
    let spawned = Instant::now();
    let mut p = Piped::spawn(helper("count", backend, domain, topic, kind, 0.0))
        .map_err(|e| format!("could not start the plain subscriber: {e}"))?;
    if p.line_where(FIRST_LIMIT, |l| l == "first").is_none() {
        return Err(format!("received nothing in {} s", FIRST_LIMIT.as_secs()));
    }
    let started = spawned.elapsed();
    let pub_pid = publisher.p.pid();
    let (m1, pub1) = (CpuMark::of(p.pid()), CpuMark::of(pub_pid));
    std::thread::sleep(secs);
    let (m2, pub2) = (CpuMark::of(p.pid()), CpuMark::of(pub_pid));
    let rss = peak_rss_mib(p.pid()).unwrap_or(0.0);
    drop(p.stdin.take());
    let (_, line) = p
        .line(Duration::from_secs(10))
        .ok_or("the plain subscriber said nothing at its end")?;
    p.wait_exit(Duration::from_secs(10));
    let doc: serde_json::Value =
        serde_json::from_str(&line).map_err(|e| format!("plain subscriber: {e}: {line}"))?;
    let field = |k: &str| doc[k].as_i64();
    let (Some(count), Some(first), Some(last), Some(latency), Some(r0), Some(r1)) = (
        doc["count"].as_u64(),
        field("first_pub_ns"),
        field("last_pub_ns"),
        field("latency_ns"),
        field("first_received_ns"),
        field("last_received_ns"),
    ) else {
        return Err(format!("plain subscriber: {line}"));
    };
    // Its rate as hz computes one: messages over the span of their receive times. Against
    // exactly the messages published from its first to its last (their publish times).
    let rate = if r1 > r0 {
        count.saturating_sub(1) as f64 / ((r1 - r0) as f64 * 1e-9)
    } else {
        0.0
    };
    let published = publisher
        .published(first, last)
        .ok_or("the publisher did not answer")?;
    let cpu = match (m1, m2) {
        (Some(a), Some(b)) => a.percent_to(&b),
        _ => 0.0,
    };
    let pub_cpu = match (pub1, pub2) {
        (Some(a), Some(b)) => a.percent_to(&b),
        _ => 0.0,
    };
    Ok((
        Measured {
            rate,
            counted: count,
            published,
            cpu,
            cpu_total: m2.map_or(Duration::ZERO, |m| m.cpu),
            rss,
            started,
            reports: Vec::new(),
            latency,
        },
        pub_cpu,
    ))
}

/// One report of `topic hz`: when it was read, its rate and window.
struct Report {
    at: SystemTime,
    rate: f64,
    window: u64,
}

/// `topic hz` for `secs` from its first report.
fn hz_run(
    backend: Backend,
    domain: u32,
    topic: &str,
    secs: Duration,
    latency: i64,
    publisher: &mut PublisherChild,
) -> Result<Measured, String> {
    let spawned = Instant::now();
    let mut p = Piped::spawn(cli(backend, domain, &["topic", "hz", topic]))
        .map_err(|e| format!("could not start topic hz: {e}"))?;
    // "average rate: %.3f" then "\tmin: %.3fs max: %.3fs std dev: %.5fs window: %s".
    let next_report = |p: &Piped, limit: Duration| -> Option<Report> {
        let (at, line) = p.line_where(limit, |l| l.starts_with("average rate: "))?;
        let rate: f64 = line
            .trim_start_matches("average rate: ")
            .trim()
            .parse()
            .ok()?;
        let (_, stats) = p.line(Duration::from_secs(1))?;
        let window: u64 = stats.rsplit("window: ").next()?.trim().parse().ok()?;
        Some(Report { at, rate, window })
    };
    let first = next_report(&p, FIRST_LIMIT)
        .ok_or_else(|| format!("reported nothing in {} s", FIRST_LIMIT.as_secs()))?;
    let started = spawned.elapsed();
    let m1 = CpuMark::of(p.pid());
    let deadline = Instant::now() + secs;
    let mut reports = vec![first];
    while let Some(left) = deadline.checked_duration_since(Instant::now()) {
        match next_report(&p, left) {
            Some(r) => reports.push(r),
            None => break,
        }
    }
    let m2 = CpuMark::of(p.pid());
    let rss = peak_rss_mib(p.pid()).unwrap_or(0.0);
    p.interrupt();
    let last = reports.last().ok_or("no report")?;
    if last.rate <= 0.0 {
        return Err("topic hz reported a rate of 0".to_owned());
    }
    // Its span in receive times, shifted back by the latency the plain subscriber saw to cover
    // the same messages' publish times (it is read a little after hz printed it: that too
    // is in the shift's error, a fraction of a period at 1 kHz).
    let to = epoch_ns(last.at) - latency;
    let span_ns = (last.window as f64 / last.rate * 1e9) as i64;
    let published = publisher
        .published(to - span_ns, to)
        .ok_or("the publisher did not answer")?;
    Ok(Measured {
        rate: last.rate,
        counted: last.window + 1,
        published,
        cpu: match (m1, m2) {
            (Some(a), Some(b)) => a.percent_to(&b),
            _ => 0.0,
        },
        cpu_total: m2.map_or(Duration::ZERO, |m| m.cpu),
        rss,
        started,
        reports: reports.iter().map(|r| r.rate).collect(),
        latency,
    })
}

/// What part 2 measured for one topic (each subscriber's figures, or why there are none).
struct HzFigures {
    plain: Result<Measured, String>,
    hz: Result<Measured, String>,
    /// The publisher's CPU % of a core while the plain subscriber counted.
    publisher_cpu: Option<f64>,
    skipped: Option<u64>,
}

fn hz_part(
    backend: Backend,
    domain: u32,
    topic: &str,
    kind: &str,
    rate: f64,
) -> Result<HzFigures, String> {
    let secs = Duration::from_secs(env_number("HORUS_ROS_BENCH_HZ_SECS", 6));
    let mut publisher = PublisherChild::start(backend, domain, topic, kind, rate)?;
    let (plain, publisher_cpu) =
        match plain_count(backend, domain, topic, kind, secs, &mut publisher) {
            Ok((m, cpu)) => (Ok(m), Some(cpu)),
            Err(e) => (Err(e), None),
        };
    // Without the plain subscriber's latency, hz's span is taken as is.
    let latency = plain.as_ref().map_or(0, |m| m.latency);
    let hz = hz_run(backend, domain, topic, secs, latency, &mut publisher);
    let skipped = publisher.stop();
    Ok(HzFigures {
        plain,
        hz,
        publisher_cpu,
        skipped,
    })
}

fn print_hz(title: &str, f: &HzFigures) {
    println!("  {title}:");
    let line = |name: &str, m: &Measured| {
        println!(
            "    {name:<16} rate {:>9.3} Hz  publisher {:>9.3} Hz  ratio {}  counted {}/{} \
             published  cpu {:>5.1} % of a core (start-up incl.: {:.2} s)  peak RSS {:.0} MiB  \
             first {} after {:.2} s",
            m.rate,
            m.published.rate,
            ratio(m.rate, m.published.rate),
            m.counted,
            m.published.count,
            m.cpu,
            m.cpu_total.as_secs_f64(),
            m.rss,
            if m.reports.is_empty() {
                "message"
            } else {
                "report"
            },
            m.started.as_secs_f64(),
        );
    };
    for (name, m) in [("plain subscriber", &f.plain), ("topic hz", &f.hz)] {
        match m {
            Ok(m) => line(name, m),
            Err(e) => println!("    {name:<16} not measured: {e}"),
        }
    }
    let (Ok(plain), Ok(hz)) = (&f.plain, &f.hz) else {
        return;
    };
    println!(
        "    topic hz / plain subscriber: rate ratio {}, cpu {}; publisher's own cpu {:.1} % of a \
         core, deadlines missed {}; latency {:.2} ms",
        ratio(
            hz.rate / hz.published.rate,
            plain.rate / plain.published.rate
        ),
        ratio(hz.cpu, plain.cpu),
        f.publisher_cpu.unwrap_or(0.0),
        f.skipped.map_or("?".to_owned(), |s| s.to_string()),
        plain.latency as f64 * 1e-6,
    );
    let reports: Vec<String> = hz.reports.iter().map(|r| format!("{r:.3}")).collect();
    println!("    topic hz reports: {}", reports.join(" "));
}

// ---------------------------------------------------------------------------------------------
// The helpers (this bench re-run with ROLE_ENV).

fn helper_context(domain: u32) -> Result<Context, String> {
    Context::builder()
        .domain_id(domain)
        .arguments(Arguments::default())
        .build()
        .map_err(|e| format!("no context: {e}"))
}

/// A raw reader of `topic` for messages `M` with `qos`.
fn raw_reader<M: Message>(
    node: &Node,
    topic: &str,
    qos: Qos,
) -> Result<horus_ros_rmw::raw::RawReader, String> {
    let spec = RawEndpointSpec {
        dds_topic_name: format!("rt{topic}"),
        dds_type_name: M::dds_type_name(),
        type_hash: M::type_hash(),
        qos,
        service_id: None,
    };
    node.create_raw_reader(&spec).map_err(|e| e.to_string())
}

/// A flag set when stdin closes.
fn stdin_closed() -> Arc<AtomicBool> {
    let closed = Arc::new(AtomicBool::new(false));
    let flag = closed.clone();
    std::thread::spawn(move || {
        let _ = std::io::copy(&mut std::io::stdin(), &mut std::io::sink());
        flag.store(true, Ordering::SeqCst);
    });
    closed
}

fn say(line: &str) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}

/// `first`: prints `first` at its first message (reliable, volatile: what echo chooses for
/// the rclpy publisher) and exits.
fn role_first(domain: u32, topic: &str) -> Result<(), String> {
    let context = helper_context(domain)?;
    let node = context
        .create_node("bench_first", "/")
        .map_err(|e| e.to_string())?;
    let mut reader = raw_reader::<StringMsg>(&node, topic, Qos::default())?;
    let deadline = Instant::now() + ECHO_LIMIT;
    while Instant::now() < deadline {
        reader.wait(Duration::from_millis(100));
        if let Ok(Some(_)) = reader.take() {
            say("first");
            return Ok(());
        }
    }
    Err("no message".to_owned())
}

/// The publish time (epoch ns) a message of the bench's publisher carries: its `data` (String)
/// or `header.stamp` (Image). Decoded only for the first and last message counted.
fn publish_time(kind: &str, sample: &horus_ros_rmw::raw::RawSample) -> Option<i64> {
    use byteorder::{BigEndian, LittleEndian};
    use horus_ros_msgs::cdr::from_cdr_body;
    if kind == "image" {
        let image: Image = if sample.big_endian {
            from_cdr_body::<Image, BigEndian>(&sample.body).ok()?
        } else {
            from_cdr_body::<Image, LittleEndian>(&sample.body).ok()?
        };
        Some(
            i64::from(image.header.stamp.sec) * 1_000_000_000
                + i64::from(image.header.stamp.nanosec),
        )
    } else {
        let text: StringMsg = if sample.big_endian {
            from_cdr_body::<StringMsg, BigEndian>(&sample.body).ok()?
        } else {
            from_cdr_body::<StringMsg, LittleEndian>(&sample.body).ok()?
        };
        text.data.parse().ok()
    }
}

/// `count`: counts raw samples (`sensor_data` QoS) until stdin closes; prints `first` at the
/// first, then `{"count", "first_pub_ns", "last_pub_ns", "latency_ns", "first_received_ns",
/// "last_received_ns"}`: the publish times of the first and last message counted, the last
/// one's latency (receive − publish time), and the receive times of both.
fn role_count(domain: u32, topic: &str, kind: &str) -> Result<(), String> {
    let context = helper_context(domain)?;
    let node = context
        .create_node("bench_count", "/")
        .map_err(|e| e.to_string())?;
    let mut reader = if kind == "image" {
        raw_reader::<Image>(&node, topic, Qos::sensor_data())?
    } else {
        raw_reader::<StringMsg>(&node, topic, Qos::sensor_data())?
    };
    let closed = stdin_closed();
    let (mut count, mut first, mut first_received, mut last) = (0u64, None, 0i64, None);
    while !closed.load(Ordering::SeqCst) {
        reader.wait(Duration::from_millis(50));
        while let Ok(Some(sample)) = reader.take() {
            let now = now_ns();
            if count == 0 {
                first = publish_time(kind, &sample);
                first_received = now;
                say("first");
            }
            // Kept (moved, not copied) and decoded at the end.
            last = Some((now, sample));
            count += 1;
        }
    }
    let (received, last) = last.ok_or("no message")?;
    let last_pub = publish_time(kind, &last).ok_or("the last message carries no publish time")?;
    let first_pub = first.ok_or("the first message carries no publish time")?;
    say(&serde_json::json!({
        "count": count,
        "first_pub_ns": first_pub,
        "last_pub_ns": last_pub,
        "latency_ns": received - last_pub,
        "first_received_ns": first_received,
        "last_received_ns": received,
    })
    .to_string());
    Ok(())
}

/// `publish`: publishes at the rate asked on absolute deadlines (a deadline missed by more
/// than a period is skipped and counted); prints `ready`, answers each stdin line `FROM TO`
/// (epoch ns) with `{"count", "rate"}` of what it published in that span, and at stdin's end
/// prints `{"skipped"}` and exits.
fn role_publish(domain: u32, topic: &str, kind: &str, rate: f64) -> Result<(), String> {
    let context = helper_context(domain)?;
    let node = context
        .create_node("bench_talker", "/")
        .map_err(|e| e.to_string())?;
    let times: Arc<Mutex<Vec<i64>>> = Arc::new(Mutex::new(Vec::new()));
    let stop = Arc::new(AtomicBool::new(false));
    {
        let (times, stop) = (times.clone(), stop.clone());
        std::thread::spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { break };
                let mut parts = line.split_whitespace().map(|p| p.parse::<i64>());
                let (Some(Ok(from)), Some(Ok(to))) = (parts.next(), parts.next()) else {
                    continue;
                };
                let t = times.lock().map(|t| t.clone()).unwrap_or_default();
                let inside: Vec<i64> = t.into_iter().filter(|&x| x >= from && x <= to).collect();
                let rate = match (inside.first(), inside.last()) {
                    (Some(&a), Some(&b)) if b > a => {
                        (inside.len() - 1) as f64 / ((b - a) as f64 * 1e-9)
                    }
                    _ => 0.0,
                };
                say(&serde_json::json!({"count": inside.len(), "rate": rate}).to_string());
            }
            stop.store(true, Ordering::SeqCst);
        });
    }
    // Each message carries its publish time (epoch ns), the one recorded for it.
    let mut publish: Box<dyn FnMut(i64) -> Result<(), String>> = if kind == "image" {
        let publisher = node
            .create_publisher::<Image>(topic, &Qos::default())
            .map_err(|e| e.to_string())?;
        let mut image = Image {
            header: Header {
                stamp: Time::default(),
                frame_id: "camera".to_owned(),
            },
            height: IMAGE_HEIGHT,
            width: IMAGE_WIDTH,
            encoding: "rgb8".to_owned(),
            is_bigendian: 0,
            step: IMAGE_WIDTH * 3,
            data: (0..IMAGE_WIDTH as usize * IMAGE_HEIGHT as usize * 3)
                .map(|i| (i % 251) as u8)
                .collect(),
        };
        Box::new(move |now| {
            image.header.stamp = Time {
                sec: (now / 1_000_000_000) as i32,
                nanosec: (now % 1_000_000_000) as u32,
            };
            publisher.publish(image.clone()).map_err(|e| e.to_string())
        })
    } else {
        let publisher = node
            .create_publisher::<StringMsg>(topic, &Qos::default())
            .map_err(|e| e.to_string())?;
        Box::new(move |now| {
            publisher
                .publish(StringMsg {
                    data: now.to_string(),
                })
                .map_err(|e| e.to_string())
        })
    };
    say("ready");
    let period = Duration::from_secs_f64(1.0 / rate);
    let start = Instant::now();
    let (mut tick, mut skipped) = (0u64, 0u64);
    while !stop.load(Ordering::SeqCst) {
        let due = start + period.mul_f64(tick as f64);
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        let now = now_ns();
        publish(now)?;
        if let Ok(mut t) = times.lock() {
            t.push(now);
        }
        tick += 1;
        let next = start + period.mul_f64(tick as f64);
        let late = Instant::now().saturating_duration_since(next);
        if late > period {
            let missed = (late.as_nanos() / period.as_nanos()) as u64;
            tick += missed;
            skipped += missed;
        }
    }
    say(&serde_json::json!({"skipped": skipped}).to_string());
    Ok(())
}

fn run_role(role: &str) -> ExitCode {
    let var = |k: &str| std::env::var(k).unwrap_or_default();
    let domain: u32 = var(DOMAIN_ENV).parse().unwrap_or(DOMAIN);
    let topic = var(TOPIC_ENV);
    let kind = var(KIND_ENV);
    let rate: f64 = var(RATE_ENV).parse().unwrap_or(1.0);
    let result = match role {
        "publish" => role_publish(domain, &topic, &kind, rate),
        "first" => role_first(domain, &topic),
        "count" => role_count(domain, &topic, &kind),
        other => Err(format!("unknown role {other}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("topic bench helper ({role}): {e}");
            ExitCode::FAILURE
        }
    }
}

// ---------------------------------------------------------------------------------------------

fn main() -> ExitCode {
    if let Ok(role) = std::env::var(ROLE_ENV) {
        return run_role(&role);
    }
    let up = interfaces_up();
    if !up.is_empty() {
        eprintln!(
            "topic bench: refusing to join DDS with network interfaces up ({}). Run it inside \
             the private namespace:\n  cargo bench -p horus-ros-cli --bench topic --no-run\n  \
             scripts/isolated cargo bench -p horus-ros-cli --bench topic",
            up.join(", ")
        );
        return ExitCode::from(2);
    }
    if std::env::var_os("CYCLONEDDS_URI").is_none() {
        std::env::set_var("CYCLONEDDS_URI", CYCLONE_CONFIG);
    }
    // Daemons started by the bench become this process's children: reaped, killed by pid.
    if let Err(e) = nix::sys::prctl::set_child_subreaper(true) {
        eprintln!("topic bench: cannot reap the daemons it starts ({e}); refusing to run");
        return ExitCode::FAILURE;
    }
    let only = std::env::var("HORUS_ROS_BENCH_TOPIC_ONLY").ok();
    let part = |name: &str| only.as_deref().is_none_or(|o| o == name);
    let chosen = std::env::var(BACKEND_ENV).ok();
    let hz_rate = env_number("HORUS_ROS_BENCH_HZ_RATE", 1000) as f64;
    let mut failed = false;
    for (i, backend) in Backend::ALL.into_iter().enumerate() {
        if backend == Backend::Zenoh {
            // Needs a router the bench does not start yet (issue 29).
            println!("backend {backend}: not measured yet");
            continue;
        }
        if chosen.as_deref().is_some_and(|c| c != backend.name()) {
            continue;
        }
        if !backend.is_available() {
            println!("backend {backend}: not built in, not measured");
            continue;
        }
        let domain = DOMAIN + 10 * i as u32;
        println!("backend {backend} (domains {domain} to {}):", domain + 2);
        if part("echo") {
            println!(
                "  time to the first echoed message: rclpy publisher (Fast DDS), std_msgs/String \
                 at 10 Hz on {ECHO_TOPIC}; spawn → `data: hello` on stdout (first), spawn → exit \
                 (exit)"
            );
            match echo_part(backend, domain) {
                Ok(f) => {
                    let base = f.plain_first.quantile(0.5).as_secs_f64();
                    println!("    plain subscriber, first  {}", f.plain_first.line());
                    println!("    plain subscriber, exit   {}", f.plain_exit.line());
                    println!("    echo cold, first         {}", f.cold_first.line());
                    println!("    echo cold, exit          {}", f.cold_exit.line());
                    println!("    echo + daemon, first     {}", f.daemon_first.line());
                    println!("    echo + daemon, exit      {}", f.daemon_exit.line());
                    println!(
                        "    median first / plain subscriber's median first: cold {}, with the \
                         daemon {}",
                        ratio(f.cold_first.quantile(0.5).as_secs_f64(), base),
                        ratio(f.daemon_first.quantile(0.5).as_secs_f64(), base),
                    );
                    failed |=
                        f.cold_first.failed + f.daemon_first.failed + f.plain_first.failed > 0;
                }
                Err(e) => {
                    println!("    not measured: {e}");
                    failed = true;
                }
            }
        }
        let topics = [
            (
                "hz",
                HZ_TOPIC,
                "string",
                hz_rate,
                format!("std_msgs/String at {hz_rate} Hz"),
            ),
            (
                "image",
                IMAGE_TOPIC,
                "image",
                IMAGE_RATE,
                format!(
                    "sensor_msgs/Image {IMAGE_WIDTH}x{IMAGE_HEIGHT} rgb8 ({} bytes) at \
                     {IMAGE_RATE} Hz",
                    IMAGE_WIDTH * IMAGE_HEIGHT * 3
                ),
            ),
        ];
        for (j, (name, topic, kind, rate, title)) in topics.into_iter().enumerate() {
            if !part(name) {
                continue;
            }
            match hz_part(backend, domain + 1 + j as u32, topic, kind, rate) {
                Ok(f) => {
                    failed |= f.plain.is_err() || f.hz.is_err();
                    print_hz(&title, &f);
                }
                Err(e) => {
                    println!("  {title}: not measured: {e}");
                    failed = true;
                }
            }
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
