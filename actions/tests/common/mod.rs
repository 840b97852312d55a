//! What the action tests share: a Fibonacci server as the ROS 2 tutorials and rclpy's test
//! servers write it, driven by its goal's `order`.

#![allow(dead_code)]

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use horus_ros_actions::interfaces::test_msgs::action::{
    Fibonacci, FibonacciFeedback, FibonacciResult,
};
use horus_ros_actions::prelude::*;
use horus_ros_actions::ActionServerBuilder;

/// "Did not hang" bound for discovery and calls on a loaded machine.
pub const WAIT: Duration = Duration::from_secs(30);

/// The sequence a goal of `order` ends with (rclpy's test server: `[0, 1]`, then `order - 1`
/// more).
pub fn fibonacci(order: i32) -> Vec<i32> {
    let mut s = vec![0, 1];
    for i in 1..order.max(1) as usize {
        s.push(s[i] + s[i - 1]);
    }
    s
}

/// A server of `/name` that rejects orders above 40 and accepts every cancel request. Each
/// step (one feedback) waits for a token from the returned sender (`gate`), or for a cancel
/// request, so tests decide when goals move on; with `gate = None` the steps run freely.
pub fn server_builder(
    gated: bool,
) -> (ActionServerBuilder<Fibonacci>, Option<mpsc::SyncSender<()>>) {
    let (tx, rx) = mpsc::sync_channel::<()>(1000);
    let rx = Arc::new(Mutex::new(rx));
    let builder = ActionServer::<Fibonacci>::builder()
        .on_goal(|_id, goal| {
            if goal.order > 40 {
                GoalResponse::Reject
            } else {
                GoalResponse::Accept
            }
        })
        .on_cancel(|_| CancelResponse::Accept)
        .execute(move |handle| {
            let order = handle.goal().order;
            if order < 0 {
                panic!("negative order");
            }
            let mut sequence = vec![0, 1];
            for i in 1..order.max(1) as usize {
                if gated {
                    // Wait for the test's go-ahead; a cancel request ends the wait too (the
                    // test sends a token after cancelling).
                    let _ = rx.lock().map(|r| r.recv_timeout(WAIT));
                }
                if handle.is_cancel_requested() {
                    let _ = handle.canceled(FibonacciResult { sequence });
                    return;
                }
                sequence.push(sequence[i] + sequence[i - 1]);
                let _ = handle.publish_feedback(FibonacciFeedback {
                    sequence: sequence.clone(),
                });
            }
            let _ = handle.succeed(FibonacciResult { sequence });
        });
    (builder, gated.then_some(tx))
}

/// Counts calls.
#[derive(Default, Clone)]
pub struct Counter(Arc<AtomicUsize>);

impl Counter {
    pub fn bump(&self) {
        self.0.fetch_add(1, Ordering::SeqCst);
    }
    pub fn get(&self) -> usize {
        self.0.load(Ordering::SeqCst)
    }
}
