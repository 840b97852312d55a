//! Tests of `param list|get|set|describe|dump|load|delete` beyond what ros2param prints: that
//! the output of every verb equals ros2param 0.32.2's (stdout, stderr, exit status) is checked
//! live, `ros2 param …` beside `horus-ros param …` on one rclpy node, on each RMW, by
//! `tests/cli_diff.rs` (`cli_diff/cases.rs`, `params`). Here: a dump loaded back gives
//! the parameters back (against a real rclpy node, `peers/jazzy_param_node.py`), the `--json`
//! documents, and the verbs against our own `NodeServices` node.
//!
//! Each test has its own DDS domain (165, 167, 168). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test param`.

mod common;

use common::{cli_peer_script, horus, Peer, Run, PEER_START};
use serde_json::Value;

const NODE: &str = "/param_node";
/// How long a peer stays up (the tests run many commands against one node).
const LINGER: &str = "300";

/// Starts the parameter node in `domain`.
fn peer(domain: u32, extra: &[&str]) -> Peer {
    let d = domain.to_string();
    let mut args = vec![d.as_str(), "param_node", LINGER];
    args.extend_from_slice(extra);
    Peer::start_path(
        &cli_peer_script("jazzy_param_node.py"),
        &args,
        PEER_START * 2,
    )
}

/// Runs `horus-ros param <args>` against the rclpy peer. A Fast DDS peer's services speak a
/// convention only the rustdds backend speaks (as rmw_cyclonedds, the Cyclone backend cannot
/// call it: `verbs_against_a_horus_ros_node` covers Cyclone), and rustdds speaks
/// rmw_cyclonedds' too, so these run the CLI on rustdds whatever HORUS_ROS_BACKEND says.
fn param(domain: u32, args: &[&str]) -> Run {
    let mut all = vec!["--backend", "rustdds", "param"];
    all.extend_from_slice(args);
    horus(domain, &all)
}

/// The test's temporary directory.
fn temp_dir() -> std::path::PathBuf {
    std::env::temp_dir().join(format!("horus_ros_param_{}", std::process::id()))
}

/// A file in the test's temporary directory.
fn temp_file(name: &str, text: &str) -> String {
    let dir = temp_dir();
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path.to_string_lossy().into_owned()
}

#[test]
fn dump_then_load_gives_the_parameters_back() {
    let _peer = peer(165, &[]);
    let original = param(165, &["dump", NODE]).stdout;
    assert!(
        original.starts_with("/param_node:\n  ros__parameters:\n"),
        "{original}"
    );
    // The dump, as a file (ros2cli's users redirect it: `ros2 param dump /n > n.yaml`).
    let file = temp_file("dump.yaml", &original);
    for (name, value) in [
        ("count", "20"),
        ("name", "changed"),
        ("numbers", "[9]"),
        ("words", "[q]"),
        ("nested.deeper.label", "y"),
        ("doubles", "[0.0]"),
    ] {
        let run = param(165, &["set", NODE, name, value]);
        assert_eq!(run.stdout, "Set parameter successful\n", "{}", run.stderr);
    }
    assert_ne!(param(165, &["dump", NODE]).stdout, original);
    // Loading the dump: one line per parameter (use_sim_time and the read-only one included).
    let load = param(165, &["load", NODE, &file]);
    assert!(
        load.stdout.contains("Set parameter count successful\n"),
        "{}",
        load.stdout
    );
    assert!(
        load.stderr.contains("Set parameter fixed failed"),
        "{}",
        load.stderr
    );
    // As with ros2param, one value does not come back: rclpy reads the dumped `1.0e-05` as a
    // float, then types `str([1.5, -2.0, 1e-05])` again, where PyYAML takes `1e-05` (no dot)
    // for a string: a mixed list, hence a string value, refused for a double array.
    assert!(
        load.stderr
            .contains("Set parameter doubles failed: Wrong parameter type"),
        "{}",
        load.stderr
    );
    let run = param(165, &["set", NODE, "doubles", "[1.5, -2.0, 1.0e-05]"]);
    assert_eq!(run.stdout, "Set parameter successful\n", "{}", run.stderr);
    assert_eq!(param(165, &["dump", NODE]).stdout, original);
    assert_eq!(
        param(165, &["get", NODE, "words"]).stdout,
        "String values are: ['a', 'b c', '5']\n"
    );
}

#[test]
fn json_documents() {
    let _peer = peer(167, &[]);
    let json = |args: &[&str]| -> Value {
        let mut all = vec!["--json"];
        all.extend_from_slice(args);
        let run = param(167, &all);
        assert_eq!(run.code, Some(0), "{run:?}");
        serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{e}: {}", run.stdout))
    };
    let got = json(&["get", NODE, "doubles"]);
    assert_eq!(
        got,
        serde_json::json!({"node": NODE, "name": "doubles", "type": "double array",
                           "value": [1.5, -2.0, 1e-05]})
    );
    let dump = json(&["dump", NODE]);
    assert_eq!(
        dump[NODE]["ros__parameters"]["nested"]["deeper"]["label"],
        "x"
    );
    assert_eq!(
        dump[NODE]["ros__parameters"]["flags"],
        serde_json::json!([true, false])
    );
    let list = json(&["list", NODE, "--param-type"]);
    assert_eq!(list[0]["node"], NODE);
    assert!(list[0]["parameters"]
        .as_array()
        .is_some_and(|p| p.contains(&serde_json::json!({"name": "count", "type": "integer"}))));
    let set = json(&["set", NODE, "count", "7"]);
    assert_eq!(set["successful"], false);
    let described = json(&["describe", NODE, "count"]);
    assert_eq!(described[0]["integer_range"][0]["step"], 5);
}

/// A horus-ros node of the test process serving its parameters (`NodeServices`), on whichever
/// backend HORUS_ROS_BACKEND names: the verbs against our own nodes (and on Cyclone DDS, which
/// cannot call the Fast DDS rclpy peer).
#[test]
fn verbs_against_a_horus_ros_node() {
    use horus_ros_msgs::rcl_interfaces::msg::{IntegerRange, ParameterDescriptor, ParameterValue};
    use horus_ros_services::{NodeServices, ParameterValueExt};

    let context = horus_ros_rmw::Context::builder()
        .domain_id(168)
        .build()
        .expect("context");
    let node = context.create_node("horus_params", "/").expect("node");
    let services = NodeServices::start(&node).expect("node services");
    let declare = |name: &str, value: ParameterValue, descriptor: ParameterDescriptor| {
        services
            .declare_parameter(name, value, descriptor)
            .expect("declare");
    };
    declare(
        "speed",
        ParameterValue::from_integer(4),
        ParameterDescriptor {
            integer_range: vec![IntegerRange {
                from_value: 0,
                to_value: 10,
                step: 2,
            }],
            ..Default::default()
        },
    );
    declare(
        "mode",
        ParameterValue::from_string("auto"),
        Default::default(),
    );
    declare(
        "gains",
        ParameterValue::from_double_array(vec![0.5, 1.5]),
        Default::default(),
    );
    declare("a.b", ParameterValue::from_bool(true), Default::default());
    let n = "/horus_params";
    let run = param(168, &["list", n]);
    assert_eq!(
        run.stdout,
        "  a.b\n  gains\n  mode\n  speed\n  start_type_description_service\n  use_sim_time\n",
        "{}",
        run.stderr
    );
    let run = param(168, &["set", n, "speed", "5"]);
    assert_eq!(
        (run.stdout.as_str(), run.stderr.as_str()),
        (
            "",
            "Setting parameter failed: Parameter {speed} doesn't comply with integer range.\n"
        )
    );
    let run = param(168, &["set", n, "speed", "6"]);
    assert_eq!(run.stdout, "Set parameter successful\n", "{}", run.stderr);
    assert_eq!(
        param(168, &["get", n, "speed"]).stdout,
        "Integer value is: 6\n"
    );
    let dump = param(168, &["dump", n]).stdout;
    assert_eq!(
        dump,
        "/horus_params:\n  ros__parameters:\n    a:\n      b: true\n    gains:\n    - 0.5\n    \
         - 1.5\n    mode: auto\n    speed: 6\n    start_type_description_service: true\n    \
         use_sim_time: false\n\n"
    );
    let file = temp_file("horus_params.yaml", &dump);
    let run = param(168, &["set", n, "mode", "manual"]);
    assert_eq!(run.stdout, "Set parameter successful\n", "{}", run.stderr);
    let run = param(168, &["load", n, &file]);
    assert!(
        run.stdout.contains("Set parameter mode successful\n"),
        "{run:?}"
    );
    assert_eq!(param(168, &["dump", n]).stdout, dump);
    let run = param(168, &["delete", n, "mode"]);
    assert!(
        run.stderr.starts_with("Deleting parameter failed"),
        "{run:?}"
    );
}
