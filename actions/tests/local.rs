//! Our client against our server, in one process (run inside `scripts/isolated`): every case of
//! the interop tests, plus those only our own server lets a test arrange (result expiry, cancel
//! by time, a panicking execution).

mod common;

use std::time::Duration;

use common::{fibonacci, server_builder, WAIT};
use horus_ros_actions::interfaces::test_msgs::action::{Fibonacci, FibonacciGoal};
use horus_ros_actions::prelude::*;
use horus_ros_actions::{
    feedback_qos, status_qos, Action, ActionNames, CancelError, EndpointOptions, FeedbackError,
    GetResultError, SendGoalError,
};
use horus_ros_msgs::action_msgs::msg::GoalStatusArray;
use horus_ros_msgs::action_msgs::srv::CancelGoal;
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_services::DdsServiceServer;

fn node(name: &str) -> Node {
    let context = Context::from_env().expect("context");
    context.create_node(name, "/").expect("node")
}

fn client(node: &Node, action: &str) -> ActionClient<Fibonacci> {
    let client = ActionClient::<Fibonacci>::builder()
        .node(node)
        .name(action)
        .build()
        .expect("client");
    assert!(client.wait_for_server(WAIT), "no server within {WAIT:?}");
    client
}

#[test]
fn goal_feedback_and_result() {
    let n = node("local_goal");
    let (builder, _) = server_builder(false);
    let _server = builder
        .node(&n)
        .name("/local_goal")
        .build()
        .expect("server");
    let client = client(&n, "/local_goal");
    let goal = client
        .send_goal(FibonacciGoal { order: 10 }, WAIT)
        .expect("accepted");
    let (state, result) = goal.get_result(WAIT).expect("result");
    assert_eq!(state, GoalState::Succeeded);
    assert_eq!(result.sequence, fibonacci(10));
    // Feedback came in order: each a prefix of the result, each longer than the one before.
    let mut last = 2;
    while let Some(fb) = goal.try_recv_feedback() {
        assert!(fb.sequence.len() > last, "out of order: {:?}", fb.sequence);
        assert_eq!(fb.sequence[..], result.sequence[..fb.sequence.len()]);
        last = fb.sequence.len();
    }
    assert!(goal.wait_for_status(GoalState::Succeeded, WAIT) == Some(GoalState::Succeeded));
    // A result already there is answered at once, as often as asked.
    assert_eq!(
        goal.get_result(WAIT).expect("again").1.sequence,
        fibonacci(10)
    );
}

/// rcl `rcl_action_server_is_available`: the three services are not enough, the feedback
/// subscription must be matched with a publisher too — else the first feedback of a goal sent at
/// once can be lost (a VOLATILE topic not matched yet).
#[test]
fn a_server_is_ready_once_its_feedback_publisher_is_matched() {
    let n = node("local_ready");
    let names = ActionNames::of("/local_ready");
    let service = |name: &str| EndpointOptions::default().node(&n).name(name);
    let _send_goal = DdsServiceServer::<<Fibonacci as Action>::SendGoal>::builder()
        .options(service(&names.send_goal))
        .build()
        .expect("send_goal");
    let _cancel_goal = DdsServiceServer::<CancelGoal>::builder()
        .options(service(&names.cancel_goal))
        .build()
        .expect("cancel_goal");
    let _get_result = DdsServiceServer::<<Fibonacci as Action>::GetResult>::builder()
        .options(service(&names.get_result))
        .build()
        .expect("get_result");
    let client = ActionClient::<Fibonacci>::builder()
        .node(&n)
        .name("/local_ready")
        .build()
        .expect("client");
    // The three services become ready; the server does not, whatever the wait.
    assert!(!client.wait_for_server(Duration::from_secs(2)));
    assert!(client.server_available(), "the three services are known");
    assert!(!client.is_server_ready());
    let _feedback = n
        .create_publisher::<<Fibonacci as Action>::FeedbackMessage>(
            &names.feedback,
            &feedback_qos(),
        )
        .expect("feedback publisher");
    assert!(client.wait_for_server(WAIT), "no server within {WAIT:?}");
    assert!(client.is_server_ready());
}

#[test]
fn rejected_goal_is_an_error() {
    let n = node("local_reject");
    let (builder, _) = server_builder(false);
    let _server = builder
        .node(&n)
        .name("/local_reject")
        .build()
        .expect("server");
    let client = client(&n, "/local_reject");
    let err = client
        .send_goal(FibonacciGoal { order: 41 }, WAIT)
        .expect_err("rejected");
    assert_eq!(err, SendGoalError::Rejected);
    assert_eq!(client.goals_in_flight(), 0);
}

#[test]
fn cancel_mid_goal_then_terminated_and_unknown() {
    let n = node("local_cancel");
    let (builder, gate) = server_builder(true);
    let gate = gate.expect("gated");
    let server = builder
        .node(&n)
        .name("/local_cancel")
        .build()
        .expect("server");
    let client = client(&n, "/local_cancel");
    let goal = client
        .send_goal(FibonacciGoal { order: 20 }, WAIT)
        .expect("accepted");
    gate.send(()).expect("step");
    let first = goal.recv_feedback(WAIT).expect("first feedback");
    assert_eq!(first.sequence, vec![0, 1, 1]);
    assert_eq!(
        goal.wait_for_status(GoalState::Executing, WAIT),
        Some(GoalState::Executing)
    );
    let canceling = goal.cancel(WAIT).expect("cancel accepted");
    assert_eq!(canceling.len(), 1);
    assert_eq!(canceling[0].goal_id.uuid, goal.goal_id().0);
    assert_eq!(server.goals(), vec![(goal.goal_id(), GoalState::Canceling)]);
    gate.send(()).expect("step");
    let (state, result) = goal.get_result(WAIT).expect("result");
    assert_eq!(state, GoalState::Canceled);
    assert_eq!(result.sequence, vec![0, 1, 1]);
    assert_eq!(
        goal.recv_feedback(WAIT).map(|_| ()),
        Err(FeedbackError::GoalEnded)
    );
    // The goal has ended: a second request says so.
    assert_eq!(goal.cancel(WAIT), Err(CancelError::GoalTerminated));
}

#[test]
fn two_goals_at_once_and_cancel_by_time() {
    let n = node("local_two");
    let (builder, gate) = server_builder(true);
    let gate = gate.expect("gated");
    let server = builder.node(&n).name("/local_two").build().expect("server");
    let client = client(&n, "/local_two");
    let a = client
        .send_goal(FibonacciGoal { order: 5 }, WAIT)
        .expect("a");
    let b = client
        .send_goal(FibonacciGoal { order: 5 }, WAIT)
        .expect("b");
    assert_ne!(a.goal_id(), b.goal_id());
    // Cancel what was accepted at or before a's stamp: a only.
    let canceling = client
        .cancel_before(a.stamp(), WAIT)
        .expect("cancel before");
    let ids: Vec<_> = canceling.iter().map(|g| g.goal_id.uuid).collect();
    assert_eq!(ids, vec![a.goal_id().0]);
    for _ in 0..10 {
        gate.send(()).expect("step");
    }
    assert_eq!(a.get_result(WAIT).expect("a").0, GoalState::Canceled);
    let (state, result) = b.get_result(WAIT).expect("b");
    assert_eq!(
        (state, result.sequence),
        (GoalState::Succeeded, fibonacci(5))
    );
    assert_eq!(server.goals().len(), 2);
    // Nothing left to cancel: rcl_action answers ERROR_NONE with no goals.
    assert_eq!(client.cancel_all(WAIT), Ok(vec![]));
}

#[test]
fn cancel_all_cancels_every_active_goal() {
    let n = node("local_all");
    let (builder, gate) = server_builder(true);
    let gate = gate.expect("gated");
    let _server = builder.node(&n).name("/local_all").build().expect("server");
    let client = client(&n, "/local_all");
    let goals: Vec<_> = (0..3)
        .map(|_| {
            client
                .send_goal(FibonacciGoal { order: 8 }, WAIT)
                .expect("accepted")
        })
        .collect();
    let canceling = client.cancel_all(WAIT).expect("cancel all");
    assert_eq!(canceling.len(), 3);
    // Every goal is CANCELING now, no longer cancelable: nothing more to cancel.
    assert_eq!(client.cancel_before(Time::now(), WAIT), Ok(vec![]));
    for _ in 0..30 {
        gate.send(()).expect("step");
    }
    for g in &goals {
        assert_eq!(g.get_result(WAIT).expect("result").0, GoalState::Canceled);
    }
}

#[test]
fn panicking_execution_aborts_the_goal_and_server_lives_on() {
    let n = node("local_panic");
    let (builder, _) = server_builder(false);
    let _server = builder
        .node(&n)
        .name("/local_panic")
        .build()
        .expect("server");
    let client = client(&n, "/local_panic");
    let bad = client
        .send_goal(FibonacciGoal { order: -1 }, WAIT)
        .expect("accepted");
    let (state, result) = bad.get_result(WAIT).expect("result");
    assert_eq!(state, GoalState::Aborted);
    assert!(result.sequence.is_empty());
    let good = client
        .send_goal(FibonacciGoal { order: 3 }, WAIT)
        .expect("accepted");
    assert_eq!(
        good.get_result(WAIT).expect("result").1.sequence,
        fibonacci(3)
    );
}

#[test]
fn results_expire_after_result_timeout() {
    let n = node("local_expiry");
    let (builder, _) = server_builder(false);
    let server = builder
        .node(&n)
        .name("/local_expiry")
        .result_timeout(Duration::from_millis(200))
        .build()
        .expect("server");
    let client = client(&n, "/local_expiry");
    let goal = client
        .send_goal(FibonacciGoal { order: 3 }, WAIT)
        .expect("accepted");
    assert_eq!(
        goal.get_result(WAIT).expect("result").0,
        GoalState::Succeeded
    );
    // Expiry is announced on the status topic: an array without the goal (transient local: the
    // latest array reaches a late subscription too).
    let mut status = n
        .create_subscription::<GoalStatusArray>("/local_expiry/_action/status", &status_qos())
        .expect("status subscription");
    let deadline = std::time::Instant::now() + WAIT;
    'expired: loop {
        while let Some(array) = status.try_take().expect("status") {
            if array.status_list.is_empty() {
                break 'expired;
            }
        }
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        assert!(!left.is_zero(), "the result never expired");
        status.wait(left);
    }
    assert!(server.goals().is_empty());
    assert_eq!(
        goal.get_result(WAIT).map(|_| ()),
        Err(GetResultError::UnknownGoal)
    );
}

#[test]
fn hundred_goals_in_flight() {
    let n = node("local_hundred");
    let (builder, _) = server_builder(false);
    let _server = builder
        .node(&n)
        .name("/local_hundred")
        .build()
        .expect("server");
    let client = client(&n, "/local_hundred");
    let mut pending: Vec<_> = (0..100)
        .map(|i| client.send_goal_pending(FibonacciGoal { order: i % 10 + 1 }, WAIT))
        .collect();
    let handles: Vec<_> = pending
        .drain(..)
        .map(|p| p.wait().expect("accepted"))
        .collect();
    let results: Vec<_> = handles.iter().map(|h| h.get_result_pending(WAIT)).collect();
    for (i, r) in results.into_iter().enumerate() {
        let (state, result) = r.wait().expect("result");
        assert_eq!(state, GoalState::Succeeded);
        assert_eq!(result.sequence, fibonacci(i as i32 % 10 + 1));
    }
}

#[test]
fn pending_operations_are_futures() {
    let n = node("local_async");
    let (builder, gate) = server_builder(true);
    let gate = gate.expect("gated");
    let _server = builder
        .node(&n)
        .name("/local_async")
        .build()
        .expect("server");
    let client = ActionClient::<Fibonacci>::builder()
        .node(&n)
        .name("/local_async")
        .build()
        .expect("client");
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .expect("runtime");
    runtime.block_on(async {
        assert!(client.wait_for_server_async(WAIT).await, "no server");
        let goal = client
            .send_goal_pending(FibonacciGoal { order: 4 }, WAIT)
            .await
            .expect("accepted");
        // Not yet answerable: the goal waits for its steps.
        let mut result = goal.get_result_pending(WAIT);
        assert!(result.try_take().is_none());
        for _ in 0..3 {
            gate.send(()).expect("step");
        }
        let (state, r) = result.await.expect("result");
        assert_eq!((state, r.sequence), (GoalState::Succeeded, fibonacci(4)));
        let cancel = goal.cancel_pending(WAIT).await;
        assert_eq!(cancel, Err(CancelError::GoalTerminated));
    });
}
