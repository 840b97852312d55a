//! First replies to real rmw_cyclonedds_cpp clients started together: our AddTwoInts server on
//! each DDS backend beside rclpy's own `add_two_ints_server` (demo_nodes_py on
//! rmw_cyclonedds_cpp), in the same run and on the same load. Each run: three rounds of eight
//! processes of one client (`wait_for_service`, then twenty calls), then sixteen processes at
//! once; each server gets a warm-up round of one client first. Prints, per server, the first
//! calls answered and all calls answered.
//!
//! Run inside a private network namespace: `scripts/bench`, or
//! `cargo bench -p interop-tests --bench first_reply --no-run` then
//! `scripts/isolated cargo bench -p interop-tests --bench first_reply`.
//! Settings: `HORUS_BENCH_FIRST_REPLY_RUNS` (runs of the rounds per server, default 3),
//! `HORUS_BENCH_FIRST_REPLY_HOGS` (processes spinning on the CPU meanwhile, as `yes` does;
//! default 2, 0 for none).

use std::process::Stdio;

use horus_ros_rmw::Backend;
use horus_ros_services::prelude::*;
use horus_ros_test_support::bench::{
    cpu_hogs, env_count, env_usize, loadavg, refuse_outside_namespace, Stopped,
};
use horus_ros_test_support::jazzy::{self, Rmw};
use interop_tests::peers::clients::{add_two_ints_server, run_round, Round, ADD_TWO_INTS};

const DOMAIN: u32 = 91;

/// The server under test, alive while this lives.
enum Server {
    /// Ours, in this process.
    Ours(
        #[allow(dead_code)] Context,
        #[allow(dead_code)] ServiceServer<AddTwoInts>,
    ),
    /// rclpy's demo server, a process of its own.
    Rclpy(#[allow(dead_code)] Stopped),
}

fn ours(backend: Backend) -> Server {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .backend(backend)
        .build()
        .expect("context");
    let server = add_two_ints_server(&context, "add_two_ints_server");
    Server::Ours(context, server)
}

fn rclpy_demo_server() -> Server {
    let child = jazzy::command("bash")
        .args([
            "-c",
            r#"exec "$(ros2 pkg prefix demo_nodes_py)/lib/demo_nodes_py/add_two_ints_server""#,
        ])
        .env("RMW_IMPLEMENTATION", Rmw::CycloneDds.name())
        .env("ROS_DOMAIN_ID", DOMAIN.to_string())
        .env("CYCLONEDDS_URI", interop_tests::cyclone_config())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start rclpy's add_two_ints_server");
    Server::Rclpy(Stopped(child))
}

/// First replies and replies over all runs, and the clients and calls asked.
#[derive(Default)]
struct Totals {
    first: usize,
    clients: usize,
    replies: u64,
    calls: u64,
}

fn measure(make: impl Fn() -> Server, runs: usize) -> Totals {
    let _server = make();
    // Warm-up: one client, waiting for the server to be there.
    let (service, type_name) = ADD_TWO_INTS;
    run_round(
        Rmw::CycloneDds,
        service,
        type_name,
        &Round::single_clients(1, 1),
        DOMAIN,
    );
    let mut totals = Totals::default();
    for _ in 0..runs {
        for processes in [8, 8, 8, 16] {
            let round = Round::single_clients(processes, 20);
            let tally = run_round(Rmw::CycloneDds, service, type_name, &round, DOMAIN);
            totals.first += tally.first_replies;
            totals.clients += round.total_clients();
            totals.replies += tally.replies;
            totals.calls += round.total_calls();
        }
    }
    totals
}

fn main() {
    refuse_outside_namespace(
        "first_reply",
        "scripts/isolated cargo bench -p interop-tests --bench first_reply",
    );
    let runs = env_usize("HORUS_BENCH_FIRST_REPLY_RUNS", 3);
    let hogs = env_count("HORUS_BENCH_FIRST_REPLY_HOGS", 2);
    let _hogs = cpu_hogs(hogs);
    println!(
        "first replies to real rmw_cyclonedds_cpp 2.2.2 clients started together: {runs} runs of \
         (3 rounds of 8 processes + 16 at once) x 20 calls per server, {hogs} CPU hogs, load {}",
        loadavg()
    );
    println!(
        "{:<44} {:>16} {:>18}",
        "server", "first replies", "all replies"
    );
    let servers = [
        ("horus-ros, Cyclone backend", Some(Backend::Cyclone)),
        ("horus-ros, rustdds backend", Some(Backend::RustDds)),
        ("rclpy add_two_ints_server (rmw_cyclonedds)", None),
    ];
    for (name, backend) in servers {
        let t = measure(|| backend.map_or_else(rclpy_demo_server, ours), runs);
        println!(
            "{name:<44} {:>16} {:>18}",
            format!("{}/{}", t.first, t.clients),
            format!("{}/{}", t.replies, t.calls)
        );
    }
    println!("load at the end: {}", loadavg());
}
