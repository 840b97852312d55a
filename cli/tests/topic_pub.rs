//! `horus-ros topic pub | type | find` against real rclpy nodes (Jazzy, Fast DDS): what `topic
//! pub` sends is received by an rclpy subscription, and the peer's `repr()` of what it received
//! is what ros2cli's `publishing #N: %r` shows of the message it sends — so each printed line is
//! checked against rclpy's own text.
//!
//! Each test has its own DDS domain. Run inside the private network namespace
//! (`scripts/isolated`), on each backend (`HORUS_ROS_BACKEND`).

mod common;

use std::io::Write;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use common::{cli_peer_script, expect, expect_json, horus, jazzy_prefix, Peer, Run, Streaming};
use serde_json::{json, Value};

/// Python start-up and rclpy's first discovery on a loaded machine.
const RCLPY_START: Duration = Duration::from_secs(60);
/// How long a message may take to reach the peer.
const RECEIVE: Duration = Duration::from_secs(20);

/// An rclpy subscriber of `type_name` on `topic`.
fn subscriber(domain: u32, node: &str, topic: &str, type_name: &str) -> Peer {
    Peer::start_path(
        &cli_peer_script("jazzy_subscriber.py"),
        &[&domain.to_string(), node, topic, type_name, "120"],
        RCLPY_START,
    )
}

/// An rclpy publisher of `type_name` on `topic`.
fn publisher(domain: u32, node: &str, topic: &str, type_name: &str) -> Peer {
    Peer::start_path(
        &cli_peer_script("jazzy_publisher.py"),
        &[&domain.to_string(), node, topic, type_name, "120"],
        RCLPY_START,
    )
}

/// `horus-ros --domain-id <domain> topic pub <args…>`, started (not awaited), with
/// `AMENT_PREFIX_PATH` set to the Jazzy install, `stdin` written to its standard input.
fn start_pub(domain: u32, args: &[&str], stdin: Option<&str>) -> Child {
    start_pub_with(domain, args, stdin, true)
}

/// [`start_pub`], without any install when `installed` is false (`AMENT_PREFIX_PATH` unset).
fn start_pub_with(domain: u32, args: &[&str], stdin: Option<&str>, installed: bool) -> Child {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command
        .arg("--domain-id")
        .arg(domain.to_string())
        .args(["topic", "pub"])
        .args(args)
        .env_remove("ROS_DOMAIN_ID")
        .env_remove("AMENT_PREFIX_PATH");
    if installed {
        command.env("AMENT_PREFIX_PATH", jazzy_prefix());
    }
    let mut child = command
        .env("RUST_LOG", "error")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start horus-ros topic pub");
    let mut input = child.stdin.take().expect("piped stdin");
    if let Some(text) = stdin {
        input.write_all(text.as_bytes()).expect("write stdin");
    }
    drop(input);
    child
}

/// Waits for a started `topic pub` to end.
fn finish(mut child: Child) -> Run {
    finish_child(&mut child)
}

/// [`finish`], the child borrowed (what was taken of its output is not in the run).
fn finish_child(child: &mut Child) -> Run {
    let pid = child.id();
    let out = horus_ros_test_support::wait_with_output(child, common::RUN_LIMIT)
        .expect("horus-ros output");
    Run {
        code: out.code(),
        stdout: out.stdout,
        stderr: out.stderr,
        pid,
    }
}

/// A started `topic pub` whose stdout is read line by line as it is printed.
struct Waiting {
    process: Streaming,
    /// What it printed so far, each line with its newline.
    stdout: String,
}

impl Waiting {
    /// Reads `child`'s stdout until pub.py's `Waiting for at least N matching
    /// subscription(s)...` line (at most [`RECEIVE`]): it then waits for subscriptions.
    fn until_waiting(child: Child, wanted: u32) -> Self {
        let process = Streaming::from_child(child);
        let waiting = format!("Waiting for at least {wanted} matching subscription(s)...");
        let stdout = process.until(RECEIVE, |line| line == waiting);
        Self { process, stdout }
    }

    /// Waits for the `topic pub` to end; its whole stdout.
    fn finish(&mut self) -> Run {
        let mut run = finish_child(self.process.child());
        // The pipe closed with the process: the rest of the lines are there.
        let rest = self.process.rest(RECEIVE);
        run.stdout = std::mem::take(&mut self.stdout) + &rest;
        run
    }
}

/// `topic pub <args…>` run to its end.
fn run_pub(domain: u32, args: &[&str], stdin: Option<&str>) -> Run {
    finish(start_pub(domain, args, stdin))
}

/// The output without pub.py's `Waiting for at least N matching subscription(s)...` lines
/// (printed or not depending on how soon the subscription matched), and how many there were.
fn without_waiting(stdout: &str, wanted: u32) -> (String, usize) {
    let waiting = format!("Waiting for at least {wanted} matching subscription(s)...\n");
    let mut rest = stdout;
    let mut n = 0;
    while let Some(r) = rest.strip_prefix(&waiting) {
        rest = r;
        n += 1;
    }
    (rest.to_owned(), n)
}

/// The messages the peer received next: (repr, fields).
fn received(peer: &mut Peer, n: usize) -> Vec<(String, Value)> {
    peer.lines(n, RECEIVE)
        .iter()
        .map(|line| {
            let v: Value = serde_json::from_str(line).expect("peer JSON line");
            (
                v["repr"].as_str().expect("repr").to_owned(),
                v["message"].clone(),
            )
        })
        .collect()
}

/// What pub.py prints for messages whose reprs are `reprs`: the loop line, then each
/// `publishing #N: repr` followed by an empty line.
fn pub_output(reprs: &[(u64, &str)]) -> String {
    let mut out = "publisher: beginning loop\n".to_owned();
    for (n, repr) in reprs {
        out.push_str(&format!("publishing #{n}: {repr}\n\n"));
    }
    out
}

#[test]
fn pub_once_sends_a_string_to_an_rclpy_subscriber() {
    let domain = 171;
    let mut peer = subscriber(domain, "listener", "/chatter", "std_msgs/msg/String");
    let run = run_pub(
        domain,
        &["--once", "/chatter", "std_msgs/String", "{data: hi}"],
        None,
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let (rest, _) = without_waiting(&run.stdout, 1);
    let got = received(&mut peer, 1);
    assert_eq!(got[0].0, "std_msgs.msg.String(data='hi')");
    assert_eq!(got[0].1, json!({"data": "hi"}));
    assert_eq!(
        rest,
        pub_output(&[(1, &got[0].0)]),
        "stderr: {}",
        run.stderr
    );

    // The values from stdin, as `--stdin` reads them.
    let run = run_pub(
        domain,
        &["-1", "--stdin", "chatter", "std_msgs/msg/String"],
        Some("data: 'from stdin'\n"),
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let got = received(&mut peer, 1);
    assert_eq!(got[0].0, "std_msgs.msg.String(data='from stdin')");
    assert_eq!(
        without_waiting(&run.stdout, 1).0,
        pub_output(&[(1, &got[0].0)])
    );

    // --json: one line per message, the waiting line on stderr.
    let run = run_pub(
        domain,
        &[
            "--json",
            "-1",
            "/chatter",
            "std_msgs/msg/String",
            "{data: j}",
        ],
        None,
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    assert_eq!(received(&mut peer, 1)[0].1, json!({"data": "j"}));
    let line: Value = serde_json::from_str(&run.stdout).expect("one JSON line");
    assert_eq!(line, json!({"count": 1, "message": {"data": "j"}}));
}

#[test]
fn pub_times_sends_sensor_msgs_with_auto_headers() {
    let domain = 172;
    let mut peer = subscriber(
        domain,
        "thermo",
        "/temperature",
        "sensor_msgs/msg/Temperature",
    );
    let run = run_pub(
        domain,
        &[
            "--times",
            "3",
            "-r",
            "20",
            "/temperature",
            "sensor_msgs/msg/Temperature",
            "{header: auto, temperature: 21.5, variance: 0.25}",
        ],
        None,
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let got = received(&mut peer, 3);
    let (rest, _) = without_waiting(&run.stdout, 1);
    // The stamps ros2cli sets at each publication are the ones received.
    let expected: Vec<(u64, &str)> = (1..=3).zip(got.iter().map(|g| g.0.as_str())).collect();
    assert_eq!(rest, pub_output(&expected), "stderr: {}", run.stderr);
    for (_, fields) in &got {
        assert_eq!(fields["temperature"], json!(21.5));
        assert_eq!(fields["variance"], json!(0.25));
        assert_eq!(fields["header"]["frame_id"], json!(""));
        assert!(fields["header"]["stamp"]["sec"].as_i64().unwrap_or(0) > 1_600_000_000);
    }
    assert!(got[0].0.starts_with(
        "sensor_msgs.msg.Temperature(header=std_msgs.msg.Header(stamp=builtin_interfaces.msg.Time(sec="
    ));
}

#[test]
fn pub_sends_test_msgs_types_read_from_interface_files() {
    let domain = 173;
    let mut basic = subscriber(domain, "basic", "/basic", "test_msgs/msg/BasicTypes");
    let mut arrays = subscriber(domain, "arrays", "/arrays", "test_msgs/msg/Arrays");
    let run = run_pub(
        domain,
        &[
            "-1",
            "/basic",
            "test_msgs/msg/BasicTypes",
            "{bool_value: true, char_value: 65, float32_value: 1.5, float64_value: -2.25, \
             int8_value: -128, uint8_value: 255, int16_value: -300, uint16_value: 65535, \
             int32_value: -70000, uint32_value: 4294967295, int64_value: -9000000000, \
             uint64_value: 18446744073709551615}",
        ],
        None,
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let got = received(&mut basic, 1);
    assert_eq!(
        got[0].0,
        "test_msgs.msg.BasicTypes(bool_value=True, byte_value=b'\\x00', char_value=65, \
         float32_value=1.5, float64_value=-2.25, int8_value=-128, uint8_value=255, \
         int16_value=-300, uint16_value=65535, int32_value=-70000, uint32_value=4294967295, \
         int64_value=-9000000000, uint64_value=18446744073709551615)"
    );
    assert_eq!(
        without_waiting(&run.stdout, 1).0,
        pub_output(&[(1, &got[0].0)])
    );

    let run = run_pub(
        domain,
        &[
            "-1",
            "/arrays",
            "test_msgs/msg/Arrays",
            "{int32_values: [1, -2, 3], float64_values: [0.5, 1.0, 1e10], \
             string_values: [a, 'b c', ''], basic_types_values: [{}, {int8_value: 5}, {}]}",
        ],
        None,
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let got = received(&mut arrays, 1);
    assert_eq!(got[0].1["int32_values"], json!([1, -2, 3]));
    assert_eq!(got[0].1["string_values"], json!(["a", "b c", ""]));
    assert_eq!(got[0].1["basic_types_values"][1]["int8_value"], json!(5));
    // numpy's repr of the fixed arrays, Python's of the rest: as rclpy prints them.
    assert_eq!(
        without_waiting(&run.stdout, 1).0,
        pub_output(&[(1, &got[0].0)])
    );
}

#[test]
fn pub_waits_for_a_subscription_that_comes_later() {
    let domain = 174;
    // -t 4 waits for one subscription; -p 2 prints every second message.
    let child = start_pub(
        domain,
        &[
            "-t",
            "4",
            "-p",
            "2",
            "-r",
            "10",
            "/later",
            "std_msgs/msg/String",
            "data: late",
        ],
        None,
    );
    // Once it says it waits (pub.py's line, on stdout without --json), the subscriber starts.
    let mut waiting = Waiting::until_waiting(child, 1);
    let mut peer = subscriber(domain, "late_listener", "/later", "std_msgs/msg/String");
    let got = received(&mut peer, 4);
    let run = waiting.finish();
    assert_eq!(run.code, Some(0), "{run:?}");
    let (rest, waited) = without_waiting(&run.stdout, 1);
    assert!(waited >= 1, "{}", run.stdout);
    assert_eq!(rest, pub_output(&[(2, &got[1].0), (4, &got[3].0)]));
    assert!(got
        .iter()
        .all(|g| g.0 == "std_msgs.msg.String(data='late')"));
}

#[test]
fn pub_reports_what_ros2cli_reports() {
    let domain = 175;
    // Nobody subscribes: pub.py's wait, then its error (its spelling kept).
    let run = run_pub(
        domain,
        &[
            "-w",
            "1",
            "--max-wait-time-secs",
            "0.3",
            "/nobody",
            "std_msgs/msg/String",
        ],
        None,
    );
    assert_eq!(run.code, Some(1), "{run:?}");
    assert_eq!(
        run.stdout,
        "Waiting for at least 1 matching subscription(s)...\n"
    );
    assert_eq!(
        run.stderr,
        "Timed out waiting for subscribers: Expected 1 subcribers but only got 0 subscribers\n"
    );
    let failures: [(&[&str], &str); 5] = [
        (
            &["--max-wait-time-secs", "1", "/x", "std_msgs/msg/String"],
            "--max-wait-time-secs option is only effective with --wait-matching-subscriptions, \
             --once or --times\n",
        ),
        (
            &["-1", "/x", "std_msgs/msg/String", "[1, 2]"],
            "The passed value needs to be a dictionary in YAML format\n",
        ),
        (
            &["-1", "/x", "std_msgs/msg/String", "{nope: 1}"],
            "Failed to populate field: 'String' object has no attribute 'nope'\n",
        ),
        (
            &["-1", "/x", "std_srvs/srv/SetBool"],
            "The passed message type is invalid\n",
        ),
        (
            &["-1", "/x", "std_msgs/msg/Int8", "{data: 300}"],
            "Failed to populate field: The 'data' field must be an integer in [-128, 127]\n",
        ),
    ];
    for (args, stderr) in failures {
        let run = run_pub(domain, args, None);
        assert_eq!(
            (run.code, run.stdout.as_str(), run.stderr.as_str()),
            (Some(1), "", stderr),
            "{args:?}"
        );
    }
    // A type nobody has (not built in, not installed, no node uses it): ros2topic's words.
    let run = run_pub(domain, &["-1", "/x", "no_such_pkg/msg/Nothing"], None);
    assert_eq!(
        (run.code, run.stdout.as_str(), run.stderr.as_str()),
        (Some(1), "", "The passed message type is invalid\n"),
        "{run:?}"
    );
}

#[test]
fn type_and_find_read_rclpy_publishers() {
    let domain = 176;
    let _points = publisher(
        domain,
        "point_talker",
        "/points",
        "geometry_msgs/msg/PointStamped",
    );
    let _hidden = publisher(
        domain,
        "hidden_talker",
        "/_hidden_points",
        "geometry_msgs/msg/PointStamped",
    );
    let _chatter = publisher(domain, "talker", "/chatter", "std_msgs/msg/String");
    expect(
        domain,
        &["topic", "type", "/points"],
        "geometry_msgs/msg/PointStamped\n",
    );
    expect(
        domain,
        &[
            "topic",
            "type",
            "/_hidden_points",
            "--include-hidden-topics",
        ],
        "geometry_msgs/msg/PointStamped\n",
    );
    for topic in ["/_hidden_points", "/nothing"] {
        let run = horus(domain, &["topic", "type", topic]);
        assert_eq!(
            (run.code, run.stdout.as_str(), run.stderr.as_str()),
            (Some(1), "", ""),
            "{topic}"
        );
    }
    expect(
        domain,
        &["topic", "find", "geometry_msgs/msg/PointStamped"],
        "/points\n",
    );
    expect(
        domain,
        &[
            "topic",
            "find",
            "geometry_msgs/msg/PointStamped",
            "--include-hidden-topics",
        ],
        "/_hidden_points\n/points\n",
    );
    expect(
        domain,
        &["topic", "find", "-c", "geometry_msgs/msg/PointStamped"],
        "1\n",
    );
    expect(domain, &["topic", "find", "std_msgs/msg/Bool"], "");
    expect_json(domain, &["--json", "topic", "type", "/chatter"], |v| {
        *v == json!({"name": "/chatter", "types": ["std_msgs/msg/String"]})
    });
    expect_json(
        domain,
        &["--json", "topic", "find", "geometry_msgs/msg/PointStamped"],
        |v| *v == json!([{"name": "/points", "types": ["geometry_msgs/msg/PointStamped"]}]),
    );
    expect_json(
        domain,
        &["--json", "topic", "find", "-c", "std_msgs/msg/String"],
        |v| *v == json!({"count": 1}),
    );
}

#[test]
fn pub_learns_a_type_from_the_subscribers_node() {
    let domain = 177;
    let mut peer = subscriber(domain, "nested_listener", "/nested", "test_msgs/msg/Nested");
    // No install: test_msgs/msg/Nested is neither compiled in nor on AMENT_PREFIX_PATH; the
    // subscriber's node describes it (~/get_type_description).
    let run = finish(start_pub_with(
        domain,
        &[
            "-1",
            "/nested",
            "test_msgs/msg/Nested",
            "{basic_types_value: {int32_value: 7}}",
        ],
        None,
        false,
    ));
    if std::env::var("HORUS_ROS_BACKEND").as_deref() == Ok("cyclone") {
        // Cyclone cannot call a Fast DDS node's service (it cannot send
        // related_sample_identity): the error says so.
        assert_eq!(run.code, Some(1), "{run:?}");
        assert!(
            run.stderr.starts_with(
                "The passed message type is invalid: 'test_msgs/msg/Nested' is not built into \
                 horus-ros nor in a package on AMENT_PREFIX_PATH, and the graph does not describe \
                 it: "
            ),
            "{}",
            run.stderr
        );
        return;
    }
    assert_eq!(run.code, Some(0), "{run:?}");
    let got = received(&mut peer, 1);
    assert_eq!(got[0].1["basic_types_value"]["int32_value"], json!(7));
    assert_eq!(
        without_waiting(&run.stdout, 1).0,
        pub_output(&[(1, &got[0].0)])
    );
}
