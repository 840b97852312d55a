//! Our own `test_msgs/action/Fibonacci` server, as the action verbs' tests run it: a feedback per
//! new term, then the sequence as the result.

use horus_ros_actions::interfaces::test_msgs::action::{
    Fibonacci, FibonacciFeedback, FibonacciResult,
};
use horus_ros_actions::{ActionServer, EndpointBuilder};
use horus_ros_rmw::Context;

/// The server of `/fibonacci`, on a node `/fibonacci_action_server` of `context`.
pub fn fibonacci_server(context: &Context) -> ActionServer<Fibonacci> {
    let node = context
        .create_node("fibonacci_action_server", "/")
        .expect("node");
    ActionServer::<Fibonacci>::builder()
        .node(&node)
        .name("/fibonacci")
        .execute(|handle| {
            let order = usize::try_from(handle.goal().order).unwrap_or(0);
            let mut sequence = vec![0, 1];
            for i in 1..order {
                sequence.push(sequence[i] + sequence[i - 1]);
                let _ = handle.publish_feedback(FibonacciFeedback {
                    sequence: sequence.clone(),
                });
            }
            let _ = handle.succeed(FibonacciResult { sequence });
        })
        .build()
        .expect("action server")
}
