//! The example's binaries on a real graph (run the whole `cargo test` under `scripts/isolated`):
//!
//! - `telemetry_node` and `telemetry_monitor`, two horus-ros programs, exchange the example's own
//!   types (`horus_demo_msgs`, generated from `interfaces/`): the telemetry and SetMode answers
//!   arrive with the values sent, and a value over a bound is refused at encode with the typed
//!   `CdrError::BoundExceeded`, never a panic;
//! - an rclpy node (the Jazzy wheels, `tests/peers/jazzy_test_msgs.py`) hears the
//!   `test_msgs/msg/Arrays` that `test_msgs_node` publishes and calls its
//!   `test_msgs/srv/BasicTypes`, with generated test_msgs types on our side: what rclpy prints is
//!   what we sent. rclpy runs on the run's RMW (`HORUS_ROS_PEER_RMW`). On rmw_fastrtps its
//!   service client needs `related_sample_identity`, which only the rustdds backend carries; on
//!   the Cyclone backend the test then checks the refusal instead (rclpy gets no reply and our
//!   server no request), as interop-tests' `jazzy_services.rs` does. On rmw_cyclonedds it is
//!   answered on both backends.

use std::process::{Child, Command, Stdio};
use std::time::Duration;

use horus_ros_example_interfaces::horus_demo_msgs::msg::Telemetry;
use horus_ros_example_interfaces::horus_demo_msgs::srv::{SetModeRequest, SetModeResponse};
use horus_ros_example_interfaces::telemetry;
use horus_ros_msgs::cdr::{to_cdr, CdrError};
use horus_ros_msgs::runtime::{BoundError, BoundKind};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Context, PublishError, SampleError};
use serde_json::Value;

/// "Did not hang" bound for discovery, calls and exits on a loaded machine.
const WAIT: Duration = Duration::from_secs(60);

/// A binary of this crate, with `ROS_DOMAIN_ID` set, its output piped.
fn binary(name: &str, domain: u32, args: &[&str]) -> Child {
    let path = match name {
        "telemetry_node" => env!("CARGO_BIN_EXE_telemetry_node"),
        "telemetry_monitor" => env!("CARGO_BIN_EXE_telemetry_monitor"),
        _ => env!("CARGO_BIN_EXE_test_msgs_node"),
    };
    Command::new(path)
        .args(args)
        .env("ROS_DOMAIN_ID", domain.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("starting {path}: {e}"))
}

/// Waits for `child` (killed past [`WAIT`]); its exit code and output.
fn finish(mut child: Child) -> (Option<i32>, String, String) {
    let out = horus_ros_test_support::wait_with_output(&mut child, WAIT).expect("waiting");
    (out.code(), out.stdout, out.stderr)
}

/// Every JSON object printed (other lines are logs).
fn json_lines(stdout: &str) -> Vec<Value> {
    stdout
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect()
}

/// The values of the lines that have `key`.
fn all<'a>(lines: &'a [Value], key: &str) -> Vec<&'a Value> {
    lines.iter().filter_map(|l| l.get(key)).collect()
}

fn decode<T: horus_ros_msgs::serde::de::DeserializeOwned>(value: &Value) -> T {
    serde_json::from_value(value.clone()).unwrap_or_else(|e| panic!("{e}: {value}"))
}

#[test]
fn own_types_between_two_horus_programs() {
    const DOMAIN: u32 = 41;
    let node = binary(
        "telemetry_node",
        DOMAIN,
        &["--name", "robot7", "--cells", "3", "--serve", "2"],
    );
    let long_reason = "r".repeat(49);
    let monitor = binary(
        "telemetry_monitor",
        DOMAIN,
        &[
            "--count",
            "3",
            "--set",
            "1",
            "operator request",
            "--set",
            "42",
            "no such mode",
            "--set",
            "2",
            &long_reason,
        ],
    );
    let (code, stdout, stderr) = finish(monitor);
    let output = format!("--- monitor stdout:\n{stdout}\n--- stderr:\n{stderr}");
    assert_eq!(code, Some(0), "{output}");
    let lines = json_lines(&stdout);

    // Three telemetry messages, each the one the node made for its sequence number.
    let heard = all(&lines, "telemetry");
    assert_eq!(heard.len(), 3, "{output}");
    for value in heard {
        let t: Telemetry = decode(value);
        assert_eq!(t, telemetry("robot7", t.sequence, 3), "{output}");
        assert_eq!(t.mode, Telemetry::MODE_IDLE);
        assert_eq!(t.motors_enabled, [true, true], "the .msg default");
    }

    // SetMode: accepted, then refused (unknown mode), then not sent (over its bound).
    let answers = all(&lines, "set_mode");
    assert_eq!(answers.len(), 2, "{output}");
    let (request, response): (SetModeRequest, SetModeResponse) = (
        decode(&answers[0]["request"]),
        decode(&answers[0]["response"]),
    );
    assert_eq!(
        (request.mode, request.reason.as_str()),
        (SetModeRequest::MODE_ACTIVE, "operator request")
    );
    assert_eq!(
        response,
        SetModeResponse {
            accepted: true,
            previous_mode: SetModeRequest::MODE_IDLE,
            message: "idle -> active (operator request)".to_owned(),
        }
    );
    let after: Telemetry = decode(all(&lines, "telemetry_after")[0]);
    assert_eq!(
        after,
        Telemetry {
            mode: Telemetry::MODE_ACTIVE,
            ..telemetry("robot7", after.sequence, 3)
        }
    );
    let refused: SetModeResponse = decode(&answers[1]["response"]);
    assert_eq!(
        refused,
        SetModeResponse {
            accepted: false,
            previous_mode: SetModeRequest::MODE_ACTIVE,
            message: "no mode 42".to_owned(),
        }
    );
    let failed = all(&lines, "set_mode_failed");
    assert_eq!(failed.len(), 1, "{output}");
    assert_eq!(
        failed[0]["error"],
        "service transport error: serialization failed: field 'reason': string of 49 bytes exceeds \
         its bound of 48 bytes",
        "{output}"
    );

    // The node answered two requests (the third never left the monitor) and exited.
    let (code, stdout, stderr) = finish(node);
    assert_eq!(
        code,
        Some(0),
        "--- node stdout:\n{stdout}\n--- stderr:\n{stderr}"
    );
    assert_eq!(stdout.matches("SetMode: ").count(), 2, "{stdout}");
}

/// The bound that `value` exceeds, from its encoding's error.
fn refused(value: &impl horus_ros_msgs::serde::Serialize) -> BoundError {
    match to_cdr(value) {
        Err(CdrError::BoundExceeded(e)) => e,
        other => panic!("expected BoundExceeded, got {other:?}"),
    }
}

#[test]
fn a_value_over_a_bound_is_a_typed_error() {
    let bound = |field: &str, kind, bound, length| BoundError {
        field: field.to_owned(),
        kind,
        bound,
        length,
    };
    // Encoding alone.
    let request = SetModeRequest {
        mode: SetModeRequest::MODE_DOCKED,
        reason: "é".repeat(25),
    };
    assert_eq!(
        refused(&request),
        bound("reason", BoundKind::String, 48, 50)
    );
    assert_eq!(
        refused(&telemetry("robot7", 1, 9)),
        bound("cell_voltages", BoundKind::Sequence, 8, 9)
    );
    let warnings = Telemetry {
        warnings: vec!["ok".into(), "w".repeat(65)],
        ..Telemetry::default()
    };
    assert_eq!(
        refused(&warnings),
        bound("warnings[1]", BoundKind::String, 64, 65)
    );
    let name = Telemetry {
        robot_name: "n".repeat(33),
        ..Telemetry::default()
    };
    assert_eq!(
        refused(&name),
        bound("robot_name", BoundKind::String, 32, 33)
    );
    assert!(to_cdr(&telemetry("robot7", 1, 8)).is_ok());

    // A publisher: nothing is sent, the error is typed.
    let context = Context::builder().domain_id(42).build().expect("context");
    let node = context.create_node("bounds", "/").expect("node");
    let publisher = node
        .create_publisher::<Telemetry>("telemetry", &Qos::default_profile())
        .expect("publisher");
    match publisher.publish(telemetry("robot7", 1, 9)) {
        Err(PublishError {
            cause: SampleError::Cdr(CdrError::BoundExceeded(e)),
            ..
        }) => assert_eq!(
            (e.field.as_str(), e.bound, e.length),
            ("cell_voltages", 8, 9)
        ),
        other => panic!("expected BoundExceeded, got {other:?}"),
    }
    assert!(publisher.publish(telemetry("robot7", 1, 8)).is_ok());

    // The node's own handling of it: a message, status 3.
    let (code, _, stderr) = finish(binary("telemetry_node", 42, &["--cells", "9"]));
    assert_eq!(code, Some(3), "{stderr}");
    assert!(
        stderr.contains(
            "telemetry not published: field 'cell_voltages': sequence of 9 elements exceeds its \
             bound of 8 elements"
        ),
        "{stderr}"
    );
}

#[cfg(no_test_msgs)]
#[test]
fn rclpy_hears_and_calls_test_msgs_node() {
    panic!("{}", horus_ros_example_interfaces::NO_TEST_MSGS);
}

#[cfg(not(no_test_msgs))]
#[test]
fn rclpy_hears_and_calls_test_msgs_node() {
    use horus_ros_example_interfaces::test_msgs::msg::Arrays;
    use horus_ros_example_interfaces::test_msgs::srv::{BasicTypesRequest, BasicTypesResponse};
    use horus_ros_example_interfaces::{arrays, basic_types_request};
    use horus_ros_rmw::Backend;
    use serde_json::json;
    use std::path::PathBuf;

    const DOMAIN: u32 = 43;
    let backend = Backend::from_env_with(|k| std::env::var(k).ok()).expect("the backend");
    let refusing = !backend
        .capabilities()
        .is_some_and(|c| c.carries_sample_identity)
        && horus_ros_test_support::jazzy::Rmw::of_peers().needs_sample_identity();
    // Serving one request ends it; refused, it never gets one and is killed at the end.
    let node = binary("test_msgs_node", DOMAIN, &["--serve", "1"]);

    let request = basic_types_request();
    let spec = json!({
        "domain": DOMAIN,
        "topic": "/arrays", "topic_type": "test_msgs/msg/Arrays",
        "service": "/basic_types", "service_type": "test_msgs/srv/BasicTypes",
        "request": request, "wait_s": 40, "timeout_s": if refusing { 3 } else { 10 },
    });
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/jazzy_test_msgs.py");
    let peer = Command::new(horus_ros_test_support::jazzy::python())
        .arg(script)
        .arg(spec.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starting the rclpy peer (HORUS_ROS_INTEROP_PYTHON: the venv's python)");
    let (code, stdout, stderr) = finish(peer);
    let output = format!("--- rclpy stdout:\n{stdout}\n--- stderr:\n{stderr}");
    let lines = json_lines(&stdout);

    // rclpy heard an Arrays: the n-th one we published, field by field.
    let heard = all(&lines, "heard");
    assert_eq!(heard.len(), 1, "{output}");
    let got: Arrays = decode(heard[0]);
    let n = u64::try_from(got.alignment_check).expect("a publication number");
    assert_eq!(got, arrays(n), "{output}");

    if refusing {
        assert_eq!(code, Some(1), "{output}");
        assert_eq!(all(&lines, "no_reply").len(), 1, "{output}");
        let mut node = node;
        let _ = node.kill();
        let (_, stdout, _) = finish(node);
        assert!(all(&json_lines(&stdout), "served").is_empty(), "{stdout}");
        return;
    }
    assert_eq!(code, Some(0), "{output}");
    // Our server got rclpy's request as it was sent, and rclpy got it back.
    let (node_code, node_stdout, node_stderr) = finish(node);
    assert_eq!(node_code, Some(0), "{node_stdout}\n{node_stderr}");
    let served = json_lines(&node_stdout);
    let served = all(&served, "served");
    assert_eq!(served.len(), 1, "{node_stdout}");
    assert_eq!(decode::<BasicTypesRequest>(served[0]), request);
    let reply: BasicTypesResponse = decode(all(&lines, "reply")[0]);
    assert_eq!(
        serde_json::to_value(&reply).ok(),
        serde_json::to_value(&request).ok()
    );
}
