//! Output tests of `param list|get|set|describe|dump|load|delete` against a real rclpy node
//! (`peers/jazzy_param_node.py`, Fast DDS). ros2cli is not installed: each output is compared
//! whole (stdout, stderr, exit status) with a checked-in transcript,
//! `tests/expected/param/<test>.txt`, recorded once from ros2param 0.32.2's verb bodies run on
//! rclpy (the suite's Jazzy wheels: values typed by rclpy's `get_parameter_value`, files read
//! by rclpy's `parameter_dict_from_yaml_file`, dumps written by PyYAML) against the same node,
//! and reviewed against ros2param 0.32.2 (ros2/ros2cli tag 0.32.2), whose lines define each
//! format:
//!
//! - `list`: `ros2param/verb/list.py` 96-112 (`{node}:` when no node is given, `  {name}` or
//!   `  {name} (type: …)`; types from `api/__init__.py` `get_parameter_type_string` 116-133);
//! - `get`: `verb/get.py` 60-105 (`Parameter not set` on stderr, exit 1; the labels
//!   `Integer value is:` … and `print(label, value)` or `print(value)` with `--hide-type`);
//! - `set` / `delete`: `verb/set.py` / `verb/delete.py` 65-78 (`Set parameter successful` /
//!   `Deleted parameter successfully` on stdout, `Setting parameter failed` / `Deleting
//!   parameter failed` with `: {reason}` on stderr, exit 0 either way);
//! - `describe`: `verb/describe.py` 60-79;
//! - `dump`: `verb/dump.py` 95-106 (`yaml.dump(…, default_flow_style=False)` printed, hence the
//!   empty last line);
//! - `load`: `api/__init__.py` `load_parameter_file` 35-58 (`Set parameter {name} successful`
//!   on stdout, `… failed` with the reason on stderr, in the file's order).
//!
//! Each test has its own DDS domain (161-163, 165-168). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test param`.

mod common;

use common::expected::Transcript;
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

/// Runs `horus-ros param <args>` against the rclpy peer. The peer runs on Fast DDS, whose
/// service convention only the rustdds backend speaks (a Cyclone DDS context is refused by
/// Fast DDS servers, as rmw_cyclonedds is: `verbs_against_a_horus_ros_node` covers Cyclone),
/// so these comparisons run the CLI on rustdds whatever HORUS_ROS_BACKEND says.
fn param(domain: u32, args: &[&str]) -> Run {
    let mut all = vec!["--backend", "rustdds", "param"];
    all.extend_from_slice(args);
    horus(domain, &all)
}

/// Asserts `horus-ros param <args>` prints what ros2param prints: the transcript's next case
/// (stdout, stderr and exit status); returns our run.
fn same_as_ros2param(expected: &mut Transcript, domain: u32, args: &[&str]) -> Run {
    let run = param(domain, args);
    // The test's files as `$TMP/<name>`.
    let dir = temp_dir().to_string_lossy().into_owned();
    let shown: Vec<String> = args.iter().map(|a| a.replace(&dir, "$TMP")).collect();
    let mut all = vec!["param"];
    all.extend(shown.iter().map(String::as_str));
    expected.check(&all, &run);
    run
}

#[test]
fn list_get_describe_and_dump_match_ros2param() {
    let mut expected = Transcript::load("param/list_get_describe_and_dump_match_ros2param.txt");
    let _peer = peer(161, &[]);
    for args in [
        vec!["list", NODE],
        vec!["list", "param_node", "--param-type"],
        vec!["list", NODE, "--filter", "n"],
        vec!["list", NODE, "--filter", ".*s$", "--param-type"],
        vec!["list", NODE, "--param-prefixes", "nested", "ratio"],
        vec![
            "describe",
            NODE,
            "count",
            "ratio",
            "fixed",
            "name",
            "dynamic",
            "nested.depth",
        ],
        vec!["describe", NODE, "count", "nope"],
        vec!["dump", NODE],
    ] {
        same_as_ros2param(&mut expected, 161, &args);
    }
    for name in [
        "flag",
        "count",
        "ratio",
        "name",
        "quoted",
        "flags",
        "numbers",
        "doubles",
        "words",
        "nested.depth",
        "nested.deeper.label",
        "fixed",
        "use_sim_time",
        "nope",
    ] {
        same_as_ros2param(&mut expected, 161, &["get", NODE, name]);
    }
    for name in ["words", "doubles", "flag"] {
        same_as_ros2param(&mut expected, 161, &["get", NODE, name, "--hide-type"]);
    }
    // Without a node: every node's parameters under its name (only the peer is not hidden).
    same_as_ros2param(&mut expected, 161, &["list"]);
    // An unknown node.
    let run = horus(161, &["param", "get", "/nobody", "x"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (Some(1), "Node not found\n")
    );
    let dump = same_as_ros2param(&mut expected, 161, &["dump", NODE]);
    assert!(
        dump.stdout
            .starts_with("/param_node:\n  ros__parameters:\n"),
        "{}",
        dump.stdout
    );
    expected.finish();
}

#[test]
fn set_matches_ros2param() {
    let mut expected = Transcript::load("param/set_matches_ros2param.txt");
    let _peer = peer(162, &[]);
    // Each set is run by us, then by the reference: setting the same value twice gives the same
    // answer twice.
    for (name, value) in [
        ("count", "10"),
        ("count", "7"),
        ("count", "x"),
        ("ratio", "-0.5"),
        ("ratio", "2.0"),
        ("name", "new value"),
        ("name", "'5'"),
        ("quoted", "false"),
        ("flags", "[false, true]"),
        ("numbers", "[4, 0x10]"),
        ("doubles", "[0.5, 1.0e+3]"),
        ("words", "[x, 'y', \"z w\"]"),
        ("nested.depth", "3"),
        ("fixed", "8"),
        ("nope", "1"),
        ("dynamic", "yes"),
        ("dynamic", "[1, a]"),
    ] {
        same_as_ros2param(&mut expected, 162, &["set", NODE, name, value]);
        same_as_ros2param(&mut expected, 162, &["get", NODE, name]);
    }
    same_as_ros2param(&mut expected, 162, &["dump", NODE]);
    expected.finish();
}

#[test]
fn delete_matches_ros2param() {
    let mut expected = Transcript::load("param/delete_matches_ros2param.txt");
    let _peer = peer(163, &[]);
    for name in ["dynamic", "count", "fixed", "nope"] {
        same_as_ros2param(&mut expected, 163, &["delete", NODE, name]);
    }
    same_as_ros2param(&mut expected, 163, &["dump", NODE]);
    let gone = param(163, &["get", NODE, "dynamic"]);
    assert_eq!(
        (gone.code, gone.stderr.as_str()),
        (Some(1), "Parameter not set\n")
    );
    expected.finish();
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
    let mut expected = Transcript::load("param/dump_then_load_gives_the_parameters_back.txt");
    let _peer = peer(165, &[]);
    let original = same_as_ros2param(&mut expected, 165, &["dump", NODE]).stdout;
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
    let load = same_as_ros2param(&mut expected, 165, &["load", NODE, &file]);
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
    same_as_ros2param(&mut expected, 165, &["get", NODE, "words"]);
    expected.finish();
}

#[test]
fn load_reads_wildcards_as_rcl_files_do() {
    let mut expected = Transcript::load("param/load_reads_wildcards_as_rcl_files_do.txt");
    let _peer = peer(166, &[]);
    let file = temp_file(
        "wildcard.yaml",
        "/**:\n  ros__parameters:\n    count: 15\n    name: from wildcard\n\
         /param_node:\n  ros__parameters:\n    count: 25\n    nested:\n      depth: 4\n\
         \x20     deeper: {label: '5'}\n    ratio: .5\n    words: [a, 'true', 3]\n",
    );
    same_as_ros2param(&mut expected, 166, &["load", NODE, &file]);
    same_as_ros2param(&mut expected, 166, &["dump", NODE]);
    same_as_ros2param(
        &mut expected,
        166,
        &["load", NODE, &file, "--no-use-wildcard"],
    );
    same_as_ros2param(&mut expected, 166, &["dump", NODE]);
    let only_wildcard = temp_file("only.yaml", "/**:\n  ros__parameters:\n    count: 35\n");
    same_as_ros2param(&mut expected, 166, &["load", NODE, &only_wildcard]);
    same_as_ros2param(&mut expected, 166, &["get", NODE, "count"]);
    let run = param(166, &["load", NODE, &only_wildcard, "--no-use-wildcard"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (Some(1), "Param file does not contain selected parameters\n")
    );
    expected.finish();
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
