//! [`ActionServer`]: serves an action as rcl_action and rclpy's `ActionServer` do
//! (rcl_action `action_server.c`, rclpy `rclpy/action/server.py`).
//!
//! One thread takes the three services' requests (woken by them, and at the next result
//! expiry); each accepted goal runs its execute callback on a thread of its own, bounded by
//! [`ActionServerBuilder::max_active_goals`].

use std::marker::PhantomData;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::task::Waker;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_msgs::action_msgs::msg::{GoalInfo, GoalStatus, GoalStatusArray};
use horus_ros_msgs::action_msgs::srv::{CancelGoal, CancelGoalRequest, CancelGoalResponse};
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::unique_identifier_msgs::msg::UUID;
use horus_ros_msgs::{Action, Service};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Node, Publisher};
use horus_ros_services::{
    DdsServiceServer, EndpointBuilder, EndpointOptions, ServiceServerTrait, TransportError,
};

use crate::common::{
    feedback_qos, lock, stamp_nanos, status_qos, ActionNames, GoalId, Notify, NotifyWaker,
    DEFAULT_RESULT_TIMEOUT,
};
use crate::error::{ActionSetupError, FeedbackPublishError};
use crate::goal_state::{GoalEvent, GoalState, InvalidTransition};

/// What the goal callback answers (rclpy `GoalResponse`, rclcpp `GoalResponse`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalResponse {
    /// Accept the goal: it is executed.
    Accept,
    /// Reject the goal: the client is told `accepted = false`.
    Reject,
}

/// What the cancel callback answers (rclpy `CancelResponse`, rclcpp `CancelResponse`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CancelResponse {
    /// Accept the request: the goal goes to CANCELING, and its execution sees
    /// [`ServerGoalHandle::is_cancel_requested`].
    Accept,
    /// Reject the request: the goal goes on as it was.
    Reject,
}

/// Most goals executing at once by default (beyond, new goals are rejected).
pub const DEFAULT_MAX_ACTIVE_GOALS: usize = 256;
/// Most ended goals whose results are kept by default (beyond, the oldest expire early).
pub const DEFAULT_MAX_RETAINED_RESULTS: usize = 4096;
/// Most `get_result` requests waiting for one goal to end (beyond, the oldest is answered at
/// once with the goal's state and an empty result).
const MAX_WAITING_RESULT_REQUESTS: usize = 64;

type GoalCallback<A> = dyn Fn(GoalId, &<A as Action>::Goal) -> GoalResponse + Send + Sync;
type CancelCallback<A> = dyn Fn(&CancelRequestInfo<A>) -> CancelResponse + Send + Sync;
type ExecuteCallback<A> = dyn Fn(ServerGoalHandle<A>) + Send + Sync;

/// What the cancel callback is shown of a goal a client asked to cancel.
#[derive(Debug, Clone)]
pub struct CancelRequestInfo<A: Action> {
    /// The goal's id.
    pub goal_id: GoalId,
    /// The goal.
    pub goal: A::Goal,
    /// Its state when the request came (ACCEPTED or EXECUTING).
    pub state: GoalState,
}

/// Builds an [`ActionServer`] ([`ActionServer::builder`]). Node, action name, the three
/// services' QoS and wire convention are set with the [`EndpointBuilder`] setters; the rest
/// with this builder's methods. Only [`execute`](Self::execute) is required.
#[must_use = "a builder does nothing until .build() is called"]
pub struct ActionServerBuilder<A: Action> {
    options: EndpointOptions,
    feedback_qos: Qos,
    status_qos: Qos,
    result_timeout: Duration,
    max_active_goals: usize,
    max_retained_results: usize,
    on_goal: Option<Box<GoalCallback<A>>>,
    on_cancel: Option<Box<CancelCallback<A>>>,
    execute: Option<Arc<ExecuteCallback<A>>>,
}

impl<A: Action> EndpointBuilder for ActionServerBuilder<A> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options
    }
}

impl<A: Action> ActionServerBuilder<A> {
    /// The callback deciding whether to accept a goal (default: accept every goal, as rclpy's
    /// `default_goal_callback`). Runs on the server's thread: keep it short.
    pub fn on_goal(
        mut self,
        callback: impl Fn(GoalId, &A::Goal) -> GoalResponse + Send + Sync + 'static,
    ) -> Self {
        self.on_goal = Some(Box::new(callback));
        self
    }

    /// The callback deciding whether to accept a request to cancel a goal (default: reject
    /// every request, as rclpy's `default_cancel_callback`). Runs on the server's thread.
    pub fn on_cancel(
        mut self,
        callback: impl Fn(&CancelRequestInfo<A>) -> CancelResponse + Send + Sync + 'static,
    ) -> Self {
        self.on_cancel = Some(Box::new(callback));
        self
    }

    /// The callback executing an accepted goal, on a thread of its own. It ends the goal with
    /// [`ServerGoalHandle::succeed`], [`abort`](ServerGoalHandle::abort) or
    /// [`canceled`](ServerGoalHandle::canceled); a goal it leaves active (or a panic) is
    /// aborted with a default result, as rclpy does ("Goal state not set, assuming aborted").
    pub fn execute(
        mut self,
        callback: impl Fn(ServerGoalHandle<A>) + Send + Sync + 'static,
    ) -> Self {
        self.execute = Some(Arc::new(callback));
        self
    }

    /// How long a result is kept after its goal ended (rcl_action `result_timeout`, default
    /// 900 s): `get_result` for an expired goal is answered `STATUS_UNKNOWN`.
    pub fn result_timeout(mut self, timeout: Duration) -> Self {
        self.result_timeout = timeout;
        self
    }

    /// The feedback topic's QoS (default: reliable, volatile, keep last 10).
    pub fn feedback_qos(mut self, qos: Qos) -> Self {
        self.feedback_qos = qos;
        self
    }

    /// The status topic's QoS (default: `rcl_action_qos_profile_status_default`).
    pub fn status_qos(mut self, qos: Qos) -> Self {
        self.status_qos = qos;
        self
    }

    /// Most goals executing at once (default [`DEFAULT_MAX_ACTIVE_GOALS`]): beyond, new goals
    /// are rejected without asking the goal callback.
    pub fn max_active_goals(mut self, max: usize) -> Self {
        self.max_active_goals = max.max(1);
        self
    }

    /// Most ended goals kept for `get_result` (default [`DEFAULT_MAX_RETAINED_RESULTS`]):
    /// beyond, the oldest expire before their `result_timeout`.
    pub fn max_retained_results(mut self, max: usize) -> Self {
        self.max_retained_results = max;
        self
    }

    /// Creates the three services and two publishers and starts the server's thread.
    pub fn build(self) -> Result<ActionServer<A>, ActionSetupError> {
        let execute = self.execute.ok_or(ActionSetupError::NoExecuteCallback)?;
        let node = match self.options.configured_node() {
            Some(node) => node.clone(),
            None => horus_ros_services::default_node()?,
        };
        let action = self
            .options
            .configured_name()
            .map(str::to_owned)
            .unwrap_or_else(default_action_name::<A>);
        let names = ActionNames::of(&action);
        let service = |name: &str| self.options.clone().node(&node).name(name);
        let send_goal = DdsServiceServer::<A::SendGoal>::builder()
            .options(service(&names.send_goal))
            .build()?;
        let cancel_goal = DdsServiceServer::<CancelGoal>::builder()
            .options(service(&names.cancel_goal))
            .build()?;
        let get_result = DdsServiceServer::<A::GetResult>::builder()
            .options(service(&names.get_result))
            .build()?;
        let feedback =
            node.create_publisher::<A::FeedbackMessage>(&names.feedback, &self.feedback_qos)?;
        let status = node.create_publisher::<GoalStatusArray>(&names.status, &self.status_qos)?;
        let shared = Arc::new(Shared {
            action,
            node,
            goals: Mutex::new(Goals {
                list: Vec::new(),
                active: 0,
            }),
            get_result: Mutex::new(get_result),
            feedback,
            status,
            notify: Arc::new(Notify::default()),
            stop: AtomicBool::new(false),
            result_timeout: self.result_timeout,
            max_active_goals: self.max_active_goals,
            max_retained_results: self.max_retained_results,
            on_goal: self.on_goal,
            on_cancel: self.on_cancel,
            execute,
        });
        shared.publish_status(&lock(&shared.goals));
        let thread = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name(format!("horus-action{}", shared.action))
                .spawn(move || shared.run(send_goal, cancel_goal))
                .map_err(ActionSetupError::Thread)?
        };
        Ok(ActionServer {
            shared,
            thread: Some(thread),
        })
    }
}

/// The default action name: the action type's name in snake case, absolute
/// (`test_msgs/action/Fibonacci` → `/fibonacci`), as services name themselves.
pub(crate) fn default_action_name<A: Action>() -> String {
    use heck::ToSnakeCase as _;
    let short = A::TYPE_NAME.rsplit('/').next().unwrap_or(A::TYPE_NAME);
    format!("/{}", short.to_snake_case())
}

/// An action server: accepts goals, executes them, answers cancel and result requests, and
/// publishes feedback and the goals' status, as rcl_action's server does. Dropping it stops
/// its thread and withdraws the goal and cancel services at once; executions still running
/// finish on their threads, and the feedback and status publishers and the result service
/// (answering the results they end with) go when the last of them has.
#[must_use = "an action server exists only while it is held"]
pub struct ActionServer<A: Action> {
    shared: Arc<Shared<A>>,
    thread: Option<JoinHandle<()>>,
}

impl<A: Action> std::fmt::Debug for ActionServer<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ActionServer")
            .field("action", &self.shared.action)
            .field("type", &A::TYPE_NAME)
            .finish()
    }
}

impl<A: Action> ActionServer<A> {
    /// A builder to choose node, name, callbacks, QoS and result timeout.
    pub fn builder() -> ActionServerBuilder<A> {
        ActionServerBuilder {
            options: EndpointOptions::default(),
            feedback_qos: feedback_qos(),
            status_qos: status_qos(),
            result_timeout: DEFAULT_RESULT_TIMEOUT,
            max_active_goals: DEFAULT_MAX_ACTIVE_GOALS,
            max_retained_results: DEFAULT_MAX_RETAINED_RESULTS,
            on_goal: None,
            on_cancel: None,
            execute: None,
        }
    }

    /// The action name, as given (or the default).
    pub fn action_name(&self) -> &str {
        &self.shared.action
    }

    /// The node the server's entities live on.
    pub fn node(&self) -> &Node {
        &self.shared.node
    }

    /// The goals the server knows (active, and ended with their results still kept), in the
    /// order they were accepted, with their states.
    pub fn goals(&self) -> Vec<(GoalId, GoalState)> {
        lock(&self.shared.goals)
            .list
            .iter()
            .map(|g| (g.id, g.state))
            .collect()
    }
}

impl<A: Action> Drop for ActionServer<A> {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.shared.notify.notify();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// One goal the server knows.
struct Goal<A: Action> {
    id: GoalId,
    stamp: Time,
    goal: A::Goal,
    state: GoalState,
    /// The result, once the goal ended.
    result: Option<A::Result>,
    /// `get_result` requests waiting for the goal to end (their sequence numbers).
    waiting: Vec<i64>,
    /// When the result expires (set when the goal ends).
    expires: Option<Instant>,
}

struct Goals<A: Action> {
    /// In the order of acceptance (the order of rcl_action's goal handles and status array).
    list: Vec<Goal<A>>,
    /// How many are active (ACCEPTED, EXECUTING, CANCELING).
    active: usize,
}

impl<A: Action> Goals<A> {
    fn find(&mut self, id: GoalId) -> Option<&mut Goal<A>> {
        self.list.iter_mut().find(|g| g.id == id)
    }
}

struct Shared<A: Action> {
    action: String,
    node: Node,
    goals: Mutex<Goals<A>>,
    /// Locked after `goals` when both are.
    get_result: Mutex<DdsServiceServer<A::GetResult>>,
    feedback: Publisher<A::FeedbackMessage>,
    status: Publisher<GoalStatusArray>,
    notify: Arc<Notify>,
    stop: AtomicBool,
    result_timeout: Duration,
    max_active_goals: usize,
    max_retained_results: usize,
    on_goal: Option<Box<GoalCallback<A>>>,
    on_cancel: Option<Box<CancelCallback<A>>>,
    execute: Arc<ExecuteCallback<A>>,
}

/// A request taken from one of the servers, decoded.
fn take<S: Service, T: ServiceServerTrait<Error = TransportError>>(
    server: &mut T,
    buf: &mut Vec<u8>,
    action: &str,
) -> Option<(i64, S::Request)> {
    loop {
        match server.try_recv_request(buf) {
            Ok(Some(request)) => {
                let seq = request.sequence_number;
                match horus_ros_msgs::cdr::from_cdr::<S::Request>(request.data) {
                    Ok(r) => return Some((seq, r)),
                    Err(e) => {
                        tracing::warn!(action, "undecodable {} request: {e}", S::TYPE_NAME);
                        continue;
                    }
                }
            }
            Ok(None) => return None,
            Err(TransportError::BufferTooSmall { needed, .. }) => buf.resize(needed, 0),
            Err(e) => {
                tracing::warn!(action, "taking a {} request failed: {e}", S::TYPE_NAME);
                return None;
            }
        }
    }
}

/// Sends `response` as the reply to request `seq`.
fn reply<S: Service, T: ServiceServerTrait<Error = TransportError>>(
    server: &mut T,
    seq: i64,
    response: &S::Response,
    action: &str,
) {
    let sent = horus_ros_msgs::cdr::to_cdr(response)
        .map_err(|e| TransportError::Serialization(e.to_string()))
        .and_then(|bytes| server.send_reply(seq, &bytes));
    if let Err(e) = sent {
        // As rclpy: the client may have gone away.
        tracing::warn!(action, "sending a {} response failed: {e}", S::TYPE_NAME);
    }
}

impl<A: Action> Shared<A> {
    /// The server's thread: takes requests until the server is dropped.
    fn run(
        self: Arc<Self>,
        mut send_goal: DdsServiceServer<A::SendGoal>,
        mut cancel_goal: DdsServiceServer<CancelGoal>,
    ) {
        let waker = Waker::from(Arc::new(NotifyWaker(Arc::clone(&self.notify))));
        let mut buf = vec![0u8; 4096];
        while !self.stop.load(Ordering::SeqCst) {
            // Registered before draining: a request arriving meanwhile wakes the next wait.
            send_goal.register_waker(&waker);
            cancel_goal.register_waker(&waker);
            lock(&self.get_result).register_waker(&waker);
            while let Some((seq, request)) =
                take::<A::SendGoal, _>(&mut send_goal, &mut buf, &self.action)
            {
                self.handle_goal(&mut send_goal, seq, request);
            }
            while let Some((seq, request)) =
                take::<CancelGoal, _>(&mut cancel_goal, &mut buf, &self.action)
            {
                self.handle_cancel(&mut cancel_goal, seq, &request);
            }
            loop {
                let taken =
                    take::<A::GetResult, _>(&mut *lock(&self.get_result), &mut buf, &self.action);
                let Some((seq, request)) = taken else { break };
                self.handle_result_request(seq, &request);
            }
            let next_expiry = self.expire();
            if self.stop.load(Ordering::SeqCst) {
                break;
            }
            self.notify.wait(next_expiry);
        }
    }

    /// A `send_goal` request: rclpy `_execute_goal_request`.
    fn handle_goal(
        self: &Arc<Self>,
        server: &mut DdsServiceServer<A::SendGoal>,
        seq: i64,
        request: <A::SendGoal as Service>::Request,
    ) {
        let (id, goal) = A::split_goal_request(request);
        let id = GoalId(id);
        let stamp = Time::now();
        let mut goals = lock(&self.goals);
        let accepted = if goals.find(id).is_some() {
            // rclpy: "Received goal with existing ID"; rejected.
            tracing::warn!(action = %self.action, goal = %id, "goal id already in use: rejected");
            false
        } else if goals.active >= self.max_active_goals {
            tracing::warn!(action = %self.action, goal = %id, "{} goals active: rejected", goals.active);
            false
        } else {
            drop(goals);
            let answer = match &self.on_goal {
                None => GoalResponse::Accept,
                Some(cb) => catch_unwind(AssertUnwindSafe(|| cb(id, &goal))).unwrap_or_else(|_| {
                    tracing::error!(action = %self.action, goal = %id, "the goal callback panicked: goal rejected");
                    GoalResponse::Reject
                }),
            };
            goals = lock(&self.goals);
            answer == GoalResponse::Accept
        };
        let response = A::create_goal_response(accepted, (stamp.sec, stamp.nanosec));
        if !accepted {
            drop(goals);
            reply::<A::SendGoal, _>(server, seq, &response, &self.action);
            return;
        }
        goals.list.push(Goal {
            id,
            stamp,
            goal: goal.clone(),
            state: GoalState::Accepted,
            result: None,
            waiting: Vec::new(),
            expires: None,
        });
        goals.active += 1;
        // The response first, then the status, then execution (rclpy's order).
        reply::<A::SendGoal, _>(server, seq, &response, &self.action);
        self.publish_status(&goals);
        drop(goals);
        let handle = ServerGoalHandle {
            shared: Arc::clone(self),
            id,
            goal,
            ended: false,
            _action: PhantomData,
        };
        let execute = Arc::clone(&self.execute);
        let action = self.action.clone();
        let spawned = std::thread::Builder::new()
            .name(format!("horus-goal-{}", &id.to_string()[..8]))
            .spawn(move || {
                handle.start_executing();
                if catch_unwind(AssertUnwindSafe(move || execute(handle))).is_err() {
                    // The handle, dropped in the unwind, aborted the goal.
                    tracing::error!(action = %action, goal = %id, "the execute callback panicked: goal aborted");
                }
            });
        if let Err(e) = spawned {
            // The closure (and the handle in it) is dropped: the goal is aborted.
            tracing::error!(action = %self.action, goal = %id, "could not start the goal's thread: {e}");
        }
    }

    /// A `cancel_goal` request: `rcl_action_process_cancel_request`, then the cancel callback
    /// for each goal found, as rclpy's `_execute_cancel_request` and rclcpp's
    /// `ServerBase::execute_cancel_request_received` (a request whose every goal the callback
    /// rejected is answered `ERROR_REJECTED`, as rclcpp does).
    fn handle_cancel(
        &self,
        server: &mut DdsServiceServer<CancelGoal>,
        seq: i64,
        request: &CancelGoalRequest,
    ) {
        let (return_code, candidates) = {
            let mut goals = lock(&self.goals);
            process_cancel_request(&mut goals.list, &request.goal_info)
        };
        let mut canceling = Vec::new();
        for (id, goal, state, stamp) in &candidates {
            let info = CancelRequestInfo {
                goal_id: *id,
                goal: goal.clone(),
                state: *state,
            };
            let answer = match &self.on_cancel {
                None => CancelResponse::Reject,
                Some(cb) => catch_unwind(AssertUnwindSafe(|| cb(&info))).unwrap_or_else(|_| {
                    tracing::error!(action = %self.action, goal = %id, "the cancel callback panicked: cancel rejected");
                    CancelResponse::Reject
                }),
            };
            if answer == CancelResponse::Accept {
                let mut goals = lock(&self.goals);
                // The goal may have ended meanwhile (rclpy: "Failed to cancel goal").
                if let Some(g) = goals.find(*id) {
                    if let Ok(next) = g.state.transition(GoalEvent::CancelGoal) {
                        g.state = next;
                        canceling.push(GoalInfo {
                            goal_id: UUID { uuid: id.0 },
                            stamp: *stamp,
                        });
                        self.publish_status(&goals);
                    }
                }
            }
        }
        let return_code = if !candidates.is_empty() && canceling.is_empty() {
            CancelGoalResponse::ERROR_REJECTED
        } else {
            return_code
        };
        let response = CancelGoalResponse {
            return_code,
            goals_canceling: canceling,
        };
        reply::<CancelGoal, _>(server, seq, &response, &self.action);
    }

    /// A `get_result` request: answered at once for an ended goal (its status and result) and
    /// an unknown one (`STATUS_UNKNOWN`), when it ends for an active one (rclpy
    /// `_execute_get_result_request`).
    fn handle_result_request(&self, seq: i64, request: &<A::GetResult as Service>::Request) {
        let id = GoalId(A::result_request_goal_id(request));
        let mut goals = lock(&self.goals);
        let answer = match goals.find(id) {
            None => Some(A::create_result_response(
                GoalStatus::STATUS_UNKNOWN,
                A::Result::default(),
            )),
            Some(g) => match &g.result {
                Some(result) => Some(A::create_result_response(g.state.status(), result.clone())),
                None => {
                    if g.waiting.len() >= MAX_WAITING_RESULT_REQUESTS {
                        let oldest = g.waiting.remove(0);
                        let response =
                            A::create_result_response(g.state.status(), A::Result::default());
                        reply::<A::GetResult, _>(
                            &mut *lock(&self.get_result),
                            oldest,
                            &response,
                            &self.action,
                        );
                    }
                    g.waiting.push(seq);
                    None
                }
            },
        };
        if let Some(response) = answer {
            reply::<A::GetResult, _>(&mut *lock(&self.get_result), seq, &response, &self.action);
        }
        drop(goals);
    }

    /// Drops the ended goals whose results expired (and the oldest beyond the retention bound);
    /// returns when the next result expires.
    fn expire(&self) -> Option<Instant> {
        let mut goals = lock(&self.goals);
        let now = Instant::now();
        let ended = goals.list.iter().filter(|g| g.expires.is_some()).count();
        let mut over = ended.saturating_sub(self.max_retained_results);
        let before = goals.list.len();
        goals.list.retain(|g| match g.expires {
            Some(at) if at <= now => false,
            Some(_) if over > 0 => {
                over -= 1;
                false
            }
            _ => true,
        });
        if goals.list.len() != before {
            self.publish_status(&goals);
        }
        goals.list.iter().filter_map(|g| g.expires).min()
    }

    /// Publishes every goal's status (rcl_action `rcl_action_get_goal_status_array`, in the
    /// order the goals were accepted).
    fn publish_status(&self, goals: &Goals<A>) {
        let message = GoalStatusArray {
            status_list: goals
                .list
                .iter()
                .map(|g| GoalStatus {
                    goal_info: GoalInfo {
                        goal_id: UUID { uuid: g.id.0 },
                        stamp: g.stamp,
                    },
                    status: g.state.status(),
                })
                .collect(),
        };
        if let Err(e) = self.status.publish(message) {
            tracing::warn!(action = %self.action, "publishing the goal status failed: {e}");
        }
    }

    /// Applies `event` to goal `id`; with a result, the goal ends and its waiting `get_result`
    /// requests are answered.
    fn transition(
        &self,
        id: GoalId,
        event: GoalEvent,
        result: Option<A::Result>,
    ) -> Result<(), GoalTransitionError> {
        let mut goals = lock(&self.goals);
        let goal = goals.find(id).ok_or(GoalTransitionError::UnknownGoal(id))?;
        let next = goal.state.transition(event)?;
        goal.state = next;
        let mut waiting = Vec::new();
        let mut ended = None;
        if next.is_terminal() {
            let result = result.unwrap_or_else(A::Result::default);
            waiting = std::mem::take(&mut goal.waiting);
            goal.expires = Some(Instant::now() + self.result_timeout);
            ended = Some(A::create_result_response(next.status(), result.clone()));
            goal.result = Some(result);
            goals.active = goals.active.saturating_sub(1);
        }
        self.publish_status(&goals);
        if let Some(response) = ended {
            let mut server = lock(&self.get_result);
            for seq in waiting {
                reply::<A::GetResult, _>(&mut *server, seq, &response, &self.action);
            }
            drop(server);
            // The expiry timer changed.
            self.notify.notify();
        }
        Ok(())
    }
}

/// The goals a cancel request names, as `rcl_action_process_cancel_request` finds them
/// (rcl_action `action_server.c`): with a goal id and no stamp, that goal (`ERROR_NONE` if
/// cancelable, `ERROR_GOAL_TERMINATED` if it ended, `ERROR_UNKNOWN_GOAL_ID` if unknown); else
/// `ERROR_NONE` and every cancelable goal accepted at or before the stamp, or with the id (a
/// zero id and zero stamp: every cancelable goal).
#[allow(clippy::type_complexity)]
fn process_cancel_request<A: Action>(
    goals: &mut [Goal<A>],
    request: &GoalInfo,
) -> (i8, Vec<(GoalId, A::Goal, GoalState, Time)>) {
    let id = GoalId(request.goal_id.uuid);
    let mut request_nanos = stamp_nanos(&request.stamp);
    let entry = |g: &Goal<A>| (g.id, g.goal.clone(), g.state, g.stamp);
    if !id.is_zero() && request_nanos == 0 {
        return match goals.iter().find(|g| g.id == id) {
            None => (CancelGoalResponse::ERROR_UNKNOWN_GOAL_ID, Vec::new()),
            Some(g) if g.state.is_cancelable() => (CancelGoalResponse::ERROR_NONE, vec![entry(g)]),
            Some(_) => (CancelGoalResponse::ERROR_GOAL_TERMINATED, Vec::new()),
        };
    }
    if id.is_zero() && request_nanos == 0 {
        request_nanos = i64::MAX;
    }
    let found = goals
        .iter()
        .filter(|g| {
            g.state.is_cancelable() && (stamp_nanos(&g.stamp) <= request_nanos || g.id == id)
        })
        .map(entry)
        .collect();
    (CancelGoalResponse::ERROR_NONE, found)
}

/// Why a goal could not be moved to a new state.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GoalTransitionError {
    /// The goal's state does not allow the event (rcl_action's goal state machine).
    #[error(transparent)]
    Invalid(#[from] InvalidTransition),
    /// The server no longer knows the goal (it was dropped).
    #[error("the server no longer knows goal {0}")]
    UnknownGoal(GoalId),
}

/// An accepted goal, given to the execute callback: its goal, feedback, the cancel request,
/// and the calls that end it (rclpy `ServerGoalHandle`, rclcpp `ServerGoalHandle`).
///
/// Dropped while the goal is active (the callback returned without ending it, or panicked),
/// it aborts the goal with a default result.
pub struct ServerGoalHandle<A: Action> {
    shared: Arc<Shared<A>>,
    id: GoalId,
    goal: A::Goal,
    ended: bool,
    _action: PhantomData<fn() -> A>,
}

impl<A: Action> std::fmt::Debug for ServerGoalHandle<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServerGoalHandle")
            .field("goal_id", &self.id)
            .field("goal", &self.goal)
            .finish()
    }
}

impl<A: Action> ServerGoalHandle<A> {
    /// The goal's id.
    pub fn goal_id(&self) -> GoalId {
        self.id
    }

    /// The goal.
    pub fn goal(&self) -> &A::Goal {
        &self.goal
    }

    /// The goal's state now.
    pub fn state(&self) -> GoalState {
        lock(&self.shared.goals)
            .find(self.id)
            .map(|g| g.state)
            .unwrap_or(GoalState::Aborted)
    }

    /// Whether a cancel request was accepted for the goal (it is CANCELING): the execution
    /// should stop and call [`canceled`](Self::canceled).
    pub fn is_cancel_requested(&self) -> bool {
        self.state() == GoalState::Canceling
    }

    /// Whether the goal is still active.
    pub fn is_active(&self) -> bool {
        self.state().is_active()
    }

    /// Publishes feedback for this goal on `<action>/_action/feedback`.
    pub fn publish_feedback(&self, feedback: A::Feedback) -> Result<(), FeedbackPublishError> {
        self.shared
            .feedback
            .publish(A::create_feedback_message(self.id.0, feedback))
            .map_err(FeedbackPublishError)
    }

    /// Ends the goal SUCCEEDED with `result` (valid from EXECUTING and CANCELING).
    pub fn succeed(mut self, result: A::Result) -> Result<(), GoalTransitionError> {
        self.end(GoalEvent::Succeed, result)
    }

    /// Ends the goal ABORTED with `result` (valid from EXECUTING and CANCELING).
    pub fn abort(mut self, result: A::Result) -> Result<(), GoalTransitionError> {
        self.end(GoalEvent::Abort, result)
    }

    /// Ends the goal CANCELED with `result` (valid from CANCELING only: after a cancel request
    /// was accepted).
    pub fn canceled(mut self, result: A::Result) -> Result<(), GoalTransitionError> {
        self.end(GoalEvent::Canceled, result)
    }

    fn end(&mut self, event: GoalEvent, result: A::Result) -> Result<(), GoalTransitionError> {
        self.shared.transition(self.id, event, Some(result))?;
        self.ended = true;
        Ok(())
    }

    /// ACCEPTED → EXECUTING as the execution starts (a goal already CANCELING stays so, and
    /// its execution sees the cancel request).
    fn start_executing(&self) {
        let accepted = lock(&self.shared.goals)
            .find(self.id)
            .is_some_and(|g| g.state == GoalState::Accepted);
        if accepted {
            let _ = self.shared.transition(self.id, GoalEvent::Execute, None);
        }
    }
}

impl<A: Action> Drop for ServerGoalHandle<A> {
    fn drop(&mut self) {
        if self.ended {
            return;
        }
        let state = self.state();
        if !state.is_active() {
            return;
        }
        tracing::warn!(action = %self.shared.action, goal = %self.id, "goal state not set, assuming aborted");
        if state == GoalState::Accepted {
            let _ = self.shared.transition(self.id, GoalEvent::Execute, None);
        }
        let _ = self
            .shared
            .transition(self.id, GoalEvent::Abort, Some(A::Result::default()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interfaces::test_msgs::action::{Fibonacci, FibonacciGoal};

    fn goal(byte: u8, sec: i32, state: GoalState) -> Goal<Fibonacci> {
        Goal {
            id: GoalId([byte; 16]),
            stamp: Time { sec, nanosec: 0 },
            goal: FibonacciGoal {
                order: i32::from(byte),
            },
            state,
            result: None,
            waiting: Vec::new(),
            expires: None,
        }
    }

    fn request(byte: u8, sec: i32) -> GoalInfo {
        GoalInfo {
            goal_id: UUID { uuid: [byte; 16] },
            stamp: Time { sec, nanosec: 0 },
        }
    }

    fn cancel(goals: &mut [Goal<Fibonacci>], byte: u8, sec: i32) -> (i8, Vec<u8>) {
        let (code, found) = process_cancel_request(goals, &request(byte, sec));
        (code, found.iter().map(|(id, ..)| id.0[0]).collect())
    }

    /// Goals 1 (t=10, executing), 2 (t=20, accepted), 3 (t=30, succeeded), 4 (t=40, canceling).
    fn goals() -> Vec<Goal<Fibonacci>> {
        vec![
            goal(1, 10, GoalState::Executing),
            goal(2, 20, GoalState::Accepted),
            goal(3, 30, GoalState::Succeeded),
            goal(4, 40, GoalState::Canceling),
        ]
    }

    #[test]
    fn cancel_by_id_only() {
        let mut g = goals();
        assert_eq!(
            cancel(&mut g, 2, 0),
            (CancelGoalResponse::ERROR_NONE, vec![2])
        );
        assert_eq!(
            cancel(&mut g, 3, 0),
            (CancelGoalResponse::ERROR_GOAL_TERMINATED, vec![])
        );
        // CANCELING is not cancelable: rcl_action calls it terminated too.
        assert_eq!(
            cancel(&mut g, 4, 0),
            (CancelGoalResponse::ERROR_GOAL_TERMINATED, vec![])
        );
        assert_eq!(
            cancel(&mut g, 9, 0),
            (CancelGoalResponse::ERROR_UNKNOWN_GOAL_ID, vec![])
        );
    }

    #[test]
    fn cancel_all_with_zero_id_and_stamp() {
        let mut g = goals();
        assert_eq!(
            cancel(&mut g, 0, 0),
            (CancelGoalResponse::ERROR_NONE, vec![1, 2])
        );
    }

    #[test]
    fn cancel_by_time_takes_goals_at_or_before_the_stamp() {
        let mut g = goals();
        assert_eq!(
            cancel(&mut g, 0, 10),
            (CancelGoalResponse::ERROR_NONE, vec![1])
        );
        assert_eq!(
            cancel(&mut g, 0, 25),
            (CancelGoalResponse::ERROR_NONE, vec![1, 2])
        );
        assert_eq!(
            cancel(&mut g, 0, 5),
            (CancelGoalResponse::ERROR_NONE, vec![])
        );
    }

    #[test]
    fn cancel_by_id_and_time_takes_both() {
        let mut g = goals();
        // Goal 2 by its id, goal 1 by time.
        assert_eq!(
            cancel(&mut g, 2, 10),
            (CancelGoalResponse::ERROR_NONE, vec![1, 2])
        );
        // An unknown id with a stamp is no error: the stamp's goals.
        assert_eq!(
            cancel(&mut g, 9, 10),
            (CancelGoalResponse::ERROR_NONE, vec![1])
        );
    }

    #[test]
    fn default_action_names_are_snake_case() {
        assert_eq!(default_action_name::<Fibonacci>(), "/fibonacci");
    }
}
