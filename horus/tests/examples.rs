//! Runs the crate's examples as the programs they are (separate processes, `--ros-args`,
//! Ctrl+C), inside the test network namespace, and looks at them with the `horus-ros` CLI as
//! ros2cli would. `cargo test` builds the examples with the tests; the CLI is built by the
//! workspace build (`scripts/test`) or `cargo build -p horus-ros-cli`.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use horus::prelude::*;

const WAIT: Duration = Duration::from_secs(30);

message! {
    /// The motor controller example's command type.
    CmdVel { linear: f32, angular: f32 }
    /// Its output type.
    MotorCommand { left_rpm: f32, right_rpm: f32 }
}

/// `target/<profile>`, where this test binary's `deps/` is.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("current exe");
    exe.parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>")
        .to_path_buf()
}

fn example(name: &str) -> PathBuf {
    horus_ros_test_support::built_example(name)
}

/// The `horus-ros` CLI of the same build (the CLI does not depend on this crate, so this one
/// cannot ask cargo for it: the workspace build builds it).
fn cli() -> PathBuf {
    let path = profile_dir().join("horus-ros");
    assert!(
        path.exists(),
        "{} not built: `cargo build -p horus-ros-cli` (scripts/test builds the workspace)",
        path.display()
    );
    path
}

/// A running example whose stdout lines arrive on a channel.
struct Running {
    child: Child,
    lines: mpsc::Receiver<String>,
    seen: Vec<String>,
}

impl Running {
    fn start(name: &str, domain: u32, args: &[&str], env: &[(&str, &str)]) -> Self {
        let mut child = Command::new(example(name))
            .args(args)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .envs(env.iter().copied())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("spawn example");
        let lines = interop_tests::line_reader(child.stdout.take().expect("stdout"));
        Self {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Waits for a line containing `what` (woken by each line; bounded).
    fn expect_line(&mut self, what: &str) -> String {
        let end = Instant::now() + WAIT;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    self.seen.push(line.clone());
                    if line.contains(what) {
                        return line;
                    }
                }
                Err(_) => panic!("no line with {what:?}; saw {:#?}", self.seen),
            }
        }
    }

    fn interrupt(&self) {
        let pid = nix::unistd::Pid::from_raw(i32::try_from(self.child.id()).expect("pid"));
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGINT).expect("SIGINT");
    }

    fn wait_success(mut self) -> Vec<String> {
        let status = self.child.wait().expect("wait");
        let mut seen = std::mem::take(&mut self.seen);
        seen.extend(self.lines.try_iter());
        assert!(status.success(), "{status}; output {seen:#?}");
        seen
    }
}

impl Drop for Running {
    /// A test that failed leaves no example behind.
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

#[test]
fn talker_and_listener_talk_across_processes_with_ros_args() {
    let domain = 181;
    let mut listener = Running::start(
        "listener",
        domain,
        &["--count", "3", "--ros-args", "-r", "chatter:=/demo/chatter"],
        &[],
    );
    listener.expect_line("listening");
    let talker = Running::start(
        "talker",
        domain,
        &["--ros-args", "-r", "__ns:=/demo", "-r", "__node:=speaker"],
        &[("TALKER_RATE_HZ", "20")],
    );
    let heard = listener.expect_line("I heard: [Hello World: ");
    assert!(heard.ends_with(']'), "{heard}");
    let lines = listener.wait_success();
    assert_eq!(
        lines.iter().filter(|l| l.contains("I heard")).count(),
        3,
        "{lines:#?}"
    );
    talker.interrupt();
    let lines = talker.wait_success();
    assert!(
        lines.iter().any(|l| l.contains("shut down after")),
        "{lines:#?}"
    );
}

#[test]
fn lidar_publishes_scans_from_its_parameter_port_and_stops_its_motor_on_ctrl_c() {
    let domain = own_domain();
    let scans = Topic::<LaserScan>::new("/scan").expect("topic");
    scans.connect_subscriber().expect("subscribe");
    let mut lidar = Running::start(
        "lidar",
        domain,
        &["--ros-args", "-p", "port:=/dev/sim0"],
        &[],
    );
    lidar.expect_line("connected on /dev/sim0");
    let scan = scans.recv_timeout(WAIT).expect("a scan");
    assert_eq!(scan.ranges.len(), 360);
    assert_eq!(scan.header.frame_id, "laser");
    lidar.interrupt();
    let lines = lidar.wait_success();
    assert!(
        lines
            .iter()
            .any(|l| l.contains("motor of /dev/sim0 stopped")),
        "shutdown ran on Ctrl+C: {lines:#?}"
    );
}

/// The domain of this test process's own topics (they live in its process-wide context,
/// configured from the environment): the examples it talks to join it.
fn own_domain() -> u32 {
    std::env::var("ROS_DOMAIN_ID")
        .ok()
        .and_then(|d| d.parse().ok())
        .unwrap_or(0)
}

#[test]
fn motor_controller_drives_and_zeroes_the_motors_on_ctrl_c() {
    let domain = own_domain();
    let commands = Topic::<MotorCommand>::new("/motor/cmd").expect("topic");
    commands.connect_subscriber().expect("subscribe");
    let cmd_vel = Topic::<CmdVel>::new("/cmd_vel").expect("topic");
    let mut motor = Running::start("motor_controller", domain, &[], &[]);
    motor.expect_line("ready");
    let end = Instant::now() + WAIT;
    let driven = loop {
        assert!(Instant::now() < end, "no motor command");
        cmd_vel.send(CmdVel {
            linear: 1.0,
            angular: 0.5,
        });
        if let Some(c) = commands.recv_timeout(Duration::from_millis(200)) {
            if c.left_rpm != 0.0 {
                break c;
            }
        }
    };
    // (1 ∓ 0.5 × 0.3 / 2) × 100, in f32.
    assert!((driven.left_rpm - 92.5).abs() < 1e-3, "{driven:?}");
    assert!((driven.right_rpm - 107.5).abs() < 1e-3, "{driven:?}");
    motor.interrupt();
    // Its shutdown zeroes the motors: the zero command reaches us before it leaves.
    let end = Instant::now() + WAIT;
    let zero = loop {
        let left = end.saturating_duration_since(Instant::now());
        match commands.recv_timeout(left) {
            Some(c) if c.left_rpm == 0.0 && c.right_rpm == 0.0 => break Some(c),
            Some(_) => continue,
            None => break None,
        }
    };
    assert!(zero.is_some(), "no zero command after Ctrl+C");
    let lines = motor.wait_success();
    assert!(
        lines.iter().any(|l| l.contains("Motors zeroed")),
        "{lines:#?}"
    );
}

#[test]
fn a_node_serves_and_calls_add_two_ints_from_tick() {
    let node = Running::start("add_two_ints_node", 184, &["--count", "2"], &[]);
    let lines = node.wait_success();
    assert!(
        lines
            .iter()
            .any(|l| l.contains("Result of add_two_ints: for 2 + 3 = 5")),
        "{lines:#?}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.contains("Result of add_two_ints: for 3 + 4 = 7")),
        "{lines:#?}"
    );
    assert!(lines.iter().any(|l| l.contains("Incoming request")));
}

#[test]
fn a_node_serves_and_sends_fibonacci_goals_from_tick() {
    let node = Running::start("fibonacci_node", 187, &["--count", "2"], &[]);
    let lines = node.wait_success();
    let results = lines
        .iter()
        .filter(|l| l.contains("Result: [0, 1, 1, 2, 3, 5] (Succeeded)"))
        .count();
    assert_eq!(results, 2, "{lines:#?}");
    assert!(
        lines.iter().any(|l| l.contains("Goal accepted :)")),
        "{lines:#?}"
    );
    assert!(
        lines.iter().any(|l| l.contains("Executing goal...")),
        "{lines:#?}"
    );
}

#[test]
fn malformed_ros_args_stop_the_program_with_rcls_message() {
    let out = Command::new(example("talker"))
        .args(["--ros-args", "-r", "foo:="])
        .env("ROS_DOMAIN_ID", "185")
        .output()
        .expect("run");
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "Couldn't parse remap rule: '-r foo:='. Error: Expected lexeme type 18, got 1 at index 5"
        ),
        "{stderr}"
    );
    let out = Command::new(example("talker"))
        .args(["--ros-args", "--custom-ros-arg"])
        .env("ROS_DOMAIN_ID", "185")
        .output()
        .expect("run");
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("found unknown ROS arguments: '--custom-ros-arg'"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// What ros2cli's `ros2 node info <full_name>` prints (ros2node `verb/info.py`): the name, then
/// six titled sections in this order, each entry `    <name>: <types>` and an empty section one
/// empty line (`print(*[], sep='\n')`). `sections` are Subscribers, Publishers, Service
/// Servers, Service Clients, Action Servers, Action Clients; each is sorted here by name, as
/// rcl's `*_names_and_types_by_node` return them.
fn ros2_node_info(full_name: &str, sections: [Vec<(String, &str)>; 6]) -> String {
    let titles = [
        "Subscribers",
        "Publishers",
        "Service Servers",
        "Service Clients",
        "Action Servers",
        "Action Clients",
    ];
    let mut out = format!("{full_name}\n");
    for (title, mut entries) in titles.into_iter().zip(sections) {
        entries.sort();
        out.push_str(&format!("  {title}:\n"));
        let lines: Vec<String> = entries
            .iter()
            .map(|(name, types)| format!("    {name}: {types}"))
            .collect();
        out.push_str(&lines.join("\n"));
        out.push('\n');
    }
    out
}

/// The services every rclcpp node offers under its name (here: NodeServices).
fn node_services(full_name: &str) -> Vec<(String, &'static str)> {
    [
        (
            "describe_parameters",
            "rcl_interfaces/srv/DescribeParameters",
        ),
        (
            "get_parameter_types",
            "rcl_interfaces/srv/GetParameterTypes",
        ),
        ("get_parameters", "rcl_interfaces/srv/GetParameters"),
        (
            "get_type_description",
            "type_description_interfaces/srv/GetTypeDescription",
        ),
        ("list_parameters", "rcl_interfaces/srv/ListParameters"),
        ("set_parameters", "rcl_interfaces/srv/SetParameters"),
        (
            "set_parameters_atomically",
            "rcl_interfaces/srv/SetParametersAtomically",
        ),
    ]
    .into_iter()
    .map(|(service, types)| (format!("{full_name}/{service}"), types))
    .collect()
}

/// The topics every rclcpp node publishes.
fn node_topics() -> Vec<(String, &'static str)> {
    vec![
        (
            "/parameter_events".to_owned(),
            "rcl_interfaces/msg/ParameterEvent",
        ),
        ("/rosout".to_owned(), "rcl_interfaces/msg/Log"),
    ]
}

/// `horus-ros node info <name>` on `domain`, discovering by itself (no daemon).
fn horus_ros_node_info(domain: u32, name: &str) -> String {
    let out = Command::new(cli())
        .args(["--no-daemon", "--spin-time", "20", "node", "info", name])
        .env("ROS_DOMAIN_ID", domain.to_string())
        .output()
        .expect("run horus-ros");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{}: {stderr}", out.status);
    assert!(!stderr.contains("WARNING"), "{stderr}");
    String::from_utf8(out.stdout).expect("UTF-8")
}

#[test]
fn horus_ros_node_info_lists_a_horus_node_as_ros2_node_info() {
    let domain = 186;
    let mut talker = Running::start("talker", domain, &[], &[("TALKER_RATE_HZ", "20")]);
    let mut adder = Running::start("add_two_ints_node", domain, &[], &[]);
    // Served and called: its server, its client and their node are all up.
    adder.expect_line("Result of add_two_ints");
    // The second message was sent after the first: /chatter is published.
    talker.expect_line("Publishing: 'Hello World: 2'");

    let mut publishers = node_topics();
    publishers.push(("/chatter".to_owned(), "std_msgs/msg/String"));
    let want = ros2_node_info(
        "/talker",
        [
            vec![],
            publishers,
            node_services("/talker"),
            vec![],
            vec![],
            vec![],
        ],
    );
    assert_eq!(horus_ros_node_info(domain, "/talker"), want);

    let add_two_ints = || {
        vec![(
            "/add_two_ints".to_owned(),
            "example_interfaces/srv/AddTwoInts",
        )]
    };
    let mut servers = node_services("/add_two_ints_node");
    servers.extend(add_two_ints());
    let want = ros2_node_info(
        "/add_two_ints_node",
        [
            vec![],
            node_topics(),
            servers,
            add_two_ints(),
            vec![],
            vec![],
        ],
    );
    assert_eq!(horus_ros_node_info(domain, "/add_two_ints_node"), want);

    for node in [talker, adder] {
        node.interrupt();
        node.wait_success();
    }
}

/// Runs an example that ends by itself, at most [`WAIT`] twice; its exit and all it printed.
fn run_to_end(name: &str, domain: u32) -> (bool, String) {
    let mut child = Command::new(example(name))
        .env("ROS_DOMAIN_ID", domain.to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("spawn {name}: {e}"));
    let out = horus_ros_test_support::wait_with_output(&mut child, 2 * WAIT)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (
        out.code() == Some(0),
        format!("{}{}", out.stdout, out.stderr),
    )
}

/// The services guide's complete example (seed 000), on `horus::prelude`.
#[test]
fn get_joint_limits_answers_and_reports_the_failed_joint() {
    let (ok, text) = run_to_end("get_joint_limits", 227);
    assert!(ok, "{text}");
    for line in [
        "Elbow limits: [0.00, 2.61] rad",
        "Gripper: the server said: Unknown joint: gripper",
    ] {
        assert!(text.contains(line), "no {line:?} in {text}");
    }
}

/// The services guide's `GetMapRegion` (seed 000), each way of calling it, stamped with
/// `horus::timestamp_now()`.
#[test]
fn get_map_region_shows_each_outcome() {
    let (ok, text) = run_to_end("get_map_region", 228);
    assert!(ok, "{text}");
    for line in [
        "Map: 200x200 pixels",
        "ServiceFailed after",
        "Resolution must be positive",
        "/archived_map: No server available",
        "served 3 requests, 3 failed",
    ] {
        assert!(text.contains(line), "no {line:?} in {text}");
    }
}
