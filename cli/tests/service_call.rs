//! Output tests of `service call` and `service bench` against real rmw_cyclonedds_cpp servers
//! (rclpy 7.1.6 on rmw_cyclonedds_cpp 2.2.2, whatever the run's peers use:
//! `interop-tests/peers/jazzy_node.py`): one of a type compiled into horus-ros-msgs
//! (example_interfaces/srv/AddTwoInts), and one of a type known only through the serving node's
//! `~/get_type_description` (test_msgs/srv/BasicTypes, which horus-ros does not compile in and
//! whose files are not on the tests' `AMENT_PREFIX_PATH`: the CLI checks that the description it
//! gets hashes to the hash it asked for). Whole stdout is compared with ros2cli's.
//!
//! Each test has its own DDS domain (121-129). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test service_call`.

mod common;

use common::{expect, expect_failure, horus, PEER_START};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use serde_json::json;

/// A real rmw_cyclonedds_cpp node `name` serving `service` of type `type_name` (with service
/// introspection when `introspection`: its `_service_event` publisher puts the type's event
/// hash on the graph); it leaves when dropped.
fn rclpy_server(
    domain: u32,
    name: &str,
    service: &str,
    type_name: &str,
    introspection: bool,
) -> RclpyPeer {
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({
            "domain": domain, "namespace": "/", "name": name,
            "servers": [{"service": service, "type": type_name,
                         "introspection": introspection}],
        }),
    )
    .expect("start the rclpy peer");
    peer.ready(PEER_START).expect("the rclpy server is up");
    peer
}

/// The AddTwoInts server on `/add_two_ints`.
fn adder(domain: u32) -> RclpyPeer {
    rclpy_server(
        domain,
        "add_two_ints_server",
        "/add_two_ints",
        "example_interfaces/srv/AddTwoInts",
        false,
    )
}

/// The test_msgs/srv/BasicTypes server on `/describe`, node `typed_server`.
fn typed_server(domain: u32, introspection: bool) -> RclpyPeer {
    rclpy_server(
        domain,
        "typed_server",
        "/describe",
        "test_msgs/srv/BasicTypes",
        introspection,
    )
}

const ADD_REQUEST: &str = "requester: making request: \
                           example_interfaces.srv.AddTwoInts_Request(a=2, b=3)\n\n";
const ADD_RESPONSE: &str = "response:\nexample_interfaces.srv.AddTwoInts_Response(sum=5)\n\n";

#[test]
fn compiled_type_against_an_rmw_cyclonedds_server() {
    let _peer = adder(121);
    let args = [
        "service",
        "call",
        "/add_two_ints",
        "example_interfaces/srv/AddTwoInts",
        "{a: 2, b: 3}",
    ];
    let run = expect(121, &args, &format!("{ADD_REQUEST}{ADD_RESPONSE}"));
    assert_eq!(run.code, Some(0));
    assert_eq!(run.stderr, "");
    // ros2cli's `pkg/Name` shorthand, block YAML, and -r (stopped by the hidden --count).
    let args = [
        "service",
        "call",
        "add_two_ints",
        "example_interfaces/AddTwoInts",
        "a: 2\nb: 3",
        "-r",
        "20",
        "--count",
        "3",
    ];
    expect(
        121,
        &args,
        &format!("{ADD_REQUEST}{ADD_RESPONSE}").repeat(3),
    );
}

const BASIC_VALUES: &str = "{string_value: it's, int16_value: -7, float32_value: 0.1, \
                            bool_value: true, uint64_value: 18446744073709551615}";

/// rclpy's text of a BasicTypes request or response (`kind`) with the fields of
/// [`BASIC_VALUES`], `float32` as written (`0.1` in a request made from YAML, its float32 value
/// once it has been on the wire).
fn basic_types(kind: &str, float32: &str) -> String {
    format!(
        "test_msgs.srv.BasicTypes_{kind}(bool_value=True, byte_value=b'\\x00', char_value=0, \
         float32_value={float32}, float64_value=0.0, int8_value=0, uint8_value=0, \
         int16_value=-7, uint16_value=0, int32_value=0, uint32_value=0, int64_value=0, \
         uint64_value=18446744073709551615, string_value=\"it's\")"
    )
}

/// rclpy's text of a BasicTypes request or response (`kind`) with every field's default.
fn basic_defaults(kind: &str) -> String {
    format!(
        "test_msgs.srv.BasicTypes_{kind}(bool_value=False, byte_value=b'\\x00', char_value=0, \
         float32_value=0.0, float64_value=0.0, int8_value=0, uint8_value=0, int16_value=0, \
         uint16_value=0, int32_value=0, uint32_value=0, int64_value=0, uint64_value=0, \
         string_value='')"
    )
}

#[test]
fn unknown_type_described_by_the_servers_node() {
    // With service introspection the server's node has the type's event publisher, whose type
    // hash is on the graph: the type is asked for by that hash.
    let _peer = typed_server(122, true);
    let args = [
        "service",
        "call",
        "/describe",
        "test_msgs/srv/BasicTypes",
        BASIC_VALUES,
    ];
    let run = expect(
        122,
        &args,
        &format!(
            "requester: making request: {}\n\nresponse:\n{}\n\n",
            basic_types("Request", "0.1"),
            basic_types("Response", "0.10000000149011612")
        ),
    );
    assert_eq!(run.code, Some(0));
    // Defaults for every field left out.
    expect(
        122,
        &["service", "call", "/describe", "test_msgs/srv/BasicTypes"],
        &format!(
            "requester: making request: {}\n\nresponse:\n{}\n\n",
            basic_defaults("Request"),
            basic_defaults("Response")
        ),
    );
    // Values are checked against the fetched description: an unknown field as ros2cli reports
    // it, a value out of its type's range as rclpy's field checks do (ros2cli with
    // `ROS_PYTHON_CHECK_FIELDS=1`; by default Jazzy's leave them off and send 300 as 44).
    expect_failure(
        122,
        &[
            "service",
            "call",
            "/describe",
            "test_msgs/srv/BasicTypes",
            "{string_valu: x}",
        ],
        "Failed to populate field: 'BasicTypes_Request' object has no attribute 'string_valu'\n",
    );
    expect_failure(
        122,
        &[
            "service",
            "call",
            "/describe",
            "test_msgs/srv/BasicTypes",
            "{int8_value: 300}",
        ],
        "Failed to populate field: The 'int8_value' field must be an integer in [-128, 127]\n",
    );
}

#[test]
fn unknown_type_without_a_hash_on_the_graph_fails_in_one_line() {
    // Without service introspection a Jazzy node shows no hash it can describe the type by:
    // its endpoints carry the request's and response's hashes, and rcl's type cache holds the
    // service type by the service's own hash, which is never on the wire.
    let _peer = typed_server(123, false);
    expect_failure(
        123,
        &["service", "call", "/describe", "test_msgs/srv/BasicTypes"],
        "Cannot call /describe: type 'test_msgs/srv/BasicTypes' is not compiled in and its \
         server /typed_server does not describe it (test_msgs/srv/BasicTypes_Request: Type not \
         currently in use by this node; test_msgs/srv/BasicTypes_Response: Type not currently \
         in use by this node)\n",
    );
}

#[test]
fn usage_errors_are_one_line_exit_1() {
    let call = |values: &str| {
        vec![
            "service".to_owned(),
            "call".to_owned(),
            "/add_two_ints".to_owned(),
            "example_interfaces/srv/AddTwoInts".to_owned(),
            values.to_owned(),
        ]
    };
    let fail = |args: Vec<String>, stderr: &str| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_failure(124, &args, stderr);
    };
    fail(
        call("{c: 1}"),
        "Failed to populate field: 'AddTwoInts_Request' object has no attribute 'c'\n",
    );
    fail(
        call("{a: x}"),
        "Failed to populate field: invalid literal for int() with base 10: 'x'\n",
    );
    fail(
        call("{a: 9223372036854775808}"),
        "Failed to populate field: The 'a' field must be an integer in \
         [-9223372036854775808, 9223372036854775807]\n",
    );
    fail(
        call("[1, 2]"),
        "Failed to populate field: Value '[1, 2]' is expected to be a dictionary but is a list\n",
    );
    let bad_yaml = call("{a: [1");
    let run = horus(
        124,
        &bad_yaml.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert_eq!(run.code, Some(1), "{run:?}");
    assert!(
        run.stderr.starts_with("Failed to parse values as YAML: ")
            && run.stderr.lines().count() == 1,
        "{run:?}"
    );
    expect_failure(
        124,
        &["service", "call", "/x", "std_msgs/msg/String"],
        "The passed type is not a service\n",
    );
    expect_failure(
        124,
        &[
            "service",
            "call",
            "/x",
            "std_srvs/srv/Empty",
            "{}",
            "-r",
            "0",
        ],
        "rate must be greater than zero\n",
    );
}

#[test]
fn no_server_gives_up_after_the_timeout() {
    let run = horus(
        125,
        &[
            "service",
            "call",
            "/add_two_ints",
            "example_interfaces/srv/AddTwoInts",
            "{a: 1}",
            "--timeout",
            "1",
        ],
    );
    assert_eq!(run.code, Some(1), "{run:?}");
    assert_eq!(run.stdout, "waiting for service to become available...\n");
    assert_eq!(
        run.stderr,
        "No server of /add_two_ints appeared within 1 s\n"
    );
}

/// `service bench` output: its four lines, with figures that are consistent.
fn assert_bench_report(run: &common::Run, header: &str) {
    assert_eq!(run.code, Some(0), "{run:?}");
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 4, "{run:?}");
    assert_eq!(lines[0], header, "{run:?}");
    assert!(lines[1].starts_with("round trip: p50 "), "{run:?}");
    assert!(lines[2].starts_with("throughput: "), "{run:?}");
    assert_eq!(lines[3], "failed:     0", "{run:?}");
}

#[test]
fn bench_measures_a_server_of_a_compiled_type_and_one_described_by_its_node() {
    let _adder = adder(126);
    // The type from the graph; two clients share the calls.
    let run = horus(
        126,
        &[
            "service",
            "bench",
            "/add_two_ints",
            "{a: 2, b: 3}",
            "-n",
            "40",
            "-c",
            "2",
        ],
    );
    assert_bench_report(
        &run,
        "service bench /add_two_ints (example_interfaces/srv/AddTwoInts): 40 calls, 2 clients, \
         10 warm-up calls each",
    );
    // JSON: every call measured, the quantiles in order.
    let run = horus(
        126,
        &[
            "--json",
            "service",
            "bench",
            "add_two_ints",
            "--type",
            "example_interfaces/AddTwoInts",
            "-n",
            "25",
            "--warmup",
            "0",
        ],
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let report: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON report");
    assert_eq!(report["succeeded"], 25, "{report}");
    assert_eq!(report["failed"], 0, "{report}");
    assert_eq!(
        report["type"], "example_interfaces/srv/AddTwoInts",
        "{report}"
    );
    let us = |k: &str| report[k].as_f64().unwrap_or(f64::NAN);
    assert!(
        0.0 < us("p50_us") && us("p50_us") <= us("p99_us") && us("p99_us") <= us("max_us"),
        "{report}"
    );
    // A type no build of ours knows, learnt from the serving node.
    let _typed = typed_server(127, true);
    let run = horus(
        127,
        &[
            "service",
            "bench",
            "/describe",
            "{string_value: x}",
            "-n",
            "10",
        ],
    );
    assert_bench_report(
        &run,
        "service bench /describe (test_msgs/srv/BasicTypes): 10 calls, 1 client, 10 warm-up \
         calls each",
    );
}

#[test]
fn bench_without_a_server_gives_up_after_the_timeout() {
    let run = horus(
        128,
        &["service", "bench", "/add_two_ints", "--timeout", "1"],
    );
    assert_eq!(run.code, Some(1), "{run:?}");
    assert_eq!(run.stdout, "");
    assert_eq!(
        run.stderr,
        "No server of /add_two_ints appeared within 1 s\n"
    );
}
