//! A horus-ros port of ROS 2's action tutorial client (`action_tutorials_py`
//! `fibonacci_action_client`).
//!
//! Node `fibonacci_action_client` sends a goal of order 10 to `/fibonacci`
//! (`action_tutorials_interfaces/action/Fibonacci`), logs `Goal accepted :)` (or
//! `Goal rejected :(`), each `Received feedback: [..]`, then `Result: [..]`, and exits.
//!
//! ```text
//! cargo run -p horus-ros-actions --example fibonacci_action_server   # or the tutorial's
//! cargo run -p horus-ros-actions --example fibonacci_action_client [ORDER]
//! ```

use std::time::{SystemTime, UNIX_EPOCH};

use horus_ros_actions::interfaces::action_tutorials_interfaces::action::{
    Fibonacci, FibonacciGoal,
};
use horus_ros_actions::prelude::*;
use horus_ros_actions::{FeedbackError, SendGoalError};

/// How long to wait for the server, a goal response and the result.
const WAIT: Duration = Duration::from_secs(60);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let order = match std::env::args().nth(1) {
        Some(arg) => arg.parse()?,
        None => 10,
    };
    let context = Context::from_env()?;
    let node = context.create_node("fibonacci_action_client", "/")?;
    let client = ActionClient::<Fibonacci>::builder()
        .node(&node)
        .name("fibonacci")
        .build()?;
    if !client.wait_for_server(WAIT) {
        return Err("no /fibonacci action server".into());
    }
    let goal = match client.send_goal(FibonacciGoal { order }, WAIT) {
        Ok(goal) => goal,
        Err(SendGoalError::Rejected) => {
            info(&node, "Goal rejected :(");
            return Ok(());
        }
        Err(e) => return Err(e.into()),
    };
    info(&node, "Goal accepted :)");
    loop {
        match goal.recv_feedback(WAIT) {
            Ok(feedback) => info(
                &node,
                &format!("Received feedback: {:?}", feedback.partial_sequence),
            ),
            Err(FeedbackError::GoalEnded) => break,
            Err(e) => return Err(e.into()),
        }
    }
    let (_, result) = goal.get_result(WAIT)?;
    info(&node, &format!("Result: {:?}", result.sequence));
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
