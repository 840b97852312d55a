//! Output tests of `interface list | packages | package | show | proto` against ros2cli 0.32
//! (jazzy): the expected texts are what ros2interface's own verb code (`verb/show.py`,
//! `api.interface_to_yaml`, …, with rosidl_runtime_py 0.13 and rosidl_adapter 4.6) prints over
//! the Jazzy wheels' install (the interop venv's `share/`, as `AMENT_PREFIX_PATH`), plus the
//! types compiled into horus-ros, and `--from-graph` against real rclpy nodes.
//!
//! The venv is found as the other tests find it (`HORUS_ROS_INTEROP_PYTHON`, else
//! `target/interop-venv`). The `--from-graph` tests join DDS domains 131-132: run inside the
//! private network namespace (`scripts/isolated cargo test -p horus-ros-cli --test interface`).

mod common;

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::{cli_peer_script, jazzy_prefix, Peer};

/// One run: stdout, stderr, exit code.
struct Out {
    stdout: String,
    stderr: String,
    code: Option<i32>,
}

/// Runs `horus-ros interface <args>` with `AMENT_PREFIX_PATH` set to `prefix` (unset: `None`).
fn interface(prefix: Option<&PathBuf>, args: &[&str]) -> Out {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command
        .arg("interface")
        .args(args)
        .env("RUST_LOG", "error")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    match prefix {
        Some(p) => command.env("AMENT_PREFIX_PATH", p),
        None => command.env_remove("AMENT_PREFIX_PATH"),
    };
    let mut child = command.spawn().expect("start horus-ros");
    let out = horus_ros_test_support::wait_with_output(&mut child, common::RUN_LIMIT)
        .expect("horus-ros output");
    Out {
        code: out.code(),
        stdout: out.stdout,
        stderr: out.stderr,
    }
}

/// Asserts `interface <args>` prints `expected` and exits 0.
fn expect(args: &[&str], expected: &str) {
    let out = interface(Some(&jazzy_prefix()), args);
    assert_eq!(
        (out.code, out.stdout.as_str()),
        (Some(0), expected),
        "`interface {}`; stderr: {}",
        args.join(" "),
        out.stderr
    );
}

/// Asserts `interface <args>` fails with exit 1 and `message` on stderr.
fn expect_failure(args: &[&str], message: &str) {
    let out = interface(Some(&jazzy_prefix()), args);
    assert_eq!(
        (out.code, out.stderr.as_str()),
        (Some(1), message),
        "`interface {}`",
        args.join(" ")
    );
}

const POSE_STAMPED_NO_COMMENTS: &str = "std_msgs/Header header\n\tbuiltin_interfaces/Time stamp\n\
    \t\tint32 sec\n\t\tuint32 nanosec\n\tstring frame_id\nPose pose\n\tPoint position\n\
    \t\tfloat64 x\n\t\tfloat64 y\n\t\tfloat64 z\n\tQuaternion orientation\n\t\tfloat64 x 0\n\
    \t\tfloat64 y 0\n\t\tfloat64 z 0\n\t\tfloat64 w 1\n";

#[test]
fn show_expands_nested_types_with_ros2clis_comments() {
    expect(
        &["show", "geometry_msgs/msg/PoseStamped"],
        &format!(
            "# A Pose with reference coordinate frame and timestamp\n\n{POSE_STAMPED_NO_COMMENTS}"
        ),
    );
    expect(
        &["show", "geometry_msgs/msg/PoseStamped", "--no-comments"],
        POSE_STAMPED_NO_COMMENTS,
    );
    expect(
        &["show", "geometry_msgs/msg/PoseStamped", "--all-comments"],
        "# A Pose with reference coordinate frame and timestamp\n\nstd_msgs/Header header\n\
         \t# Standard metadata for higher-level stamped data types.\n\
         \t# This is generally used to communicate timestamped data\n\
         \t# in a particular coordinate frame.\n\n\
         \t# Two-integer timestamp that is expressed as seconds and nanoseconds.\n\
         \tbuiltin_interfaces/Time stamp\n\
         \t\t# This message communicates ROS Time defined here:\n\
         \t\t# https://design.ros2.org/articles/clock_and_time.html\n\n\
         \t\t# The seconds component, valid over all int32 values.\n\t\tint32 sec\n\n\
         \t\t# The nanoseconds component, valid in the range [0, 1e9), to be added to the \
         seconds component.\n\t\t# e.g.\n\
         \t\t# The time -1.7 seconds is represented as {sec: -2, nanosec: 3e8}\n\
         \t\t# The time 1.7 seconds is represented as {sec: 1, nanosec: 7e8}\n\
         \t\tuint32 nanosec\n\n\t# Transform frame with which this data is associated.\n\
         \tstring frame_id\nPose pose\n\
         \t# A representation of pose in free space, composed of position and orientation.\n\n\
         \tPoint position\n\t\t# This contains the position of a point in free space\n\
         \t\tfloat64 x\n\t\tfloat64 y\n\t\tfloat64 z\n\tQuaternion orientation\n\
         \t\t# This represents an orientation in free space in quaternion form.\n\n\
         \t\tfloat64 x 0\n\t\tfloat64 y 0\n\t\tfloat64 z 0\n\t\tfloat64 w 1\n",
    );
    // ros2cli's cut of trailing comments (rosidl_adapter dedents the comment first) keeps the
    // `#`; indented comment lines and lone `#` lines are not comments to it.
    expect(
        &["show", "sensor_msgs/msg/Range", "--no-comments"],
        "#\nstd_msgs/Header header #\n\tbuiltin_interfaces/Time stamp\n\t\tint32 sec\n\
         \t\tuint32 nanosec\n\tstring frame_id\n                             # returned the \
         distance reading\nuint8 ULTRASOUND=0\nuint8 INFRARED=1\nuint8 radiation_type    #\n\
         \x20                       # (sound, IR, etc) [enum]\nfloat32 field_of_view   #\n\
         \x20                       # valid for [rad]\n\
         \x20                       # the object causing the range reading may have\n\
         \x20                       # been anywhere within -field_of_view/2 and\n\
         \x20                       # field_of_view/2 at the measured range.\n\
         \x20                       # 0 angle corresponds to the x-axis of the sensor.\n\
         float32 min_range       #\nfloat32 max_range       #\n\
         \x20                       # Fixed distance rangers require min_range==max_range\n\
         float32 range           #\n\
         \x20                       # (Note: values < range_min or > range_max should be \
         discarded)\n\
         \x20                       # Fixed distance rangers only output -Inf or +Inf.\n\
         \x20                       # -Inf represents a detection within fixed distance.\n\
         \x20                       # (Detection too close to the sensor to quantify)\n\
         \x20                       # +Inf represents no detection within the fixed distance.\n\
         \x20                       # (Object out of range)\nfloat32 variance        #\n\
         \x20                       # 0 is interpreted as variance unknown\n",
    );
    expect(
        &["show", "test_msgs/action/Fibonacci"],
        "#goal definition\nint32 order\n---\n#result definition\nint32[] sequence\n---\n\
         #feedback\nint32[] sequence\n",
    );
}

#[test]
fn compiled_types_show_their_fields_without_an_install() {
    let out = interface(None, &["show", "geometry_msgs/msg/PoseStamped"]);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert_eq!(
        out.stdout,
        "std_msgs/Header header\n\tbuiltin_interfaces/Time stamp\n\t\tint32 sec\n\
         \t\tuint32 nanosec\n\tstring frame_id\ngeometry_msgs/Pose pose\n\
         \tgeometry_msgs/Point position\n\t\tfloat64 x\n\t\tfloat64 y\n\t\tfloat64 z\n\
         \tgeometry_msgs/Quaternion orientation\n\t\tfloat64 x 0.0\n\t\tfloat64 y 0.0\n\
         \t\tfloat64 z 0.0\n\t\tfloat64 w 1.0\n"
    );
    // The defaults are those of the compiled descriptions, which are Jazzy's (`0.0`, `1.0`);
    // the files say `0` and `1`.
    // Not installed in the venv, compiled in: listed and shown.
    expect(
        &["show", "example_interfaces/srv/AddTwoInts"],
        "int64 a\nint64 b\n---\nint64 sum\n",
    );
    expect(
        &["package", "example_interfaces"],
        "example_interfaces/srv/AddTwoInts\n",
    );
    let out = interface(None, &["proto", "std_srvs/srv/SetBool"]);
    assert_eq!(
        (out.code, out.stdout.as_str()),
        (Some(0), "\"data: false\n\"\n")
    );
}

#[test]
fn proto_prints_a_default_message_as_message_to_yaml() {
    expect(
        &["proto", "test_msgs/msg/BasicTypes"],
        "\"bool_value: false\nbyte_value: \"\\0\"\nchar_value: 0\nfloat32_value: 0.0\n\
         float64_value: 0.0\nint8_value: 0\nuint8_value: 0\nint16_value: 0\nuint16_value: 0\n\
         int32_value: 0\nuint32_value: 0\nint64_value: 0\nuint64_value: 0\n\"\n",
    );
    expect(
        &["proto", "test_msgs/msg/Defaults", "--no-quotes"],
        "bool_value: true\nbyte_value: '2'\nchar_value: 100\nfloat32_value: 1.125\n\
         float64_value: 1.125\nint8_value: -50\nuint8_value: 200\nint16_value: -1000\n\
         uint16_value: 2000\nint32_value: -30000\nuint32_value: 60000\nint64_value: -40000000\n\
         uint64_value: 50000000\n\n",
    );
    expect(&["proto", "std_msgs/msg/Empty"], "\"{}\n\"\n");
    expect(&["proto", "test_msgs/action/Fibonacci"], "\"order: 0\n\"\n");
    expect(
        &["--json", "proto", "geometry_msgs/msg/Point"],
        "{\n  \"x\": 0.0,\n  \"y\": 0.0,\n  \"z\": 0.0\n}\n",
    );
}

#[test]
fn lists_are_ros2clis() {
    expect(
        &["list", "-a"],
        "Actions:\n    test_msgs/action/Fibonacci\n    test_msgs/action/NestedMessage\n",
    );
    expect(&["packages", "-a"], "test_msgs\n");
    // ros2cli prints a package's interfaces in hash order; sorted here, by kind as asked.
    expect(
        &["package", "test_msgs", "-s", "-a"],
        "test_msgs/srv/Arrays\ntest_msgs/srv/BasicTypes\ntest_msgs/srv/Empty\n\
         test_msgs/action/Fibonacci\ntest_msgs/action/NestedMessage\n",
    );
    let out = interface(Some(&jazzy_prefix()), &["list"]);
    assert!(out
        .stdout
        .starts_with("Messages:\n    action_msgs/msg/GoalInfo\n"));
    assert!(out
        .stdout
        .contains("\nServices:\n    action_msgs/srv/CancelGoal\n"));
    assert!(out
        .stdout
        .contains("    example_interfaces/srv/AddTwoInts\n"));
    assert!(out.stdout.ends_with(
        "\nActions:\n    test_msgs/action/Fibonacci\n    test_msgs/action/NestedMessage\n"
    ));
    let out = interface(Some(&jazzy_prefix()), &["--json", "list", "-s"]);
    let doc: serde_json::Value = serde_json::from_str(&out.stdout).expect("json");
    assert!(doc["services"]
        .as_array()
        .is_some_and(|s| s.iter().any(|t| t == "std_srvs/srv/SetBool")));
}

#[test]
fn unknown_types_and_packages_fail_as_ros2cli() {
    expect_failure(&["package", "nope"], "Unknown package 'nope'\n");
    expect_failure(&["show", "nope/msg/Nope"], "Unknown package 'nope'\n");
    expect_failure(
        &["show", "std_msgs/Nope"],
        "Invalid name 'std_msgs/Nope'. Expected three parts separated by '/'\n",
    );
    expect_failure(
        &["show", "std_msgs/msg/Nope"],
        &format!(
            "Could not find the interface '{}'\n",
            jazzy_prefix().join("share/std_msgs/msg/Nope.idl").display()
        ),
    );
    expect_failure(&["proto", "nope/msg/Nope"], "Unknown package 'nope'\n");
}

/// How long an rclpy peer may take to start.
const RCLPY_START: Duration = Duration::from_secs(60);

/// Runs `--domain-id <domain> --no-daemon interface <args>` without an install (the command
/// waits for the graph to be complete and for the node's service itself).
fn from_graph(domain: u32, args: &[&str]) -> Out {
    let mut all = vec![
        "--domain-id".to_owned(),
        domain.to_string(),
        "--no-daemon".to_owned(),
    ];
    all.push("interface".to_owned());
    all.extend(args.iter().map(|a| (*a).to_owned()));
    let mut child = Command::new(env!("CARGO_BIN_EXE_horus-ros"))
        .args(&all)
        .env_remove("AMENT_PREFIX_PATH")
        .env_remove("ROS_DOMAIN_ID")
        .env("RUST_LOG", "error")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start horus-ros");
    let out = horus_ros_test_support::wait_with_output(&mut child, common::RUN_LIMIT)
        .expect("horus-ros output");
    Out {
        code: out.code(),
        stdout: out.stdout,
        stderr: out.stderr,
    }
}

/// On the Cyclone backend, an rclpy (rmw_fastrtps) node's services cannot be called (the
/// request/reply convention rmw_cyclonedds cannot speak either): `--from-graph` says so.
fn refused_on_cyclone(out: &Out) -> bool {
    if std::env::var("HORUS_ROS_BACKEND").as_deref() != Ok("cyclone") {
        return false;
    }
    assert_eq!(
        (out.code, out.stdout.as_str()),
        (Some(1), ""),
        "{}",
        out.stderr
    );
    assert!(
        out.stderr
            .contains("whose service convention needs related_sample_identity"),
        "{}",
        out.stderr
    );
    true
}

#[test]
fn from_graph_reads_a_message_type_off_a_publishing_node() {
    let _peer = Peer::start_path(
        &cli_peer_script("jazzy_publisher.py"),
        &[
            "131",
            "point_talker",
            "/points",
            "geometry_msgs/msg/PointStamped",
            "120",
        ],
        RCLPY_START,
    );
    let out = from_graph(
        131,
        &["show", "geometry_msgs/msg/PointStamped", "--from-graph"],
    );
    if refused_on_cyclone(&out) {
        return;
    }
    assert_eq!(
        (out.code, out.stdout.as_str()),
        (
            Some(0),
            "std_msgs/Header header\n\tbuiltin_interfaces/Time stamp\n\t\tint32 sec\n\
             \t\tuint32 nanosec\n\tstring frame_id\ngeometry_msgs/Point point\n\tfloat64 x\n\
             \tfloat64 y\n\tfloat64 z\n"
        ),
        "stderr: {}",
        out.stderr
    );
    let out = from_graph(
        131,
        &["proto", "geometry_msgs/msg/PointStamped", "--from-graph"],
    );
    assert_eq!(
        (out.code, out.stdout.as_str()),
        (
            Some(0),
            "\"header:\n  stamp:\n    sec: 0\n    nanosec: 0\n  frame_id: ''\npoint:\n  x: 0.0\n\
             \x20 y: 0.0\n  z: 0.0\n\"\n"
        ),
        "stderr: {}",
        out.stderr
    );
}

/// A Jazzy node describes a service type by the service's hash only, which its endpoints do not
/// announce; with service introspection on, its `_service_event` publisher announces the
/// `_Event` type's hash, whose description holds the request and response.
#[test]
fn from_graph_reads_a_service_type_off_its_server() {
    let _peer = Peer::start_path(
        &cli_peer_script("jazzy_set_bool.py"),
        &[
            "132",
            "set_bool_server",
            "/set_bool",
            "120",
            "--introspection",
            "metadata",
        ],
        RCLPY_START,
    );
    let out = from_graph(132, &["show", "std_srvs/srv/SetBool", "--from-graph"]);
    if refused_on_cyclone(&out) {
        return;
    }
    assert_eq!(
        (out.code, out.stdout.as_str()),
        (Some(0), "bool data\n---\nbool success\nstring message\n"),
        "stderr: {}",
        out.stderr
    );
}
