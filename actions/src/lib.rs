//! horus-ros actions: ROS 2 action servers and clients from Rust, as rcl_action draws them,
//! wire-compatible with rclpy's and rclcpp's (ROS 2 Jazzy).
//!
//! ```no_run
//! use std::time::Duration;
//! use horus_ros_actions::interfaces::test_msgs::action::{Fibonacci, FibonacciFeedback, FibonacciResult};
//! use horus_ros_actions::prelude::*;
//!
//! let _server = ActionServer::<Fibonacci>::builder()
//!     .name("/fibonacci")
//!     .on_goal(|_id, goal| if goal.order <= 46 { GoalResponse::Accept } else { GoalResponse::Reject })
//!     .on_cancel(|_goal| CancelResponse::Accept)
//!     .execute(|handle| {
//!         let mut sequence = vec![0, 1];
//!         for i in 1..handle.goal().order.max(1) as usize {
//!             if handle.is_cancel_requested() {
//!                 let _ = handle.canceled(FibonacciResult { sequence });
//!                 return;
//!             }
//!             sequence.push(sequence[i] + sequence[i - 1]);
//!             let _ = handle.publish_feedback(FibonacciFeedback { sequence: sequence.clone() });
//!         }
//!         let _ = handle.succeed(FibonacciResult { sequence });
//!     })
//!     .build()?;
//!
//! let client = ActionClient::<Fibonacci>::builder().name("/fibonacci").build()?;
//! client.wait_for_server(Duration::from_secs(5));
//! let goal = client.send_goal(Default::default(), Duration::from_secs(5))?;
//! while let Ok(feedback) = goal.recv_feedback(Duration::from_secs(5)) {
//!     println!("feedback: {:?}", feedback.sequence);
//! }
//! let (state, result) = goal.get_result(Duration::from_secs(10))?;
//! println!("{state:?}: {:?}", result.sequence);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Action types come from `.action` files (the interface generator, horus-ros-codegen) or from
//! Rust ([`action!`]), the same on the wire and in their hashes.
//!
//! # Entities
//!
//! An action `/a` is three services and two topics, named as rcl_action's `names.c` names them
//! ([`ActionNames`]): `/a/_action/send_goal` (`pkg/action/A_SendGoal`),
//! `/a/_action/cancel_goal` (`action_msgs/srv/CancelGoal`), `/a/_action/get_result`
//! (`pkg/action/A_GetResult`), `/a/_action/feedback` (`pkg/action/A_FeedbackMessage`) and
//! `/a/_action/status` (`action_msgs/msg/GoalStatusArray`), with rcl_action's default QoS
//! (services: `services_default`; feedback: keep last 10, reliable, volatile; status:
//! `rcl_action_qos_profile_status_default`, keep last 1, reliable, transient local). The
//! services are the services crate's servers and clients: both DDS service conventions
//! (rmw_fastrtps, rmw_cyclonedds), chosen per peer.
//!
//! # Builders
//!
//! [`ActionServer::builder()`] and [`ActionClient::builder()`] take the services' endpoint
//! setters ([`EndpointBuilder`]: `node`, `name` — the action name —, `qos` of the three
//! services, `wire_flavour`, `options`) and their own (callbacks, feedback and status QoS,
//! result timeout, bounds).
//!
//! # Goals
//!
//! A server's goals follow rcl_action's state machine ([`GoalState`], [`GoalEvent`]); cancel
//! requests are processed as `rcl_action_process_cancel_request` does (by id, by time, all);
//! results are kept for `result_timeout` after their goal ended (default 900 s) and a
//! `get_result` request for a goal still running is answered when it ends.
//!
//! # Without blocking
//!
//! [`ActionClient::send_goal_pending`], [`ClientGoalHandle::get_result_pending`] and
//! [`ClientGoalHandle::cancel_pending`] return pending operations to check from a loop (a HORUS
//! node's `tick()`: `try_take`), to wait on, or to `.await` on any executor (they are
//! `Future`s). Feature `tokio`: `ActionClient::wait_for_server_async` too.

mod client;
#[macro_use]
mod macros;
mod common;
mod error;
pub mod goal_state;
pub mod interfaces;
mod server;

pub use client::{
    ActionClient, ActionClientBuilder, ClientGoalHandle, PendingCancel, PendingGoal, PendingResult,
    DEFAULT_FEEDBACK_CAPACITY,
};
pub use common::{
    feedback_qos, services_qos, status_qos, ActionNames, GoalId, DEFAULT_RESULT_TIMEOUT,
};
pub use error::{
    ActionSetupError, CancelError, FeedbackError, FeedbackPublishError, GetResultError,
    SendGoalError,
};
pub use goal_state::{GoalEvent, GoalState, InvalidTransition};
pub use horus_ros_msgs::action_msgs::msg::GoalInfo;
pub use horus_ros_msgs::Action;
pub use horus_ros_services::{EndpointBuilder, EndpointOptions};
pub use server::{
    ActionServer, ActionServerBuilder, CancelRequestInfo, CancelResponse, GoalResponse,
    GoalTransitionError, ServerGoalHandle, DEFAULT_MAX_ACTIVE_GOALS, DEFAULT_MAX_RETAINED_RESULTS,
};

/// Everything an application needs, in one import.
pub mod prelude {
    pub use crate::{
        Action, ActionClient, ActionServer, CancelResponse, ClientGoalHandle, EndpointBuilder,
        GoalId, GoalResponse, GoalState, ServerGoalHandle,
    };
    pub use horus_ros_rmw::{Context, Node};
    pub use std::time::Duration;
}

#[doc(hidden)]
pub mod __private {
    pub use horus_ros_services::__private::{horus_ros_msgs, names, pastey};
    pub use horus_ros_services::service;
}
