//! `horus-ros topic hz` beside `ros2 topic hz` (ros2cli 0.32.2), run at the same time on the same
//! rclpy publisher (`cli/tests/peers/jazzy_topic_publisher.py`, std_msgs/msg/String at
//! `HORUS_ROS_BENCH_HZ_RATE` Hz, default 100), on each of the three RMWs: the peers and `ros2` on
//! rmw_fastrtps_cpp, rmw_cyclonedds_cpp and rmw_zenoh_cpp (beside `rmw_zenohd`), `horus-ros` on
//! the backend that RMW selects. Both run for `HORUS_ROS_BENCH_HZ_SECS` (default 10) from their
//! first report; printed: the last `average rate:` of each and their ratio, with
//! `HORUS_ROS_BENCH_HZ_HOGS` processes spinning on the CPU meanwhile (default 2, as `yes` does).
//!
//! Run inside a private network namespace: `scripts/bench`, or
//! `cargo bench -p horus-ros-cli --bench hz_beside_ros2 --no-run` then
//! `scripts/isolated cargo bench -p horus-ros-cli --bench hz_beside_ros2`.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use horus_ros_test_support::bench::{
    cpu_hogs, env_count, env_usize, loadavg, refuse_outside_namespace, Stopped,
};
use horus_ros_test_support::jazzy::{self, Rmw};
use horus_ros_test_support::line_reader;

const DOMAIN: u32 = 93;
const TOPIC: &str = "/hz_beside_ros2";
/// How long each `topic hz` may take to its first report (Python and rclpy start included).
const FIRST_REPORT: Duration = Duration::from_secs(60);

/// A `topic hz` process and its standard output, line by line.
struct Hz {
    _child: Stopped,
    lines: Receiver<String>,
}

impl Hz {
    fn spawn(mut command: Command) -> Self {
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start topic hz");
        let lines = line_reader(child.stdout.take().expect("piped stdout"));
        Self {
            _child: Stopped(child),
            lines,
        }
    }

    /// The rate of its next `average rate:` line printed by `deadline`.
    fn next_rate(&self, deadline: Instant) -> Option<f64> {
        loop {
            let left = deadline.checked_duration_since(Instant::now())?;
            let line = self.lines.recv_timeout(left).ok()?;
            if let Some(rate) = line.strip_prefix("average rate: ") {
                return rate.trim().parse().ok();
            }
        }
    }

    /// Its last rate after `secs` from its first report (None if it reported nothing).
    fn last_rate(&self, secs: Duration) -> Option<f64> {
        let mut last = self.next_rate(Instant::now() + FIRST_REPORT)?;
        let end = Instant::now() + secs;
        while let Some(rate) = self.next_rate(end) {
            last = rate;
        }
        Some(last)
    }
}

/// A command in the peers' environment on `rmw`, in the bench's domain.
fn on_rmw(mut command: Command, rmw: Rmw) -> Command {
    command
        .env("RMW_IMPLEMENTATION", rmw.name())
        .env("ROS_DOMAIN_ID", DOMAIN.to_string())
        .env(
            "CYCLONEDDS_URI",
            "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
             <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
             <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>",
        );
    command
}

fn rmw_zenohd() -> Stopped {
    let mut command = jazzy::command("bash");
    command
        .args([
            "-c",
            r#"exec "$(ros2 pkg prefix rmw_zenoh_cpp)/lib/rmw_zenoh_cpp/rmw_zenohd""#,
        ])
        .env(
            "ZENOH_CONFIG_OVERRIDE",
            r#"listen/endpoints=["tcp/localhost:7447"]"#,
        )
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    let mut child = command.spawn().expect("start rmw_zenohd");
    let lines = line_reader(child.stdout.take().expect("piped stdout"));
    let started = std::iter::from_fn(|| lines.recv_timeout(FIRST_REPORT).ok())
        .any(|l| l.starts_with("Started Zenoh router"));
    assert!(started, "rmw_zenohd did not start");
    Stopped(child)
}

fn publisher(rmw: Rmw, rate: usize) -> Stopped {
    let script =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/jazzy_topic_publisher.py");
    let mut command = Command::new(jazzy::python());
    command.arg(script).args([
        &DOMAIN.to_string(),
        "hz_publisher",
        TOPIC,
        "std_msgs/msg/String",
        &rate.to_string(),
        r#"[["data", "hz"]]"#,
        "-",
        "3600",
    ]);
    let mut child = on_rmw(command, rmw)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start the publisher");
    let lines = line_reader(child.stdout.take().expect("piped stdout"));
    lines
        .recv_timeout(FIRST_REPORT)
        .expect("the publisher's first line");
    Stopped(child)
}

fn main() {
    refuse_outside_namespace(
        "hz_beside_ros2",
        "scripts/isolated cargo bench -p horus-ros-cli --bench hz_beside_ros2",
    );
    let rate = env_usize("HORUS_ROS_BENCH_HZ_RATE", 100);
    let secs = Duration::from_secs(env_usize("HORUS_ROS_BENCH_HZ_SECS", 10) as u64);
    let hogs = env_count("HORUS_ROS_BENCH_HZ_HOGS", 2);
    let _hogs = cpu_hogs(hogs);
    println!(
        "topic hz of an rclpy publisher at {rate} Hz, horus-ros beside ros2 (run together, {} s \
         from each one's first report), {hogs} CPU hogs, load {}",
        secs.as_secs(),
        loadavg()
    );
    println!(
        "{:<20} {:>16} {:>16} {:>10}",
        "RMW", "horus-ros Hz", "ros2 Hz", "ratio"
    );
    for rmw in Rmw::ALL {
        let _router = (rmw == Rmw::Zenoh).then(rmw_zenohd);
        let _publisher = publisher(rmw, rate);
        let mut ours = on_rmw(Command::new(env!("CARGO_BIN_EXE_horus-ros")), rmw);
        ours.args(["topic", "hz", TOPIC]);
        let mut theirs = on_rmw(jazzy::command("ros2"), rmw);
        theirs.args(["topic", "hz", TOPIC]);
        let (ours, theirs) = (Hz::spawn(ours), Hz::spawn(theirs));
        // Both read at once, each in a thread of its own (each stopped when its thread ends).
        let o = std::thread::spawn(move || ours.last_rate(secs));
        let t = std::thread::spawn(move || theirs.last_rate(secs));
        let (ours, theirs) = (o.join().ok().flatten(), t.join().ok().flatten());
        let show = |r: Option<f64>| r.map_or_else(|| "none".to_owned(), |r| format!("{r:.3}"));
        let ratio = match (ours, theirs) {
            (Some(o), Some(t)) if t > 0.0 => format!("{:.3}", o / t),
            _ => "-".to_owned(),
        };
        println!(
            "{:<20} {:>16} {:>16} {:>10}",
            rmw.name(),
            show(ours),
            show(theirs),
            ratio
        );
    }
    println!("load at the end: {}", loadavg());
}
