//! The live graph both tools are run against: a Zenoh router (rmw_zenoh_cpp's own `rmw_zenohd`)
//! when the RMW is rmw_zenoh_cpp, the rclpy peer `peers/jazzy_live_graph.py`, ros2cli's daemon
//! and horus-ros's daemon, all on the RMW of the run; and the environment every process of the
//! run shares.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use horus_ros_test_support::jazzy::{self, Rmw};

use crate::common::{cli_peer_script, Streaming};

/// The run's DDS domain (and Zenoh's): no other test of this crate uses it.
pub const DOMAIN: u32 = 124;
/// The port of the run's own Zenoh router (rmw_zenoh_cpp only): a router on rmw_zenoh's default
/// port, if one runs, is left alone.
pub const ROUTER_PORT: u16 = 17620;
/// How long the peer, the router or a daemon may take to start.
pub const START: Duration = Duration::from_secs(60);
/// Seconds between the steps of the peer's action server (each is one feedback message).
pub const ACTION_STEP: &str = "0.05";

/// The two programs compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tool {
    /// `horus-ros`, on the backend `RMW_IMPLEMENTATION` chooses.
    Horus,
    /// ros2cli 0.32.2's `ros2`, on the RMW `RMW_IMPLEMENTATION` names.
    Ros2,
}

impl Tool {
    /// Its name, as typed.
    pub fn name(self) -> &'static str {
        match self {
            Tool::Horus => "horus-ros",
            Tool::Ros2 => "ros2",
        }
    }
}

/// `ZENOH_CONFIG_OVERRIDE` of a session of the run: it joins the run's router.
fn session_override() -> String {
    format!(r#"connect/endpoints=["tcp/127.0.0.1:{ROUTER_PORT}"]"#)
}

/// `program` in the real peers' environment (`target/jazzy-env/run`: ros2cli, rclpy and the
/// interface packages on `AMENT_PREFIX_PATH`), in the run's domain, on `rmw`. horus-ros runs in
/// the very same environment: its backend comes from `RMW_IMPLEMENTATION` as rcl's RMW does
/// (`HORUS_ROS_BACKEND`, which `scripts/test` sets per run, is removed), and it reads the same
/// interface files.
pub fn command(rmw: Rmw, program: &str) -> Command {
    let mut command = jazzy::command(program);
    command
        .env("ROS_DOMAIN_ID", DOMAIN.to_string())
        .env("RMW_IMPLEMENTATION", rmw.name())
        .env("HORUS_ROS_PEER_RMW", rmw.name())
        .env_remove("HORUS_ROS_BACKEND")
        .env_remove("RUST_LOG")
        .env_remove("ZENOH_ROUTER_CHECK_ATTEMPTS");
    if rmw == Rmw::Zenoh {
        // The router runs before anything else starts: every session waits for it
        // (rmw_zenoh's default looks once, and a session started on a loaded machine can miss
        // it and go on alone, with an empty graph).
        command
            .env("ZENOH_CONFIG_OVERRIDE", session_override())
            .env("ZENOH_ROUTER_CHECK_ATTEMPTS", "0");
    } else {
        command.env_remove("ZENOH_CONFIG_OVERRIDE");
    }
    command
}

/// The command line of `tool args…`.
pub fn tool_command(rmw: Rmw, tool: Tool, args: &[String]) -> Command {
    let mut command = match tool {
        Tool::Horus => command(rmw, env!("CARGO_BIN_EXE_horus-ros")),
        Tool::Ros2 => command(rmw, "ros2"),
    };
    command.args(args);
    command
}

/// [`tool_command`], `ros2` niced: the peer and horus-ros come first for the CPU. ros2cli's
/// runs of a batch start several at once beside one horus-ros run (see `BATCH`); on a loaded
/// 2-core machine they could otherwise keep the peer from answering horus-ros's discovery in
/// time.
pub fn batched_command(rmw: Rmw, tool: Tool, args: &[String]) -> Command {
    match tool {
        Tool::Horus => tool_command(rmw, tool, args),
        Tool::Ros2 => {
            let mut ros2 = command(rmw, "nice");
            ros2.args(["-n", "10", "ros2"]).args(args);
            ros2
        }
    }
}

/// Runs `tool args…` to its end (at most `limit`): stdout, stderr, exit code.
pub fn run(rmw: Rmw, tool: Tool, args: &[&str], limit: Duration) -> (String, String, Option<i32>) {
    let args: Vec<String> = args.iter().map(|a| (*a).to_owned()).collect();
    let mut child = tool_command(rmw, tool, &args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("start {}: {e}", tool.name()));
    let out = horus_ros_test_support::wait_with_output(&mut child, limit)
        .unwrap_or_else(|e| panic!("{}: {e}", tool.name()));
    let code = out.code();
    (out.stdout, out.stderr, code)
}

/// A process of the graph whose stdout is read line by line; stopped (SIGTERM, then waited for
/// at most 20 s, then killed) when dropped.
struct Process {
    name: &'static str,
    process: Streaming,
}

impl Process {
    fn spawn(name: &'static str, command: &mut Command) -> Self {
        let process = Streaming::spawn(command.stdin(Stdio::piped()).stderr(Stdio::inherit()))
            .unwrap_or_else(|e| panic!("start {name}: {e}"));
        Self { name, process }
    }

    /// Waits for a line that `wanted` accepts, at most `limit`; returns it.
    fn line_where(&self, limit: Duration, wanted: impl Fn(&str) -> bool) -> String {
        let deadline = Instant::now() + limit;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.process.next_line(left) {
                Some(line) if wanted(&line) => return line,
                Some(_) => {}
                None => panic!(
                    "{} did not print the awaited line within {limit:?}",
                    self.name
                ),
            }
        }
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        let child = self.process.child();
        if matches!(child.try_wait(), Ok(None)) {
            if let Ok(pid) = i32::try_from(child.id()) {
                let _ = nix::sys::signal::kill(
                    nix::unistd::Pid::from_raw(pid),
                    nix::sys::signal::Signal::SIGTERM,
                );
            }
            if !matches!(
                horus_ros_test_support::wait_exit(child, Duration::from_secs(20)),
                Ok(Some(_))
            ) {
                let _ = child.kill();
            }
        }
    }
}

/// Everything the comparisons run against; taken down in reverse order when dropped (the
/// daemons stopped with `daemon stop`, the peer by closing its stdin, the router by SIGTERM).
pub struct LiveGraph {
    /// The RMW of every process of the run.
    pub rmw: Rmw,
    peer: Option<Process>,
    router: Option<Process>,
    daemons: bool,
}

/// The nodes of `peers/jazzy_live_graph.py`, as `node list` prints them.
pub const NODES: [&str; 10] = [
    "/add_two_ints_client",
    "/add_two_ints_server",
    "/fibonacci_client",
    "/fibonacci_server",
    "/listener",
    "/param_node",
    "/py_managed",
    "/robot/imu_node",
    "/talker",
    "/strings_node",
];

impl LiveGraph {
    /// Starts the router (rmw_zenoh_cpp), the peer, both daemons, and waits until both tools
    /// see the peer's whole graph.
    pub fn start(rmw: Rmw) -> Self {
        let mut graph = Self {
            rmw,
            peer: None,
            router: None,
            daemons: false,
        };
        if rmw == Rmw::Zenoh {
            let mut router = command(rmw, "bash");
            router
                .args([
                    "-c",
                    r#"exec "$(ros2 pkg prefix rmw_zenoh_cpp)/lib/rmw_zenoh_cpp/rmw_zenohd""#,
                ])
                .env(
                    "ZENOH_CONFIG_OVERRIDE",
                    format!(r#"listen/endpoints=["tcp/127.0.0.1:{ROUTER_PORT}"]"#),
                );
            let router = Process::spawn("rmw_zenohd", &mut router);
            router.line_where(START, |l| l.starts_with("Started Zenoh router"));
            graph.router = Some(router);
        }
        let mut peer = command(rmw, &jazzy::python().to_string_lossy());
        peer.arg(cli_peer_script("jazzy_live_graph.py"))
            .arg(ACTION_STEP);
        let peer = Process::spawn("jazzy_live_graph.py", &mut peer);
        peer.line_where(START, |l| l.contains("\"ready\""));
        graph.peer = Some(peer);
        graph.daemons = true;
        let (out, err, code) = run(rmw, Tool::Ros2, &["daemon", "start"], START);
        assert_eq!(code, Some(0), "ros2 daemon start: {out}{err}");
        let (out, err, code) = run(rmw, Tool::Horus, &["daemon", "start"], START);
        assert_eq!(code, Some(0), "horus-ros daemon start: {out}{err}");
        for tool in [Tool::Ros2, Tool::Horus] {
            graph.wait_for_peer(tool);
        }
        graph
    }

    /// Waits (bounded) until `tool` lists every node, topic, service and action of the peer:
    /// a daemon's graph fills as discovery goes.
    fn wait_for_peer(&self, tool: Tool) {
        let services: Vec<String> = NODES
            .iter()
            .map(|n| format!("{n}/set_parameters"))
            .chain([
                "/add_two_ints".to_owned(),
                "/py_managed/get_state".to_owned(),
            ])
            .collect();
        let topics = [
            "/chatter",
            "/long",
            "/latched",
            "/best_effort",
            "/robot/imu",
            "/pub_target",
            "/strings",
            "/arrays",
            "/py_managed/transition_event",
        ];
        let checks: [(&[&str], Vec<&str>); 4] = [
            (&["node", "list"], NODES.to_vec()),
            (&["topic", "list"], topics.to_vec()),
            (
                &["service", "list"],
                services.iter().map(String::as_str).collect(),
            ),
            (&["action", "list"], vec!["/fibonacci"]),
        ];
        let deadline = Instant::now() + START;
        for (args, names) in checks {
            loop {
                let (out, err, _) = run(self.rmw, tool, args, START);
                let lines: Vec<&str> = out
                    .lines()
                    .map(|l| l.split(' ').next().unwrap_or(l))
                    .collect();
                let missing: Vec<&&str> = names.iter().filter(|n| !lines.contains(n)).collect();
                if missing.is_empty() {
                    break;
                }
                assert!(
                    Instant::now() < deadline,
                    "`{} {}` still misses {missing:?} after {START:?}:\n{out}{err}",
                    tool.name(),
                    args.join(" ")
                );
            }
        }
    }

    /// Sends one command to the peer (see `peers/jazzy_live_graph.py`) and waits for its
    /// reply; returns the reply's `done` value.
    pub fn peer_command(&mut self, command: &str) -> String {
        let peer = self.peer.as_mut().expect("the peer runs");
        {
            use std::io::Write;
            let stdin = peer
                .process
                .child()
                .stdin
                .as_mut()
                .expect("the peer's stdin");
            writeln!(stdin, "{command}")
                .and_then(|()| stdin.flush())
                .expect("write to the peer");
        }
        let line = peer.line_where(START, |l| l.contains("\"done\""));
        let reply: serde_json::Value = serde_json::from_str(&line).expect("a JSON reply");
        reply["done"].as_str().unwrap_or_default().to_owned()
    }
}

impl Drop for LiveGraph {
    fn drop(&mut self) {
        if self.daemons {
            for tool in [Tool::Ros2, Tool::Horus] {
                let _ = run(self.rmw, tool, &["daemon", "stop"], START);
            }
        }
        if let Some(mut peer) = self.peer.take() {
            // Its stdin closed: the peer destroys its nodes and leaves.
            drop(peer.process.child().stdin.take());
            let _ =
                horus_ros_test_support::wait_exit(peer.process.child(), Duration::from_secs(20));
        }
        self.router.take();
    }
}
