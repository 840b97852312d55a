//! Output tests of `service call` against independent Cyclone DDS servers (Python,
//! `interop-tests/peers/`): a type compiled into horus-ros-msgs
//! (`cyclone_add_two_ints_server.py`), and one known only through the serving node's
//! `~/get_type_description` (`cyclone_typed_server.py`, whose descriptions and RIHS01 hashes are
//! built in Python, independently of ours: the CLI checks that the description it gets hashes to
//! the hash it asked for). Whole stdout is compared with ros2cli's.
//!
//! Each test has its own DDS domain (121-129). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test service_call`.

mod common;

use std::process::{Command, Stdio};

use common::{
    cyclone_config, expect, expect_failure, horus, peer_script, python, Streaming, LINGER,
    PEER_START,
};

/// A peer server that logs a line per request: unlike `common::Peer`, its first line is not
/// JSON; its stdout is read until it exits (a closed pipe would kill it at its second line).
struct Peer {
    /// Held for its lifetime: the server runs until dropped.
    _process: Streaming,
}

impl Peer {
    /// Starts `script` with `args` and waits for its first line.
    fn start(script: &str, args: &[&str]) -> Self {
        let process = Streaming::spawn(
            Command::new(python())
                .arg(peer_script(script))
                .args(args)
                .env("CYCLONEDDS_URI", cyclone_config())
                .stderr(Stdio::inherit()),
        )
        .unwrap_or_else(|e| panic!("start {script}: {e}"));
        if process.next_line(PEER_START).is_none() {
            panic!("{script} printed nothing within {PEER_START:?}");
        }
        Self { _process: process }
    }
}

const ADD_REQUEST: &str = "requester: making request: \
                           example_interfaces.srv.AddTwoInts_Request(a=2, b=3)\n\n";
const ADD_RESPONSE: &str = "response:\nexample_interfaces.srv.AddTwoInts_Response(sum=5)\n\n";

#[test]
fn compiled_type_against_a_cyclone_server() {
    let _peer = Peer::start(
        "cyclone_add_two_ints_server.py",
        &["121", "/add_two_ints", LINGER],
    );
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

const DESCRIBE_VALUES: &str = "{label: it's, samples: [1.5, 2, -0.25], \
                               origin: {id: 7, x: 1.0, y: 2.5}, dims: [1, 2, 300], verbose: true}";

#[test]
fn unknown_type_described_by_the_servers_node() {
    let _peer = Peer::start("cyclone_typed_server.py", &["122", LINGER, "1"]);
    let args = [
        "service",
        "call",
        "/describe",
        "horus_test_msgs/srv/Describe",
        DESCRIBE_VALUES,
    ];
    let run = expect(
        122,
        &args,
        "requester: making request: horus_test_msgs.srv.Describe_Request(verbose=True, \
         samples=[1.5, 2.0, -0.25], label=\"it's\", origin=horus_test_msgs.msg.Point(id=7, \
         x=1.0, y=2.5), dims=array([  1,   2, 300], dtype=int16))\n\n\
         response:\nhorus_test_msgs.srv.Describe_Response(summary=\"it's: 3 samples \
         (verbose)\", total=3.25, points=[horus_test_msgs.msg.Point(id=7, x=1.0, y=2.5), \
         horus_test_msgs.msg.Point(id=8, x=4.25, y=2.5)], flags=array([3, 1], dtype=uint8), \
         ratio=0.10000000149011612)\n\n",
    );
    assert_eq!(run.code, Some(0));
    // Defaults for every field left out.
    expect(
        122,
        &[
            "service",
            "call",
            "/describe",
            "horus_test_msgs/srv/Describe",
        ],
        "requester: making request: horus_test_msgs.srv.Describe_Request(verbose=False, \
         samples=[], label='', origin=horus_test_msgs.msg.Point(id=0, x=0.0, y=0.0), \
         dims=array([0, 0, 0], dtype=int16))\n\n\
         response:\nhorus_test_msgs.srv.Describe_Response(summary=': 0 samples', total=0.0, \
         points=[horus_test_msgs.msg.Point(id=0, x=0.0, y=0.0), \
         horus_test_msgs.msg.Point(id=1, x=0.0, y=0.0)], flags=array([0, 0], dtype=uint8), \
         ratio=0.10000000149011612)\n\n",
    );
    // Values are checked against the fetched description.
    expect_failure(
        122,
        &[
            "service",
            "call",
            "/describe",
            "horus_test_msgs/srv/Describe",
            "{labl: x}",
        ],
        "Failed to populate field: 'Describe_Request' object has no attribute 'labl'\n",
    );
    expect_failure(
        122,
        &[
            "service",
            "call",
            "/describe",
            "horus_test_msgs/srv/Describe",
            "{dims: [1, 2]}",
        ],
        "Failed to populate field: The 'dims' field must be a set or sequence with length 3 \
         and each value of type 'int' and each integer in [-32768, 32767]\n",
    );
    expect_failure(
        122,
        &[
            "service",
            "call",
            "/describe",
            "horus_test_msgs/srv/Describe",
            "{origin: {id: 1.5}}",
        ],
        "Failed to populate field: The 'id' field must be of type 'int'\n",
    );
}

#[test]
fn unknown_type_without_a_hash_on_the_graph_fails_in_one_line() {
    // Without service introspection a Jazzy node shows no hash it can describe the type by.
    let _peer = Peer::start("cyclone_typed_server.py", &["123", LINGER, "0"]);
    expect_failure(
        123,
        &[
            "service",
            "call",
            "/describe",
            "horus_test_msgs/srv/Describe",
        ],
        "Cannot call /describe: type 'horus_test_msgs/srv/Describe' is not compiled in and \
         its server /typed_server does not describe it \
         (horus_test_msgs/srv/Describe_Request: Type not currently in use by this node; \
         horus_test_msgs/srv/Describe_Response: Type not currently in use by this node)\n",
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
    let _adder = Peer::start(
        "cyclone_add_two_ints_server.py",
        &["126", "/add_two_ints", LINGER],
    );
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
    let _typed = Peer::start("cyclone_typed_server.py", &["127", LINGER, "1"]);
    let run = horus(
        127,
        &["service", "bench", "/describe", "{label: x}", "-n", "10"],
    );
    assert_bench_report(
        &run,
        "service bench /describe (horus_test_msgs/srv/Describe): 10 calls, 1 client, 10 warm-up \
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
