//! horus-ros against ros2cli 0.32.2, live: every verb the two share (`node`, `topic`,
//! `service`, `param`, `action`, `lifecycle`, `interface`), with its options' edge cases and its
//! errors, is run as `horus-ros ARGS` and as `ros2 ARGS` (same ARGS, same environment) on one
//! graph of real rclpy nodes (`peers/jazzy_live_graph.py`), and their stdout, stderr and exit
//! status must be equal — after a normalisation limited to what changes from one run to the
//! next (timing, random ids), named per case in `cli_diff/cases.rs` (`Norm`). The one
//! difference kept on purpose (`Known`: ros2cli crashing with a Python traceback on bad input,
//! where horus-ros prints one line) is checked as its reason says, and so is one of ros2cli's
//! timing: a stream verb stopped by SIGINT whose rclpy context its SIGINT handler shut down
//! first (`failed to shutdown`, exit status 1; seen on rmw_zenoh_cpp). A `ros2` run that
//! fails on its own (hung, or its Zenoh session not closed in time) is run once more; a
//! `horus-ros` run never is.
//!
//! The RMW is the run's peers' (`HORUS_ROS_PEER_RMW`: rmw_fastrtps_cpp by default,
//! rmw_cyclonedds_cpp, rmw_zenoh_cpp — with a `rmw_zenohd` of the test's own); every process
//! (the peer, `ros2`, its daemon, `horus-ros`, its daemon) runs on it: horus-ros's backend
//! follows `RMW_IMPLEMENTATION` as rcl's RMW does.
//!
//! Both tools answer the graph queries through their daemons, started once, as a user's
//! commands do: ros2cli's `--no-daemon` waits a fixed `--spin-time` (0.5 s), too short for a
//! Fast DDS graph to be complete on a loaded machine, so only two cases run without them
//! (with `--spin-time 5`).
//!
//! The test prints a table, one row per verb (`cli-diff<TAB>rmw<TAB>verb<TAB>result`, which
//! `scripts/cli-diff` collects for the three RMWs), then every difference as a diff. Run inside
//! the private network namespace:
//! `HORUS_ROS_PEER_RMW=rmw_cyclonedds_cpp scripts/isolated cargo test -p horus-ros-cli --test
//! cli_diff -- --nocapture`.

mod common;
#[path = "cli_diff/mod.rs"]
mod live;

use std::time::Instant;

use horus_ros_test_support::jazzy::Rmw;
use live::graph::LiveGraph;
use live::{cases, report, run_all, Verdict};

#[test]
fn horus_ros_prints_what_ros2cli_prints() {
    let rmw = Rmw::of_peers();
    let started = Instant::now();
    let dir = std::env::temp_dir().join(format!("horus_ros_live_{}", std::process::id()));
    let cases = cases::all(&dir);
    // HORUS_ROS_CLI_DIFF_ONLY=<regex>: only the cases whose command line it matches.
    let only = regex::Regex::new(&std::env::var("HORUS_ROS_CLI_DIFF_ONLY").unwrap_or_default())
        .expect("HORUS_ROS_CLI_DIFF_ONLY: a regular expression");
    let mut graph = LiveGraph::start(rmw);
    let cases: Vec<_> = cases
        .into_iter()
        .filter(|c| only.is_match(&c.command_line()))
        .collect();
    let outcomes = run_all(&mut graph, &cases);
    drop(graph);
    let _ = std::fs::remove_dir_all(&dir);
    let report = report(rmw.name(), &outcomes, started.elapsed());
    println!("{report}");
    // scripts/cli-diff collects the reports of the three RMWs from these files.
    if let Some(path) = std::env::var_os("HORUS_ROS_CLI_DIFF_REPORT") {
        std::fs::write(&path, &report).expect("write the report");
    }
    let different = outcomes
        .iter()
        .filter(|o| matches!(o.verdict, Verdict::Different(_)))
        .count();
    assert_eq!(different, 0, "horus-ros differs from ros2cli:\n{report}");
}
