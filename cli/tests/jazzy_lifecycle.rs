//! Tests of `lifecycle nodes|list|get|set` driving a real rclpy 7.1
//! `rclpy.lifecycle.LifecycleNode` (`lifecycle/tests/peers/jazzy_lifecycle.py`) through its
//! transitions (a failing callback included) and the `--json` documents, and driving a horus-ros
//! `LifecycleNode`. That every verb prints what ros2lifecycle 0.32.2 prints (stdout, stderr,
//! exit status) in each state is checked live, `ros2 lifecycle …` beside `horus-ros lifecycle
//! …` on one rclpy node, on each RMW, by `tests/cli_diff.rs` (`cli_diff/cases.rs`,
//! `lifecycles`).
//!
//! Each test has its own DDS domain (141-142). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test jazzy_lifecycle`.

mod common;

use std::path::PathBuf;

use common::{horus, Peer, Run, PEER_START};
use horus_ros_lifecycle::{CallbackReturn, LifecycleCallbacks, LifecycleNode, State};
use serde_json::{json, Value};

const NODE: &str = "/py_managed";

/// The two tests run one after the other: each runs many CLI processes and Python peers, and on
/// a loaded machine a CLI's discovery wait can end before a rustdds participant's
/// `ros_discovery_info` arrived (see docs/design.md, "CLI daemon": such a participant holds the
/// wait at most 1.6 s), which then reads "Node not found".
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner())
}

/// The rclpy lifecycle node `/py_managed` in `domain`.
fn peer(domain: u32) -> Peer {
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../lifecycle/tests/peers/jazzy_lifecycle.py");
    let spec = json!({"domain": domain, "name": "py_managed", "lifecycle": true}).to_string();
    Peer::start_path(&script, &[spec.as_str()], PEER_START * 2)
}

/// Runs `horus-ros [--backend rustdds] lifecycle <args>`. The rclpy peer runs on Fast DDS,
/// whose service convention only the rustdds backend speaks (as rmw_cyclonedds, the Cyclone
/// backend cannot call it), so the verbs that call services run on rustdds against it.
fn lifecycle(domain: u32, rustdds: bool, args: &[&str]) -> Run {
    let mut all = if rustdds {
        vec!["--backend", "rustdds", "lifecycle"]
    } else {
        vec!["lifecycle"]
    };
    all.extend_from_slice(args);
    horus(domain, &all)
}

/// The run's stdout as JSON (a failure shows its stderr).
fn json_of(run: &Run) -> Value {
    serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("{e}: stdout {:?}, stderr {:?}", run.stdout, run.stderr))
}

fn expect(run: &Run, stdout: &str, stderr: &str, code: i32) {
    assert_eq!(
        (run.stdout.as_str(), run.stderr.as_str(), run.code),
        (stdout, stderr, Some(code))
    );
}

#[test]
fn verbs_drive_an_rclpy_lifecycle_node() {
    let _serial = one_at_a_time();
    let domain = 141;
    let mut peer = peer(domain);

    let nodes = lifecycle(domain, true, &["nodes"]);
    assert_eq!(nodes.stdout, "/py_managed\n");
    // Graph only: the same on the backend the environment chooses.
    expect(
        &lifecycle(domain, false, &["nodes"]),
        "/py_managed\n",
        "",
        0,
    );

    let get = lifecycle(domain, true, &["get", "py_managed"]);
    assert_eq!(get.stdout, "unconfigured [1]\n");
    let missing = lifecycle(domain, true, &["get", "/no_such_node"]);
    expect(&missing, "", "Node not found\n", 1);
    expect(
        &lifecycle(domain, true, &["set", "/no_such_node", "configure"]),
        "",
        "Node not found\n",
        1,
    );

    let list = lifecycle(domain, true, &["list", "py_managed"]);
    assert_eq!(
        list.stdout,
        "- configure [1]\n\tStart: unconfigured\n\tGoal: configuring\n\
         - shutdown [5]\n\tStart: unconfigured\n\tGoal: shuttingdown\n"
    );
    let all = lifecycle(domain, true, &["list", NODE, "-a"]);
    assert_eq!(
        all.stdout.lines().filter(|l| l.starts_with("- ")).count(),
        25
    );
    let unknown = lifecycle(domain, true, &["set", NODE, "activate"]);
    expect(
        &unknown,
        "",
        "Unknown transition requested, available ones are:\n- configure [1]\n- shutdown [5]\n",
        1,
    );

    // A successful transition, and the way back, print ros2lifecycle's line.
    expect(
        &lifecycle(domain, true, &["set", NODE, "configure"]),
        "Transitioning successful\n",
        "",
        0,
    );
    let back = lifecycle(domain, true, &["set", NODE, "cleanup"]);
    expect(&back, "Transitioning successful\n", "", 0);
    // By id: 1 (configure), 3 (activate).
    expect(
        &lifecycle(domain, true, &["set", NODE, "1"]),
        "Transitioning successful\n",
        "",
        0,
    );
    expect(
        &lifecycle(domain, true, &["set", NODE, "3"]),
        "Transitioning successful\n",
        "",
        0,
    );
    assert_eq!(
        lifecycle(domain, true, &["get", NODE]).stdout,
        "active [3]\n"
    );

    // A failing callback: "Transitioning failed" on stderr, exit status 0; the node stays active,
    // so both sides see the same failure.
    peer.send(&json!({"behave": {"on_deactivate": "failure"}}).to_string());
    let failed = lifecycle(domain, true, &["set", NODE, "deactivate"]);
    expect(&failed, "", "Transitioning failed\n", 0);

    // --json.
    let run = lifecycle(domain, true, &["--json", "get", NODE]);
    let v: Value = json_of(&run);
    assert_eq!(
        v,
        json!({"node": NODE, "state": {"id": 3, "label": "active"}})
    );
    let run = lifecycle(domain, true, &["--json", "get"]);
    let v: Value = json_of(&run);
    assert_eq!(
        v,
        json!([{"node": NODE, "state": {"id": 3, "label": "active"}, "error": null}])
    );
    let run = lifecycle(domain, true, &["--json", "list", NODE]);
    let v: Value = json_of(&run);
    assert_eq!(v["node"], json!(NODE));
    assert_eq!(
        v["transitions"][0],
        json!({"id": 4, "label": "deactivate", "start": {"id": 3, "label": "active"},
               "goal": {"id": 14, "label": "deactivating"}})
    );
    let run = lifecycle(domain, true, &["--json", "nodes"]);
    assert_eq!(Some(json_of(&run)), Some(json!([NODE])));
    let run = lifecycle(domain, true, &["--json", "nodes", "-c"]);
    assert_eq!(Some(json_of(&run)), Some(json!({"count": 1})));
    let run = lifecycle(domain, true, &["--json", "set", NODE, "deactivate"]);
    let v: Value = json_of(&run);
    assert_eq!(
        v,
        json!({"node": NODE, "transition": {"id": 4, "label": "deactivate"}, "success": false})
    );
    peer.send(&json!({"behave": {"on_deactivate": "success"}}).to_string());
    let run = lifecycle(domain, true, &["--json", "set", NODE, "shutdown"]);
    let v: Value = json_of(&run);
    assert_eq!(
        v,
        json!({"node": NODE, "transition": {"id": 7, "label": "shutdown"}, "success": true})
    );
    expect(
        &lifecycle(domain, true, &["get", NODE]),
        "finalized [4]\n",
        "",
        0,
    );
}

/// Configure fails once, then succeeds.
struct FailsOnce(bool);

impl LifecycleCallbacks for FailsOnce {
    fn on_configure(&mut self, _previous: State) -> CallbackReturn {
        if std::mem::replace(&mut self.0, false) {
            CallbackReturn::Failure
        } else {
            CallbackReturn::Success
        }
    }
}

/// The verbs drive a horus-ros lifecycle node, on the backend the environment chooses.
#[test]
fn verbs_drive_a_horus_ros_lifecycle_node() {
    let _serial = one_at_a_time();
    let domain = 142;
    let context = horus_ros_rmw::Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node("managed", "/ns").expect("node");
    let managed = LifecycleNode::builder()
        .node(&node)
        .callbacks(FailsOnce(true))
        .build()
        .expect("lifecycle node");
    let run = |args: &[&str]| lifecycle(domain, false, args);
    expect(&run(&["nodes"]), "/ns/managed\n", "", 0);
    expect(&run(&["get", "/ns/managed"]), "unconfigured [1]\n", "", 0);
    expect(
        &run(&["set", "/ns/managed", "configure"]),
        "",
        "Transitioning failed\n",
        0,
    );
    expect(
        &run(&["set", "/ns/managed", "configure"]),
        "Transitioning successful\n",
        "",
        0,
    );
    assert_eq!(managed.current_state(), State::Inactive);
    expect(
        &run(&["list", "/ns/managed"]),
        "- cleanup [2]\n\tStart: inactive\n\tGoal: cleaningup\n\
         - activate [3]\n\tStart: inactive\n\tGoal: activating\n\
         - shutdown [6]\n\tStart: inactive\n\tGoal: shuttingdown\n",
        "",
        0,
    );
    expect(
        &run(&["set", "/ns/managed", "3"]),
        "Transitioning successful\n",
        "",
        0,
    );
    expect(&run(&["get"]), "/ns/managed: active [3]\n", "", 0);
    assert_eq!(managed.current_state(), State::Active);
}
