//! `horus-ros topic echo` against real rclpy publishers (on the peers' RMW,
//! `HORUS_ROS_PEER_RMW`): the text is compared, live, with what ros2cli 0.32.2's `ros2 topic
//! echo` prints for the same publisher (`ros2_echo`); the options' edge cases are compared the
//! same way on one graph by `tests/cli_diff.rs`.
//!
//! Types: compiled in (std_msgs, sensor_msgs), from interface files on `AMENT_PREFIX_PATH`
//! (test_msgs from the venv's `share/`), and known only from the publisher's node
//! (`AMENT_PREFIX_PATH` unset: its `~/get_type_description`).
//!
//! Joins DDS domains 210-216: run inside the private network namespace
//! (`scripts/isolated cargo test -p horus-ros-cli --test topic_echo`), on each backend
//! (`HORUS_ROS_BACKEND`).

mod common;
mod topic_support;

use std::time::Duration;

use common::jazzy_prefix;
use serde_json::Value;
use topic_support::{publisher, Ament, Cli};

/// Longest a `--once` / `--timeout` run may take (discovery and type look-up included).
const RUN: Duration = Duration::from_secs(60);

/// Runs `topic echo <args>` until it ends; its stdout and exit code.
fn echo(domain: u32, args: &[&str], ament: Ament<'_>) -> (String, Option<i32>) {
    let mut all = vec!["topic", "echo"];
    all.extend_from_slice(args);
    Cli::start(domain, &all, ament).finish(RUN)
}

/// What ros2cli prints for the same publisher: `ros2 topic echo <topic> <type> --once
/// --no-daemon --no-lost-messages <args>`, run live in the peers' environment, on their RMW and
/// in their domain. The type is given, so that ros2cli's node (which looks for a fixed 0.5 s)
/// need not have discovered the publisher to know it; a report of messages sent before its
/// reader matched depends on timing and is left out. Its stdout; it must succeed.
fn ros2_echo(domain: u32, topic: &str, type_name: &str, args: &[&str]) -> String {
    let mut command = horus_ros_test_support::jazzy::command("ros2");
    command
        .args(["topic", "echo", topic, type_name])
        .args(["--once", "--no-daemon", "--no-lost-messages"])
        .args(args)
        .env("ROS_DOMAIN_ID", domain.to_string())
        .env("CYCLONEDDS_URI", common::cyclone_config())
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped());
    let mut child = command.spawn().expect("start ros2");
    let out = horus_ros_test_support::wait_with_output(&mut child, RUN).expect("ros2's output");
    assert_eq!(out.code(), Some(0), "ros2 topic echo: {}", out.stderr);
    out.stdout
}

#[test]
fn echoes_std_msgs_string_as_ros2cli() {
    let domain = 210;
    let _peer = publisher(
        domain,
        "talker",
        "/chatter",
        "std_msgs/msg/String",
        10.0,
        r#"[["data", "hello world"]]"#,
        false,
    );
    let yaml = ros2_echo(domain, "/chatter", "std_msgs/msg/String", &[]);
    assert_eq!(yaml, "data: hello world\n---\n");

    let (out, code) = echo(domain, &["/chatter", "--once"], Ament::Inherit);
    assert_eq!((out.as_str(), code), ("data: hello world\n---\n", Some(0)));

    // The type as given, in its short form.
    let (out, code) = echo(
        domain,
        &["chatter", "std_msgs/String", "--once"],
        Ament::Inherit,
    );
    assert_eq!((out.as_str(), code), ("data: hello world\n---\n", Some(0)));

    let (out, code) = echo(domain, &["/chatter", "--once", "--csv"], Ament::Inherit);
    assert_eq!(
        (out, code),
        (
            ros2_echo(domain, "/chatter", "std_msgs/msg/String", &["--csv"]),
            Some(0)
        )
    );

    let (out, code) = echo(
        domain,
        &["/chatter", "--once", "--field", "data"],
        Ament::Inherit,
    );
    assert_eq!((out.as_str(), code), ("hello world\n---\n", Some(0)));

    let (out, code) = echo(domain, &["--json", "/chatter", "--once"], Ament::Inherit);
    assert_eq!(code, Some(0));
    let j: Value = serde_json::from_str(out.trim()).expect("one JSON line");
    assert_eq!(j, serde_json::json!({ "data": "hello world" }));

    let (out, code) = echo(
        domain,
        &[
            "/chatter",
            "--once",
            "--filter",
            "m.data == 'hello world' and len(m.data) > 3",
        ],
        Ament::Inherit,
    );
    assert_eq!((out.as_str(), code), ("data: hello world\n---\n", Some(0)));

    // A filter that nothing passes: nothing printed until the timeout, then exit 0.
    let (out, code) = echo(
        domain,
        &[
            "/chatter",
            "--filter",
            "m.data != 'hello world'",
            "--timeout",
            "3",
        ],
        Ament::Inherit,
    );
    assert_eq!((out.as_str(), code), ("", Some(0)));

    let (out, code) = echo(domain, &["/chatter", "--once", "--raw"], Ament::Inherit);
    // CDR_LE header, length 12, "hello world\0", padding to 4.
    assert_eq!(
        (out.as_str(), code),
        (
            "b'\\x00\\x01\\x00\\x00\\x0c\\x00\\x00\\x00hello world\\x00'\n---\n",
            Some(0)
        )
    );

    let (out, code) = echo(
        domain,
        &["/chatter", "--once", "--include-message-info"],
        Ament::Inherit,
    );
    assert_eq!(code, Some(0));
    let keys: Vec<&str> = out
        .lines()
        .take(4)
        .map(|l| l.split(':').next().unwrap_or_default())
        .collect();
    assert_eq!(
        keys,
        [
            "publication_sequence_number",
            "received_timestamp",
            "reception_sequence_number",
            "source_timestamp"
        ],
        "{out}"
    );
    assert!(out.ends_with("---\ndata: hello world\n---\n"), "{out}");
    // Fast DDS stamps each sample: the writer's source timestamp, not rmw's 0 for none.
    let source: i64 = out
        .lines()
        .find_map(|l| l.strip_prefix("source_timestamp: "))
        .and_then(|v| v.parse().ok())
        .expect("a source timestamp");
    assert!(source > 0, "{out}");
}

#[test]
fn echoes_sensor_msgs_imu_as_ros2cli() {
    let domain = 211;
    let _peer = publisher(
        domain,
        "imu",
        "/imu",
        "sensor_msgs/msg/Imu",
        10.0,
        r#"[["header.frame_id", "imu_link"], ["orientation.w", 1.0],
            ["orientation_covariance.0", 0.5], ["linear_acceleration.z", 9.81]]"#,
        false,
    );
    let (out, code) = echo(domain, &["/imu", "--once"], Ament::Inherit);
    assert_eq!(
        (out, code),
        (
            ros2_echo(domain, "/imu", "sensor_msgs/msg/Imu", &[]),
            Some(0)
        )
    );

    let (out, code) = echo(domain, &["/imu", "--once", "--csv"], Ament::Inherit);
    assert_eq!(
        (out, code),
        (
            ros2_echo(domain, "/imu", "sensor_msgs/msg/Imu", &["--csv"]),
            Some(0)
        )
    );

    let (out, code) = echo(
        domain,
        &["/imu", "--once", "--field", "orientation"],
        Ament::Inherit,
    );
    assert_eq!(
        (out.as_str(), code),
        ("x: 0.0\ny: 0.0\nz: 0.0\nw: 1.0\n---\n", Some(0))
    );

    let (out, code) = echo(
        domain,
        &["/imu", "--once", "--field", "header.frame_id"],
        Ament::Inherit,
    );
    assert_eq!((out.as_str(), code), ("imu_link\n---\n", Some(0)));

    let (out, code) = echo(
        domain,
        &[
            "/imu",
            "--once",
            "--no-arr",
            "--field",
            "linear_acceleration",
        ],
        Ament::Inherit,
    );
    assert_eq!(
        (out.as_str(), code),
        ("x: 0.0\ny: 0.0\nz: 9.81\n---\n", Some(0))
    );

    let (out, code) = echo(
        domain,
        &[
            "--json",
            "/imu",
            "--once",
            "--field",
            "orientation_covariance",
        ],
        Ament::Inherit,
    );
    assert_eq!(code, Some(0));
    let j: Value = serde_json::from_str(out.trim()).expect("one JSON line");
    assert_eq!(j[0], 0.5);
    assert_eq!(j.as_array().map(Vec::len), Some(9));

    // An unknown field: ros2cli's AttributeError text.
    let (out, code) = echo(
        domain,
        &["/imu", "--once", "--field", "orientation.v"],
        Ament::Inherit,
    );
    assert_ne!(code, Some(0), "{out}");
}

#[test]
fn echoes_a_type_from_interface_files() {
    let domain = 212;
    // `test_msgs/msg/Strings`: not compiled in.
    let _peer = publisher(
        domain,
        "strings",
        "/strings",
        "test_msgs/msg/Strings",
        10.0,
        "[]",
        false,
    );
    let prefix = jazzy_prefix();
    let (out, code) = echo(domain, &["/strings", "--once"], Ament::Prefix(&prefix));
    assert_eq!(
        (out, code),
        (
            ros2_echo(domain, "/strings", "test_msgs/msg/Strings", &[]),
            Some(0)
        )
    );
}

#[test]
fn echoes_a_type_known_only_from_the_publishers_node() {
    let domain = 213;
    let _peer = publisher(
        domain,
        "strings",
        "/strings",
        "test_msgs/msg/Strings",
        10.0,
        "[]",
        false,
    );
    if std::env::var("HORUS_ROS_BACKEND").as_deref() == Ok("cyclone")
        && horus_ros_test_support::jazzy::Rmw::of_peers()
            == horus_ros_test_support::jazzy::Rmw::FastRtps
    {
        // A Fast DDS node's services speak a request/reply convention the Cyclone backend (and
        // rmw_cyclonedds) cannot: the error names the node asked and says so.
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_horus-ros"))
            .args(["--domain-id", &domain.to_string(), "--no-daemon"])
            .args(["topic", "echo", "/strings", "--once"])
            .env_remove("ROS_DOMAIN_ID")
            .env_remove("AMENT_PREFIX_PATH")
            .env("RUST_LOG", "error")
            .output()
            .expect("run horus-ros");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains("/strings/get_type_description")
                && stderr.contains("whose service convention needs related_sample_identity"),
            "{stderr}"
        );
        return;
    }
    let (out, code) = echo(domain, &["/strings", "--once"], Ament::Unset);
    assert_eq!(
        (out, code),
        (
            ros2_echo(domain, "/strings", "test_msgs/msg/Strings", &[]),
            Some(0)
        )
    );
    let (out, code) = echo(domain, &["/strings", "--once", "--csv"], Ament::Unset);
    assert_eq!(
        (out, code),
        (
            ros2_echo(domain, "/strings", "test_msgs/msg/Strings", &["--csv"]),
            Some(0)
        )
    );
}

#[test]
fn says_why_a_type_cannot_be_found() {
    let domain = 214;
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_horus-ros"))
        .args(["--domain-id", &domain.to_string(), "--no-daemon"])
        .args(["topic", "echo", "/nothing", "test_msgs/msg/Strings"])
        .env_remove("ROS_DOMAIN_ID")
        .env_remove("AMENT_PREFIX_PATH")
        .env("RUST_LOG", "horus_ros=debug")
        .output()
        .expect("run horus-ros");
    // ros2cli's error for a type it cannot import; why, at debug level.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        (out.status.code(), stderr.lines().last()),
        (Some(1), Some("The passed message type is invalid")),
        "{stderr}"
    );
    assert!(
        stderr.contains("test_msgs/msg/Strings") && stderr.contains("no node uses it"),
        "{stderr}"
    );

    // No type given and no such topic: ros2cli's warning and error.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_horus-ros"))
        .args(["--domain-id", &domain.to_string(), "--no-daemon"])
        .args(["topic", "echo", "/nothing"])
        .env_remove("ROS_DOMAIN_ID")
        .env("RUST_LOG", "error")
        .output()
        .expect("run horus-ros");
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "WARNING: topic [/nothing] does not appear to be published yet\n"
    );
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("Could not determine the type for the passed topic"));
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn timeout_ends_a_quiet_echo() {
    let (out, code) = echo(
        215,
        &["/quiet", "std_msgs/msg/String", "--timeout", "1"],
        Ament::Inherit,
    );
    assert_eq!((out.as_str(), code), ("", Some(0)));
}

/// A new writer of `/lost` (std_msgs/msg/String) on `node`, a RustDDS node whatever the CLI's
/// backend: it can address a sample to a single reader, which the others are sent a GAP for
/// instead. Reliable and TRANSIENT_LOCAL, so that a TRANSIENT_LOCAL reader gets every sample
/// however late its side of the match comes (a VOLATILE reader takes only what is written after
/// it has matched the writer, which the test cannot observe).
fn lost_writer(node: &horus_ros_rmw::Node) -> horus_ros_rmw::RawWriter {
    use horus_ros_msgs::message::Message;
    use horus_ros_msgs::std_msgs::msg::String as StringMsg;
    let spec = horus_ros_rmw::RawEndpointSpec {
        dds_topic_name: "rt/lost".to_owned(),
        dds_type_name: StringMsg::dds_type_name(),
        type_hash: StringMsg::type_hash(),
        qos: horus_ros_rmw::qos::Qos::default().transient_local(),
        service_id: None,
    };
    node.create_raw_writer(&spec).expect("writer")
}

/// A std_msgs/msg/String CDR body.
fn string_body(s: &str) -> Vec<u8> {
    let mut b = u32::try_from(s.len() + 1)
        .expect("short")
        .to_le_bytes()
        .to_vec();
    b.extend_from_slice(s.as_bytes());
    b.push(0);
    b
}

/// Samples a writer skipped over reach the echo as a sequence-number gap: reported before the
/// next message as ros2topic echo's `_message_lost_event_callback` prints it, unless
/// `--no-lost-messages`; the message info carries the writer's source timestamp and the sample's
/// sequence number. Deterministic: the writer's second sample is addressed to another reader,
/// so the echo is sent a GAP for it, never the sample. On the Cyclone backend the sequence
/// numbers are not known: no loss is reported and the number is `null`.
#[test]
fn reports_lost_messages_and_message_info() {
    let domain = 216;
    let context = horus_ros_rmw::Context::builder()
        .domain_id(domain)
        .backend(horus_ros_rmw::backend::Backend::RustDds)
        .build()
        .expect("context");
    let node = context.create_node("lossy", "/").expect("node");
    let mut feed = context.discovery_feed().expect("feed");
    let mut echoes = std::collections::HashSet::new();
    let cyclone = std::env::var("HORUS_ROS_BACKEND").is_ok_and(|b| b == "cyclone");
    for (json, no_lost) in [(false, false), (true, false), (false, true)] {
        let mut args = vec![
            "topic",
            "echo",
            "/lost",
            "std_msgs/msg/String",
            "-i",
            "--qos-reliability",
            "reliable",
            "--qos-durability",
            "transient_local",
        ];
        if json {
            args.insert(0, "--json");
        }
        if no_lost {
            args.push("--no-lost-messages");
        }
        // A writer of its own per run: a TRANSIENT_LOCAL reader gets the writer's whole history.
        let writer = lost_writer(&node);
        let cli = Cli::start(domain, &args, Ament::Inherit);
        // The writer addresses "two" away from the readers it has matched: wait for the echo's.
        let deadline = std::time::Instant::now() + RUN;
        loop {
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            assert!(!left.is_zero(), "the writer did not match the echo in time");
            if let Some(horus_ros_rmw::DiscoveryEvent::Matched { local, remote }) =
                feed.next_timeout(left)
            {
                // This run's echo, not the reader of an earlier one that is going away.
                if local == writer.gid() && echoes.insert(remote) {
                    break;
                }
            }
        }
        let before = horus_ros_rmw::unix_time_ns();
        let first = writer.write(string_body("one"), None, None).expect("write");
        let elsewhere = horus_ros_rmw::Gid::from_bytes([0xaa; 16]);
        writer
            .write(string_body("two"), None, Some(elsewhere))
            .expect("write");
        let third = writer
            .write(string_body("three"), None, None)
            .expect("write");
        let mut out = Vec::new();
        while !out.iter().any(|l: &String| l.contains("three")) {
            out.push(cli.line());
        }
        let after = horus_ros_rmw::unix_time_ns();
        let text = out.join("\n");
        assert!(!text.contains("two"), "{text}");
        // Each message: its info (YAML, or the JSON line's `message_info`).
        let infos: Vec<Value> = if json {
            out.iter()
                .filter_map(|l| serde_json::from_str::<Value>(l).ok())
                .filter_map(|j| j.get("message_info").cloned())
                .collect()
        } else {
            out.split(|l| l == "---")
                .filter(|block| block.iter().any(|l| l.starts_with("source_timestamp: ")))
                .map(|block| {
                    let map: serde_json::Map<String, Value> = block
                        .iter()
                        .filter_map(|l| l.split_once(": "))
                        .map(|(k, v)| {
                            let v = serde_json::from_str(v).unwrap_or(Value::Null);
                            (k.to_owned(), v)
                        })
                        .collect();
                    Value::Object(map)
                })
                .collect()
        };
        assert_eq!(infos.len(), 2, "{text}");
        for (info, sent) in infos.iter().zip([first, third]) {
            let source = info["source_timestamp"].as_i64().expect("source_timestamp");
            let received = info["received_timestamp"]
                .as_i64()
                .expect("received_timestamp");
            assert!(
                before <= source && source <= received && received <= after,
                "{text}"
            );
            assert_eq!(info["reception_sequence_number"], Value::Null, "{text}");
            let number = if cyclone {
                Value::Null
            } else {
                sent.sequence_number.into()
            };
            assert_eq!(info["publication_sequence_number"], number, "{text}");
        }
        let reported: Vec<usize> = (0..out.len())
            .filter(|&i| out[i].contains("lost") || out[i].starts_with('\t'))
            .collect();
        if cyclone || no_lost {
            assert_eq!(reported, Vec::<usize>::new(), "{text}");
            continue;
        }
        let at = *reported.first().expect("a loss reported");
        if json {
            assert_eq!(reported.len(), 1, "{text}");
            let j: Value = serde_json::from_str(&out[at]).expect("a JSON line");
            assert_eq!(
                j,
                serde_json::json!({"message_lost": {"total_count_change": 1, "total_count": 1}}),
                "{text}"
            );
        } else {
            assert_eq!(
                out[at..at + 3].join("\n"),
                "A message was lost!!!\n\ttotal count change:1\n\ttotal count: 1---",
                "{text}"
            );
            assert_eq!(reported, [at, at + 1, at + 2], "{text}");
        }
        // Between the message before the gap and the one after it.
        let one = out.iter().position(|l| l.contains("one")).expect("one");
        assert!(one < at, "{text}");
    }
}
