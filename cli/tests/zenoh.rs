//! The zenoh backend against an independent peer: an rclpy node on rmw_zenoh_cpp 0.2.10 written
//! by hand with the eclipse-zenoh Python package (`tests/peers/zenoh_rclpy_talker.py`, to the
//! wire facts: tokens, keys, attachments), through our router (`horus-ros router`), and our own
//! publisher and subscription in two processes.
//!
//! Run inside the private network namespace: `scripts/isolated cargo test -p horus-ros-cli --test
//! zenoh`. The Python interpreter with `eclipse-zenoh` and `xxhash` is `HORUS_ROS_ZENOH_PYTHON`,
//! else `HORUS_ROS_INTEROP_PYTHON` (scripts/setup installs both packages there). Each test has
//! a router of its own on its own port, so they run in parallel. Waits are bounded and woken by
//! the processes' output (`graph --watch` lines, the peer's lines), never polled.

mod common;

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use serde_json::Value;

/// How long a process may take to print an expected line.
const LIMIT: Duration = Duration::from_secs(20);

/// The interpreter with eclipse-zenoh and xxhash.
fn python() -> PathBuf {
    std::env::var_os("HORUS_ROS_ZENOH_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(common::python)
}

/// `ZENOH_CONFIG_OVERRIDE` of a session that joins the router on `port`.
fn session_override(port: u16) -> String {
    format!(r#"connect/endpoints=["tcp/127.0.0.1:{port}"];listen/endpoints=["tcp/127.0.0.1:0"]"#)
}

/// A process whose stdout is read line by line; killed when dropped.
struct Proc {
    child: Child,
    lines: mpsc::Receiver<String>,
    name: String,
}

impl Proc {
    fn spawn(mut command: Command, name: &str) -> Self {
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap_or_else(|e| panic!("start {name}: {e}"));
        let stdout = child.stdout.take().expect("piped stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Self {
            child,
            lines: rx,
            name: name.to_owned(),
        }
    }

    /// Reads lines until one satisfies `want`, at most [`LIMIT`]; that line.
    fn line_where(&mut self, what: &str, mut want: impl FnMut(&str) -> bool) -> String {
        let deadline = Instant::now() + LIMIT;
        let mut seen = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) if want(&line) => return line,
                Ok(line) => seen.push(line),
                Err(_) => panic!(
                    "{}: no line {what} within {LIMIT:?}; it printed:\n{}",
                    self.name,
                    seen.join("\n")
                ),
            }
        }
    }

    /// Kills it now (SIGKILL: no goodbye, as a crash).
    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        self.kill();
    }
}

/// `horus-ros router` listening on `127.0.0.1:<port>`, once it printed its ready line.
fn router(port: u16) -> Proc {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command.arg("router").env(
        "ZENOH_CONFIG_OVERRIDE",
        format!(r#"listen/endpoints=["tcp/127.0.0.1:{port}"]"#),
    );
    let mut router = Proc::spawn(command, "horus-ros router");
    router.line_where("'Started Zenoh router'", |l| {
        l.starts_with("Started Zenoh router with id ")
    });
    router
}

/// `horus-ros --backend zenoh <args>` joining the router on `port`, not yet waited for.
fn horus_command(port: u16, domain: u32, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command
        .args(["--backend", "zenoh", "--no-daemon", "--domain-id"])
        .arg(domain.to_string())
        .args(args)
        .env_remove("ROS_DOMAIN_ID")
        .env("RUST_LOG", "error")
        .env("ZENOH_CONFIG_OVERRIDE", session_override(port));
    command
}

/// Runs `horus-ros --backend zenoh <args>` to its end; its stdout.
fn horus(port: u16, domain: u32, args: &[&str]) -> String {
    let mut child = horus_command(port, domain, args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start horus-ros");
    let out = horus_ros_test_support::wait_with_output(&mut child, LIMIT).expect("output");
    assert_eq!(
        out.code(),
        Some(0),
        "horus-ros {args:?}: stdout {} stderr {}",
        out.stdout,
        out.stderr
    );
    out.stdout
}

/// The peer, once it printed its tokens.
fn talker(port: u16, domain: u32) -> (Proc, Value) {
    let script =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/zenoh_rclpy_talker.py");
    let mut command = Command::new(python());
    command
        .arg(&script)
        .args([port.to_string(), domain.to_string(), "60".to_owned()]);
    let mut peer = Proc::spawn(command, "zenoh_rclpy_talker.py");
    let line = peer.line_where("of JSON", |l| l.starts_with('{'));
    let created: Value = serde_json::from_str(&line).expect("the peer's JSON line");
    (peer, created)
}

/// A GID as ros2cli prints it: dotted lower-case hex.
fn dotted(hex: &str) -> String {
    hex.as_bytes()
        .chunks(2)
        .map(|c| std::str::from_utf8(c).expect("hex"))
        .collect::<Vec<_>>()
        .join(".")
}

fn field<'a>(v: &'a Value, name: &str) -> &'a str {
    v[name]
        .as_str()
        .unwrap_or_else(|| panic!("no {name} in {v}"))
}

/// The peer's node, publisher and subscription are on our graph with the GIDs rmw_zenoh
/// computes; its samples reach our subscription; ours reach its subscriber with rmw_zenoh's
/// key and attachment; killed, it leaves the graph.
#[test]
fn an_rmw_zenoh_peer_through_our_router() {
    let (port, domain) = (17447, 0);
    let _router = router(port);
    let mut watch = Proc::spawn(
        horus_command(port, domain, &["graph", "--watch"]),
        "horus-ros graph --watch",
    );
    let (mut peer, created) = talker(port, domain);
    let pub_gid = dotted(field(&created, "pub_gid"));
    watch.line_where("'+ node /talker'", |l| l.ends_with("+ node /talker"));
    watch.line_where("'+ publisher /chatter … gid <the peer's>'", |l| {
        l.contains("+ publisher /chatter [std_msgs/msg/String]") && l.contains(&pub_gid)
    });

    // The graph verbs, unchanged on the zenoh backend.
    let nodes = horus(port, domain, &["node", "list"]);
    assert!(nodes.lines().any(|l| l == "/talker"), "{nodes}");
    let topics = horus(port, domain, &["topic", "list", "-t"]);
    assert!(
        topics
            .lines()
            .any(|l| l == "/chatter [std_msgs/msg/String]")
            && topics.lines().any(|l| l == "/back [std_msgs/msg/String]"),
        "{topics}"
    );
    let info = horus(port, domain, &["topic", "info", "-v", "/chatter"]);
    assert!(info.contains("Publisher count: 1"), "{info}");
    assert!(info.contains("Node name: talker"), "{info}");
    assert!(info.contains(&format!("GID: {pub_gid}")), "{info}");
    assert!(info.contains("History (Depth): KEEP_LAST (10)"), "{info}");
    let services = horus(port, domain, &["service", "list", "-t"]);
    assert!(
        services
            .lines()
            .any(|l| l == "/add_two_ints [example_interfaces/srv/AddTwoInts]"),
        "{services}"
    );
    let service = horus(port, domain, &["service", "info", "-v", "/add_two_ints"]);
    assert!(service.contains("Services count: 1"), "{service}");
    assert!(
        service.contains(&format!(
            " - Request Reader : {}",
            dotted(field(&created, "srv_gid"))
        )),
        "the server's request side has the GID rmw_zenoh computes: {service}"
    );
    let node_info = horus(port, domain, &["node", "info", "/talker"]);
    assert!(
        node_info.contains("/chatter: std_msgs/msg/String"),
        "{node_info}"
    );

    // Its samples reach our subscription.
    let echo = horus(port, domain, &["topic", "echo", "/chatter", "--once"]);
    assert!(echo.starts_with("data: 'Hello World: "), "{echo}");

    // Ours reach its subscriber, with rmw_zenoh's key, payload and attachment.
    let publisher = Proc::spawn(
        horus_command(
            port,
            domain,
            &[
                "topic",
                "pub",
                "-r",
                "10",
                "/back",
                "std_msgs/msg/String",
                "{data: from horus}",
            ],
        ),
        "horus-ros topic pub",
    );
    let line = peer.line_where("of a sample on /back", |l| l.contains("\"key\""));
    let sample: Value = serde_json::from_str(&line).expect("JSON");
    assert_eq!(
        field(&sample, "key"),
        "0/back/std_msgs::msg::dds_::String_/RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
    );
    assert_eq!(field(&sample, "data"), "from horus");
    assert!(
        field(&sample, "payload").starts_with("00010000"),
        "{sample}"
    );
    let attachment = field(&sample, "attachment");
    assert_eq!(attachment.len(), 66, "33 bytes: {sample}");
    assert_eq!(&attachment[32..34], "10", "the GID's length byte: {sample}");
    assert!(sample["seq"].as_i64().is_some_and(|s| s >= 1), "{sample}");
    assert_eq!(
        sample["gid_is_token_hash"],
        Value::Bool(true),
        "the attachment's GID is the XXH3-128 of our MP token: {sample}"
    );
    // Our MP token, chunk by chunk (rmw_zenoh's liveliness_utils.cpp layout).
    let tokens = sample["publisher_tokens"].as_array().expect("tokens");
    assert_eq!(tokens.len(), 1, "{sample}");
    let token = tokens[0].as_str().expect("a token");
    let chunks: Vec<&str> = token.split('/').collect();
    assert_eq!(chunks.len(), 13, "{token}");
    assert_eq!(&chunks[..2], ["@ros2_lv", "0"], "{token}");
    assert!(
        chunks[3].parse::<u64>().is_ok() && chunks[4].parse::<u64>().is_ok(),
        "{token}"
    );
    let node = format!("_horus_ros_{}", publisher.child.id());
    assert_eq!(
        &chunks[5..12],
        [
            "MP",
            "%",
            "%",
            node.as_str(),
            "%back",
            "std_msgs::msg::dds_::String_",
            "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
        ],
        "{token}"
    );

    // Killed (no goodbye): its tokens go, and the graph drops it.
    peer.kill();
    watch.line_where("'- node /talker'", |l| l.ends_with("- node /talker"));
    let nodes = horus(port, domain, &["node", "list"]);
    assert!(!nodes.lines().any(|l| l == "/talker"), "{nodes}");
}

/// Our own publisher and subscription, in two processes on the zenoh backend.
#[test]
fn our_pub_and_sub_across_two_processes() {
    let (port, domain) = (17448, 3);
    let _router = router(port);
    let mut publisher = Proc::spawn(
        horus_command(
            port,
            domain,
            &[
                "topic",
                "pub",
                "-r",
                "10",
                "/numbers",
                "std_msgs/msg/Int32",
                "{data: 42}",
            ],
        ),
        "horus-ros topic pub",
    );
    // Its token is declared before it publishes: a session opened from now on sees it.
    publisher.line_where("'publishing #1'", |l| l.starts_with("publishing #1:"));
    let echo = horus(port, domain, &["topic", "echo", "/numbers", "--once"]);
    assert_eq!(echo, "data: 42\n---\n");
}

/// The router stops on SIGINT and on SIGTERM, with status 0 (as rmw_zenohd on Ctrl+C).
#[test]
fn the_router_stops_on_sigint_and_sigterm() {
    use nix::sys::signal::{kill, Signal};
    use nix::unistd::Pid;
    for (port, signal) in [(17449, Signal::SIGINT), (17450, Signal::SIGTERM)] {
        let mut router = router(port);
        let pid = Pid::from_raw(i32::try_from(router.child.id()).expect("pid"));
        kill(pid, signal).expect("signal the router");
        let status = horus_ros_test_support::wait_exit(&mut router.child, LIMIT)
            .expect("wait")
            .unwrap_or_else(|| panic!("the router did not stop on {signal}"));
        assert!(status.success(), "{signal}: {status}");
    }
}
