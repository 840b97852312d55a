//! `horus-ros topic echo` against real rclpy publishers (rmw_fastrtps_cpp, the suite's Jazzy
//! wheels): the text is compared with what ros2topic echo prints for the same message — the peer
//! computes it with rosidl_runtime_py's `message_to_yaml` / `message_to_csv` conversion (copied
//! into the peer) and PyYAML, as ros2cli does.
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

use serde_json::Value;
use topic_support::{jazzy_prefix, publisher, Ament, Cli};

/// Longest a `--once` / `--timeout` run may take (discovery and type look-up included).
const RUN: Duration = Duration::from_secs(60);

/// Runs `topic echo <args>` until it ends; its stdout and exit code.
fn echo(domain: u32, args: &[&str], ament: Ament<'_>) -> (String, Option<i32>) {
    let mut all = vec!["topic", "echo"];
    all.extend_from_slice(args);
    Cli::start(domain, &all, ament).finish(RUN)
}

fn yaml_of(peer: &common::Peer) -> String {
    peer.field("/yaml")
}

#[test]
fn echoes_std_msgs_string_as_ros2cli() {
    let domain = 210;
    let peer = publisher(
        domain,
        "talker",
        "/chatter",
        "std_msgs/msg/String",
        10.0,
        r#"[["data", "hello world"]]"#,
        false,
    );
    assert_eq!(yaml_of(&peer), "data: hello world\n");

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
    assert_eq!((out, code), (format!("{}\n", peer.field("/csv")), Some(0)));

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
}

#[test]
fn echoes_sensor_msgs_imu_as_ros2cli() {
    let domain = 211;
    let peer = publisher(
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
    assert_eq!((out, code), (format!("{}---\n", yaml_of(&peer)), Some(0)));

    let (out, code) = echo(domain, &["/imu", "--once", "--csv"], Ament::Inherit);
    assert_eq!((out, code), (format!("{}\n", peer.field("/csv")), Some(0)));

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

/// `test_msgs/msg/Strings`: not compiled in.
const STRINGS_YAML: &str = "string_value: ''
string_value_default1: Hello world!
string_value_default2: Hello'world!
string_value_default3: Hello\"world!
string_value_default4: Hello'world!
string_value_default5: Hello\"world!
bounded_string_value: ''
bounded_string_value_default1: Hello world!
bounded_string_value_default2: Hello'world!
bounded_string_value_default3: Hello\"world!
bounded_string_value_default4: Hello'world!
bounded_string_value_default5: Hello\"world!
";

#[test]
fn echoes_a_type_from_interface_files() {
    let domain = 212;
    let peer = publisher(
        domain,
        "strings",
        "/strings",
        "test_msgs/msg/Strings",
        10.0,
        "[]",
        false,
    );
    assert_eq!(yaml_of(&peer), STRINGS_YAML);
    let prefix = jazzy_prefix();
    let (out, code) = echo(domain, &["/strings", "--once"], Ament::Prefix(&prefix));
    assert_eq!((out, code), (format!("{STRINGS_YAML}---\n"), Some(0)));
}

#[test]
fn echoes_a_type_known_only_from_the_publishers_node() {
    let domain = 213;
    let peer = publisher(
        domain,
        "strings",
        "/strings",
        "test_msgs/msg/Strings",
        10.0,
        "[]",
        false,
    );
    if std::env::var("HORUS_ROS_BACKEND").as_deref() == Ok("cyclone") {
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
    assert_eq!((out, code), (format!("{}---\n", yaml_of(&peer)), Some(0)));
    let (out, code) = echo(domain, &["/strings", "--once", "--csv"], Ament::Unset);
    assert_eq!((out, code), (format!("{}\n", peer.field("/csv")), Some(0)));
}

#[test]
fn says_why_a_type_cannot_be_found() {
    let domain = 214;
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_horus-ros"))
        .args(["--domain-id", &domain.to_string(), "--no-daemon"])
        .args(["topic", "echo", "/nothing", "test_msgs/msg/Strings"])
        .env_remove("ROS_DOMAIN_ID")
        .env_remove("AMENT_PREFIX_PATH")
        .env("RUST_LOG", "error")
        .output()
        .expect("run horus-ros");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("test_msgs/msg/Strings") && stderr.contains("no node in the graph"),
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
