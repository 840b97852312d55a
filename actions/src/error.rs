//! Errors: one enum per operation.

use horus_ros_services::{SetupError, TransportError};

/// Why an action server or client could not be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ActionSetupError {
    /// One of the three services (its server or client) could not be created.
    #[error(transparent)]
    Service(#[from] SetupError),
    /// The feedback or status topic's endpoint could not be created.
    #[error(transparent)]
    Endpoint(#[from] horus_ros_rmw::EndpointError),
    /// The graph of the node's context could not be followed.
    #[error(transparent)]
    Graph(#[from] horus_ros_graph::GraphStartError),
    /// A thread of the server or client could not be started.
    #[error("could not start the action's thread: {0}")]
    Thread(std::io::Error),
    /// The server builder was given no execute callback.
    #[error("an action server needs an execute callback: call .execute(..) before .build()")]
    NoExecuteCallback,
}

/// Why feedback could not be published.
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct FeedbackPublishError(#[from] pub horus_ros_rmw::PublishError);

/// Why a goal was not accepted ([`ActionClient::send_goal`](crate::ActionClient::send_goal)).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SendGoalError {
    /// The server rejected the goal (`accepted = false`).
    #[error("the action server rejected the goal")]
    Rejected,
    /// No response within the timeout.
    #[error("the goal request timed out")]
    Timeout,
    /// No action server of this name and type is on the graph.
    #[error("no action server is available")]
    NoServer,
    /// The request or response could not be sent or received, or the server left before
    /// answering ([`TransportError::ServerGone`]).
    #[error("goal request transport error: {0}")]
    Transport(TransportError),
}

/// Why a goal's result could not be had ([`ClientGoalHandle::get_result`](crate::ClientGoalHandle::get_result)).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GetResultError {
    /// No result within the timeout (the goal may still be running).
    #[error("the result request timed out")]
    Timeout,
    /// The server does not know the goal (`STATUS_UNKNOWN`: never accepted, or its result
    /// expired).
    #[error("the action server does not know the goal (or its result expired)")]
    UnknownGoal,
    /// No action server is on the graph.
    #[error("no action server is available")]
    NoServer,
    /// The action server left the graph before the goal ended (or before answering).
    #[error("the action server left the graph")]
    ServerGone,
    /// The request or response could not be sent or received.
    #[error("result request transport error: {0}")]
    Transport(TransportError),
}

/// Why a cancel request did not cancel ([`ClientGoalHandle::cancel`](crate::ClientGoalHandle::cancel),
/// [`ActionClient::cancel_all`](crate::ActionClient::cancel_all)): the response codes of
/// `action_msgs/srv/CancelGoal` but `ERROR_NONE`, and the call's failures.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CancelError {
    /// `ERROR_REJECTED`: the server refused (or found nothing to cancel).
    #[error("the action server rejected the cancel request")]
    Rejected,
    /// `ERROR_UNKNOWN_GOAL_ID`: the server does not know the goal.
    #[error("the action server does not know the goal")]
    UnknownGoal,
    /// `ERROR_GOAL_TERMINATED`: the goal has already ended.
    #[error("the goal has already ended")]
    GoalTerminated,
    /// A return code `action_msgs/srv/CancelGoal` does not define.
    #[error("the action server answered return code {0}")]
    Other(i8),
    /// No response within the timeout.
    #[error("the cancel request timed out")]
    Timeout,
    /// No action server is on the graph.
    #[error("no action server is available")]
    NoServer,
    /// The request or response could not be sent or received, or the server left.
    #[error("cancel request transport error: {0}")]
    Transport(TransportError),
}

/// Why no feedback came ([`ClientGoalHandle::recv_feedback`](crate::ClientGoalHandle::recv_feedback)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FeedbackError {
    /// None within the timeout.
    #[error("no feedback within the timeout")]
    Timeout,
    /// The goal has ended (its status is terminal) and every feedback received was taken.
    #[error("the goal has ended")]
    GoalEnded,
    /// The action server left the graph.
    #[error("the action server left the graph")]
    ServerGone,
}

/// Maps a call's error into one operation's error.
pub(crate) fn from_service_error<E>(
    e: horus_ros_services::ServiceError,
    timeout: E,
    no_server: E,
    transport: impl FnOnce(TransportError) -> E,
) -> E {
    use horus_ros_services::ServiceError as S;
    match e {
        S::Timeout => timeout,
        S::NoServer => no_server,
        S::ServiceFailed(message) => transport(TransportError::ServiceFailed(message)),
        S::Transport(t) => transport(t),
    }
}
