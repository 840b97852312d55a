//! What a node can reach from its own `init`, `tick` and `shutdown`: its ROS node, its
//! parameters, and services and actions served or called without blocking the tick.
//!
//! ```no_run
//! use horus::prelude::*;
//! use horus::msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsResponse};
//!
//! struct Adder { server: Option<horus::current::ServiceQueue<AddTwoInts>> }
//!
//! impl Node for Adder {
//!     fn init(&mut self) -> Result<()> {
//!         self.server = Some(horus::current::serve::<AddTwoInts>("add_two_ints")?);
//!         Ok(())
//!     }
//!     fn tick(&mut self) {
//!         if let Some(server) = &self.server {
//!             while let Some(request) = server.try_recv() {
//!                 let sum = request.request().a + request.request().b;
//!                 request.respond(AddTwoIntsResponse { sum });
//!             }
//!         }
//!     }
//! }
//! ```

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use horus_ros_actions::{
    Action, ActionClient, ActionServer, ActionSetupError, CancelResponse, GoalResponse,
    ServerGoalHandle,
};
use horus_ros_msgs::rcl_interfaces::msg::{ParameterType, ParameterValue};
use horus_ros_msgs::Service;
use horus_ros_rmw::Node as RosNode;
use horus_ros_services::{AsyncServiceClient, AsyncServiceServer, EndpointBuilder, SetupError};
use tokio::sync::oneshot;

use crate::api::runtime::current;

/// Why something of the current node could not be reached or created.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum CurrentNodeError {
    /// Not called from a scheduled node's `init`, `tick` or `shutdown`.
    #[error("not called from a scheduled node (init, tick or shutdown)")]
    NoNode,
    /// The node's scheduler runs without ROS.
    #[error("node '{0}' has no ROS side (its scheduler runs without ROS)")]
    NoRos(String),
    /// The service server or client could not be created (the cause is the error's source).
    #[error("could not create the service server or client: {0}")]
    Setup(Arc<SetupError>),
    /// The action server or client could not be created.
    #[error("could not create the action server or client: {0}")]
    ActionSetup(Arc<ActionSetupError>),
}

impl From<ActionSetupError> for CurrentNodeError {
    fn from(error: ActionSetupError) -> Self {
        Self::ActionSetup(Arc::new(error))
    }
}

impl From<SetupError> for CurrentNodeError {
    fn from(error: SetupError) -> Self {
        Self::Setup(Arc::new(error))
    }
}

/// The HORUS name of the node running on this thread.
pub fn name() -> Option<String> {
    current().map(|r| r.name.clone())
}

/// The ROS node of the node running on this thread.
pub fn ros_node() -> Result<RosNode, CurrentNodeError> {
    let runtime = current().ok_or(CurrentNodeError::NoNode)?;
    let ros = runtime
        .ros()
        .ok_or_else(|| CurrentNodeError::NoRos(runtime.name.clone()))?;
    Ok(ros.node().clone())
}

/// A parameter of the current node (given with `--ros-args -p name:=value` or in a
/// `--params-file`, or set with `ros2 param set`).
pub fn parameter(name: &str) -> Option<ParameterValue> {
    current()?.ros()?.parameter(name)
}

/// A Rust value a parameter can hold.
pub trait FromParameter: Sized {
    /// The value, if the parameter has this type.
    fn from_parameter(value: &ParameterValue) -> Option<Self>;
}

impl FromParameter for bool {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        (v.r#type == ParameterType::PARAMETER_BOOL).then_some(v.bool_value)
    }
}

impl FromParameter for i64 {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        (v.r#type == ParameterType::PARAMETER_INTEGER).then_some(v.integer_value)
    }
}

impl FromParameter for f64 {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        match v.r#type {
            ParameterType::PARAMETER_DOUBLE => Some(v.double_value),
            // rclcpp refuses this; a robot program usually means it.
            ParameterType::PARAMETER_INTEGER => Some(v.integer_value as f64),
            _ => None,
        }
    }
}

impl FromParameter for String {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        (v.r#type == ParameterType::PARAMETER_STRING).then(|| v.string_value.clone())
    }
}

/// The current node's parameter `name` as a `T`, or `default` when it is not set or not a `T`.
pub fn parameter_or<T: FromParameter>(name: &str, default: T) -> T {
    parameter(name)
        .and_then(|v| T::from_parameter(&v))
        .unwrap_or(default)
}

/// A non-blocking client of service `name` (relative names resolve under the current node):
/// `call_async` in one tick, `PendingResponse::check` in the next ones.
pub fn client<S: Service>(name: &str) -> Result<AsyncServiceClient<S>, CurrentNodeError> {
    let node = ros_node()?;
    AsyncServiceClient::<S>::builder()
        .node(&node)
        .name(name)
        .build()
        .map_err(CurrentNodeError::from)
}

/// How long a request waits for a tick to answer it before the server gives up on it (with an
/// error reply) when served with [`serve`].
pub const SERVE_TIMEOUT: Duration = Duration::from_secs(10);

/// The most requests of one [`ServiceQueue`] waiting for a tick at once; beyond, requests wait
/// in the DDS reader until earlier ones are answered or time out.
pub const SERVE_MAX_IN_FLIGHT: usize = 64;

/// Serves service `name` under the current node; requests are answered from `tick` (see
/// [`ServiceQueue`]) within [`SERVE_TIMEOUT`].
pub fn serve<S: Service>(name: &str) -> Result<ServiceQueue<S>, CurrentNodeError> {
    serve_with_timeout(name, SERVE_TIMEOUT)
}

/// [`serve`], with requests that no tick answered within `timeout` given an error reply (a
/// horus-ros client gets `ServiceFailed`; a ROS 2 client, which has no error reply, times out).
pub fn serve_with_timeout<S: Service>(
    name: &str,
    timeout: Duration,
) -> Result<ServiceQueue<S>, CurrentNodeError> {
    let node = ros_node()?;
    let handle = serve_runtime().map_err(SetupError::Thread)?;
    // Requests the node has not taken yet: at most SERVE_MAX_IN_FLIGHT live ones (the server's
    // bound on handlers in flight); one whose wait ended untaken is dropped at the next push.
    let waiting: Waiting<S> = Arc::new(Mutex::new(VecDeque::new()));
    let queue = Arc::clone(&waiting);
    let server = AsyncServiceServer::<S>::builder()
        .node(&node)
        .name(name)
        .on_request(move |request| {
            // The server's thread only hands the request over; its answer is awaited on the
            // serve runtime, so other requests go on being served meanwhile.
            let (reply, answer) = oneshot::channel();
            let queued = {
                let mut waiting = lock(&queue);
                waiting.retain(|p: &PendingRequest<S>| !p.reply.is_closed());
                if waiting.len() < SERVE_MAX_IN_FLIGHT {
                    waiting.push_back(PendingRequest { request, reply });
                    Ok(())
                } else {
                    Err("the serving node has too many requests waiting")
                }
            };
            async move {
                queued.map_err(str::to_owned)?;
                match tokio::time::timeout(timeout, answer).await {
                    Ok(Ok(response)) => Ok(response),
                    Ok(Err(_)) => Err("the serving node dropped the request unanswered".to_owned()),
                    Err(_) => Err(format!(
                        "the serving node did not answer within {} ms",
                        timeout.as_millis()
                    )),
                }
            }
        })
        .runtime(handle)
        .max_in_flight(SERVE_MAX_IN_FLIGHT)
        .build()?;
    Ok(ServiceQueue {
        _server: server,
        requests: waiting,
    })
}

/// The runtime the answers of [`serve`]d requests are awaited on: one thread for the process,
/// started at the first `serve`, woken by answers and timers only.
fn serve_runtime() -> std::io::Result<tokio::runtime::Handle> {
    static HANDLE: Mutex<Option<tokio::runtime::Handle>> = Mutex::new(None);
    let mut slot = HANDLE.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(handle) = &*slot {
        return Ok(handle.clone());
    }
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_time()
        .build()?;
    let handle = runtime.handle().clone();
    std::thread::Builder::new()
        .name("horus-serve".to_owned())
        .spawn(move || runtime.block_on(std::future::pending::<()>()))?;
    *slot = Some(handle.clone());
    Ok(handle)
}

/// A service served from `tick`: the server's thread hands each request over and never waits
/// for the answer; `tick` takes requests with [`try_recv`](Self::try_recv) (never blocks) and
/// answers them with [`PendingRequest::respond`]. At most [`SERVE_MAX_IN_FLIGHT`] requests wait
/// for a tick at once, each until its timeout ([`SERVE_TIMEOUT`] unless
/// [`serve_with_timeout`] says otherwise), after which its client gets an error reply.
pub struct ServiceQueue<S: Service> {
    _server: AsyncServiceServer<S>,
    requests: Waiting<S>,
}

/// The requests of a [`ServiceQueue`] waiting for a tick, oldest first.
type Waiting<S> = Arc<Mutex<VecDeque<PendingRequest<S>>>>;

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl<S: Service> std::fmt::Debug for ServiceQueue<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServiceQueue")
            .field("service", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> ServiceQueue<S> {
    /// The next request waiting for an answer, if any (requests whose wait already ended, by
    /// timeout, are skipped).
    pub fn try_recv(&self) -> Option<PendingRequest<S>> {
        let mut waiting = lock(&self.requests);
        while let Some(pending) = waiting.pop_front() {
            if !pending.reply.is_closed() {
                return Some(pending);
            }
        }
        None
    }
}

/// A request waiting for the node's answer.
pub struct PendingRequest<S: Service> {
    request: S::Request,
    reply: oneshot::Sender<S::Response>,
}

impl<S: Service> PendingRequest<S> {
    /// The request.
    pub fn request(&self) -> &S::Request {
        &self.request
    }

    /// Sends the response (dropped if the request has timed out meanwhile).
    pub fn respond(self, response: S::Response) {
        let _ = self.reply.send(response);
    }
}

/// A non-blocking client of action `name` (relative names resolve under the current node):
/// `send_goal_pending` in one tick and `PendingGoal::try_take` in the next ones, then the goal
/// handle's `try_recv_feedback` and `get_result_pending` — no call blocks the tick.
pub fn action_client<A: Action>(name: &str) -> Result<ActionClient<A>, CurrentNodeError> {
    let node = ros_node()?;
    Ok(ActionClient::<A>::builder()
        .node(&node)
        .name(name)
        .build()?)
}

/// The most goals of one [`GoalQueue`] waiting for a tick to take them; beyond, new goals are
/// rejected (the client learns it at once).
pub const ACTION_MAX_WAITING: usize = 64;

/// Serves action `name` under the current node, its goals executed from `tick` (see
/// [`GoalQueue`]): every goal is accepted while fewer than [`ACTION_MAX_WAITING`] wait to be
/// taken, and every cancel request is accepted (the tick sees it as
/// [`ServerGoalHandle::is_cancel_requested`] and ends the goal with `canceled`).
pub fn action_server<A: Action>(name: &str) -> Result<GoalQueue<A>, CurrentNodeError> {
    let node = ros_node()?;
    let goals: WaitingGoals<A> = Arc::new(Mutex::new(VecDeque::new()));
    let (for_goal, for_execute) = (Arc::clone(&goals), Arc::clone(&goals));
    let server = ActionServer::<A>::builder()
        .node(&node)
        .name(name)
        .on_goal(move |_id, _goal| {
            if lock(&for_goal).len() < ACTION_MAX_WAITING {
                GoalResponse::Accept
            } else {
                GoalResponse::Reject
            }
        })
        .on_cancel(|_| CancelResponse::Accept)
        // The execution only hands the goal over: the handle keeps the goal active until the
        // node ends it (a handle dropped while active aborts its goal).
        .execute(move |handle| lock(&for_execute).push_back(handle))
        .build()?;
    Ok(GoalQueue {
        _server: server,
        goals,
    })
}

/// The goals of a [`GoalQueue`] waiting for a tick, oldest first.
type WaitingGoals<A> = Arc<Mutex<VecDeque<ServerGoalHandle<A>>>>;

/// An action served from `tick`: the server's threads hand each accepted goal over and never
/// wait for the node; `tick` takes goals with [`try_recv`](Self::try_recv) (never blocks), keeps
/// their handles, publishes feedback and ends each goal (`succeed`, `abort`, `canceled`) in the
/// ticks it takes.
pub struct GoalQueue<A: Action> {
    _server: ActionServer<A>,
    goals: WaitingGoals<A>,
}

impl<A: Action> std::fmt::Debug for GoalQueue<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GoalQueue")
            .field("action", &A::TYPE_NAME)
            .finish()
    }
}

impl<A: Action> GoalQueue<A> {
    /// The next accepted goal, if any.
    pub fn try_recv(&self) -> Option<ServerGoalHandle<A>> {
        lock(&self.goals).pop_front()
    }
}
