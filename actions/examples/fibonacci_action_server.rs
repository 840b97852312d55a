//! A horus-ros port of ROS 2's action tutorial server (`action_tutorials_py`
//! `fibonacci_action_server`, `action_tutorials_cpp` `fibonacci_action_server`).
//!
//! Node `fibonacci_action_server` serves `action_tutorials_interfaces/action/Fibonacci` on
//! `fibonacci` (resolved to `/fibonacci`), logging as the tutorial does: `Executing goal...`,
//! each `Feedback: [..]` (one per second), `Returning result: [..]`. Any ROS 2 Jazzy action
//! client of that type can use it:
//!
//! ```text
//! cargo run -p horus-ros-actions --example fibonacci_action_server
//! cargo run -p horus-ros-actions --example fibonacci_action_client    # or the tutorial's
//! ros2 action send_goal /fibonacci action_tutorials_interfaces/action/Fibonacci "{order: 5}"
//! ```
//!
//! Usage: `fibonacci_action_server [--period-ms MS] [--count N]`: `--period-ms` sets the time
//! per step (default 1000, the tutorial's `time.sleep(1)`), `--count N` exits after N goals
//! (else it serves until SIGINT/SIGTERM). The domain comes from `ROS_DOMAIN_ID`.

use std::sync::mpsc;
use std::time::{SystemTime, UNIX_EPOCH};

use horus_ros_actions::interfaces::action_tutorials_interfaces::action::{
    Fibonacci, FibonacciFeedback, FibonacciResult,
};
use horus_ros_actions::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut period = Duration::from_secs(1);
    let mut count = None;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let value = args.next().ok_or(format!("{arg} needs a value"))?;
        match arg.as_str() {
            "--period-ms" => period = Duration::from_millis(value.parse()?),
            "--count" => count = Some(value.parse::<usize>()?),
            other => return Err(format!("unknown argument {other}").into()),
        }
    }
    let context = Context::from_env()?;
    let node = context.create_node("fibonacci_action_server", "/")?;
    let (done, goals_done) = mpsc::channel::<()>();
    let log_node = node.clone();
    let _server = ActionServer::<Fibonacci>::builder()
        .node(&node)
        .name("fibonacci")
        .execute(move |handle| {
            info(&log_node, "Executing goal...");
            let mut partial_sequence = vec![0, 1];
            for i in 1..handle.goal().order.max(1) as usize {
                partial_sequence.push(partial_sequence[i] + partial_sequence[i - 1]);
                info(&log_node, &format!("Feedback: {partial_sequence:?}"));
                let _ = handle.publish_feedback(FibonacciFeedback {
                    partial_sequence: partial_sequence.clone(),
                });
                std::thread::sleep(period);
            }
            info(
                &log_node,
                &format!("Returning result: {partial_sequence:?}"),
            );
            let _ = handle.succeed(FibonacciResult {
                sequence: partial_sequence,
            });
            let _ = done.send(());
        })
        .build()?;
    match count {
        None => {
            context.wait_for_shutdown(None);
        }
        Some(n) => {
            for _ in 0..n {
                if goals_done.recv().is_err() {
                    break;
                }
            }
            // A result is sent once, reliably: stay until the clients have left (they leave
            // once they have it), woken by graph changes, at most a minute.
            let graph = horus_ros_graph::Graph::of(&context)?;
            graph.wait_until(Duration::from_secs(60), |c| {
                c.count_subscribers("/fibonacci/_action/feedback") == 0
            });
        }
    }
    Ok(())
}

/// Logs as rclpy's logger prints to the console: `[INFO] [<stamp>] [<node>]: <message>`.
fn info(node: &Node, message: &str) {
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    println!(
        "[INFO] [{}.{:09}] [{}]: {message}",
        now.as_secs(),
        now.subsec_nanos(),
        node.name().as_str()
    );
}
