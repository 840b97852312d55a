//! [`ActionClient`]: sends goals to an action server and follows them, as rcl_action's client
//! and rclpy's `ActionClient` do (rcl_action `action_client.c`, rclpy
//! `rclpy/action/client.py`).
//!
//! The three services are called with the services crate's [`AsyncServiceClient`]s (both DDS
//! service conventions, per peer); feedback and status come on two subscriptions, each read by
//! a thread of its own woken by its data; a third thread follows the graph and tells every goal
//! when the server has left.

use std::collections::{HashMap, VecDeque};
use std::future::Future;
use std::marker::PhantomData;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::task::{Context as TaskContext, Poll};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_graph::{Graph, GraphSubscription, SubscriptionInterrupter};
use horus_ros_msgs::action_msgs::msg::{GoalInfo, GoalStatusArray};
use horus_ros_msgs::action_msgs::srv::{CancelGoal, CancelGoalRequest, CancelGoalResponse};
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::unique_identifier_msgs::msg::UUID;
use horus_ros_msgs::{Action, Service};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node, RawReaderWaker, Subscription};
use horus_ros_services::{
    AsyncServiceClient, EndpointBuilder, EndpointOptions, PendingResponse, ServiceError,
    TransportError,
};

use crate::common::{feedback_qos, lock, status_qos, ActionNames, GoalId};
use crate::error::{
    from_service_error, ActionSetupError, CancelError, FeedbackError, GetResultError, SendGoalError,
};
use crate::goal_state::GoalState;

/// Most feedback messages held per goal, not yet taken; beyond, the oldest is dropped.
pub const DEFAULT_FEEDBACK_CAPACITY: usize = 100;

/// Builds an [`ActionClient`] ([`ActionClient::builder`]). Node, action name, the three
/// services' QoS and wire convention are set with the [`EndpointBuilder`] setters.
#[must_use = "a builder does nothing until .build() is called"]
pub struct ActionClientBuilder<A: Action> {
    options: EndpointOptions,
    feedback_qos: Qos,
    status_qos: Qos,
    feedback_capacity: usize,
    _action: PhantomData<fn() -> A>,
}

impl<A: Action> EndpointBuilder for ActionClientBuilder<A> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options
    }
}

impl<A: Action> ActionClientBuilder<A> {
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

    /// Most feedback messages held per goal, not yet taken (default
    /// [`DEFAULT_FEEDBACK_CAPACITY`]); beyond, the oldest is dropped.
    pub fn feedback_capacity(mut self, capacity: usize) -> Self {
        self.feedback_capacity = capacity.max(1);
        self
    }

    /// Creates the three service clients and two subscriptions and starts their threads.
    pub fn build(self) -> Result<ActionClient<A>, ActionSetupError> {
        let node = match self.options.configured_node() {
            Some(node) => node.clone(),
            None => horus_ros_services::default_node()?,
        };
        let action = self
            .options
            .configured_name()
            .map(str::to_owned)
            .unwrap_or_else(crate::server::default_action_name::<A>);
        let names = ActionNames::of(&action);
        let service = |name: &str| self.options.clone().node(&node).name(name);
        let send_goal = AsyncServiceClient::<A::SendGoal>::builder()
            .options(service(&names.send_goal))
            .build()?;
        let cancel_goal = AsyncServiceClient::<CancelGoal>::builder()
            .options(service(&names.cancel_goal))
            .build()?;
        let get_result = AsyncServiceClient::<A::GetResult>::builder()
            .options(service(&names.get_result))
            .build()?;
        let feedback =
            node.create_subscription::<A::FeedbackMessage>(&names.feedback, &self.feedback_qos)?;
        let status =
            node.create_subscription::<GoalStatusArray>(&names.status, &self.status_qos)?;
        let graph = Graph::of(node.context())?;
        let graph_events = graph.subscribe();
        let shared = Arc::new(Shared {
            action,
            feedback_gid: feedback.gid(),
            node,
            send_goal,
            cancel_goal,
            get_result,
            goals: Mutex::new(HashMap::new()),
            changed: Condvar::new(),
            feedback_capacity: self.feedback_capacity,
            stop: AtomicBool::new(false),
            graph,
        });
        shared.check_server();
        let mut client = ActionClient {
            shared: Arc::clone(&shared),
            wakers: vec![feedback.waker(), status.waker()],
            interrupter: graph_events.interrupter(),
            threads: Vec::new(),
        };
        let spawn = |name: &str, f: Box<dyn FnOnce() + Send>| {
            std::thread::Builder::new()
                .name(format!("horus-{name}{}", shared.action))
                .spawn(f)
                .map_err(ActionSetupError::Thread)
        };
        let s = Arc::clone(&shared);
        client
            .threads
            .push(spawn("fb", Box::new(move || s.read_feedback(feedback)))?);
        let s = Arc::clone(&shared);
        client
            .threads
            .push(spawn("st", Box::new(move || s.read_status(status)))?);
        let s = Arc::clone(&shared);
        client
            .threads
            .push(spawn("gr", Box::new(move || s.follow_graph(graph_events)))?);
        Ok(client)
    }
}

/// An action client: sends goals ([`send_goal`](Self::send_goal),
/// [`send_goal_pending`](Self::send_goal_pending)), cancels them, and follows each accepted
/// goal through a [`ClientGoalHandle`] (feedback, status, result).
///
/// Readiness, in the services' words: [`server_available`](Self::server_available) (an action
/// server is known: its three services are on the graph), [`is_server_ready`](Self::is_server_ready)
/// (rcl `rcl_action_server_is_available`, rclpy `server_is_ready`: they can be called now), and
/// [`wait_for_server`](Self::wait_for_server) (woken by graph changes).
#[must_use = "an action client exists only while it is held"]
pub struct ActionClient<A: Action> {
    shared: Arc<Shared<A>>,
    wakers: Vec<RawReaderWaker>,
    interrupter: SubscriptionInterrupter,
    threads: Vec<JoinHandle<()>>,
}

impl<A: Action> std::fmt::Debug for ActionClient<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ActionClient")
            .field("action", &self.shared.action)
            .field("type", &A::TYPE_NAME)
            .finish()
    }
}

impl<A: Action> Drop for ActionClient<A> {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        for w in &self.wakers {
            w.wake();
        }
        self.interrupter.interrupt();
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

impl<A: Action> ActionClient<A> {
    /// A builder to choose node, name and QoS.
    pub fn builder() -> ActionClientBuilder<A> {
        ActionClientBuilder {
            options: EndpointOptions::default(),
            feedback_qos: feedback_qos(),
            status_qos: status_qos(),
            feedback_capacity: DEFAULT_FEEDBACK_CAPACITY,
            _action: PhantomData,
        }
    }

    /// The action name, as given (or the default).
    pub fn action_name(&self) -> &str {
        &self.shared.action
    }

    /// The node the client's entities live on.
    pub fn node(&self) -> &Node {
        &self.shared.node
    }

    /// Whether an action server is known: its three services are on the graph.
    pub fn server_available(&self) -> bool {
        self.shared.server_available()
    }

    /// Whether an action server can be called now, as rcl `rcl_action_server_is_available`
    /// (rclpy `server_is_ready`) has it: its three services are ready (known and matched both
    /// ways) and the feedback subscription is matched with a publisher, so that the first
    /// feedback of a goal sent now is not lost.
    pub fn is_server_ready(&self) -> bool {
        self.shared.send_goal.is_server_ready()
            && self.shared.cancel_goal.is_server_ready()
            && self.shared.get_result.is_server_ready()
            && self.shared.feedback_matched()
    }

    /// The same as [`is_server_ready`](Self::is_server_ready) (rclcpp's name).
    pub fn action_server_is_ready(&self) -> bool {
        self.is_server_ready()
    }

    /// Waits until [`is_server_ready`](Self::is_server_ready), at most `timeout`; woken by graph
    /// changes, never polled (rclpy `wait_for_server`): the services' `wait_for_service` of each
    /// of the three services in turn (an rmw_cyclonedds server still settling included), then
    /// the feedback subscription's match. Goals may be sent from other threads meanwhile.
    pub fn wait_for_server(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        let left = || deadline.saturating_duration_since(Instant::now());
        self.shared.send_goal.wait_for_service(left())
            && self.shared.cancel_goal.wait_for_service(left())
            && self.shared.get_result.wait_for_service(left())
            && self.shared.wait_for_feedback_match(deadline)
    }

    /// [`wait_for_server`](Self::wait_for_server) as a future (feature `tokio`: the services'
    /// `wait_for_service_async`, then graph events, woken by graph changes).
    #[cfg(feature = "tokio")]
    pub async fn wait_for_server_async(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        let left = || deadline.saturating_duration_since(Instant::now());
        let send_goal = self.shared.send_goal.wait_for_service_async(left());
        if !send_goal.await {
            return false;
        }
        let cancel_goal = self.shared.cancel_goal.wait_for_service_async(left());
        if !cancel_goal.await {
            return false;
        }
        let get_result = self.shared.get_result.wait_for_service_async(left());
        if !get_result.await {
            return false;
        }
        self.shared.feedback_match_async(deadline).await
    }

    /// Sends `goal` and waits for the server's answer, at most `timeout`: the handle of the
    /// accepted goal, or why not ([`SendGoalError::Rejected`] for a rejected one).
    pub fn send_goal(
        &self,
        goal: A::Goal,
        timeout: Duration,
    ) -> Result<ClientGoalHandle<A>, SendGoalError> {
        self.send_goal_pending(goal, timeout).wait()
    }

    /// Sends `goal` without blocking: a [`PendingGoal`] to check from a loop
    /// ([`try_take`](PendingGoal::try_take)), wait on, or `.await`.
    pub fn send_goal_pending(&self, goal: A::Goal, timeout: Duration) -> PendingGoal<A> {
        let id = GoalId::random();
        // Registered before the request leaves: feedback may come before the response.
        lock(&self.shared.goals).insert(id, GoalSlot::new());
        let response = self
            .shared
            .send_goal
            .call_async(A::create_goal_request(id.0, goal), timeout);
        PendingGoal {
            shared: Arc::clone(&self.shared),
            id,
            response: Some(response),
            outcome: None,
        }
    }

    /// Asks the server to cancel every goal (a zero goal id and stamp), waiting at most
    /// `timeout`: the goals it is canceling.
    pub fn cancel_all(&self, timeout: Duration) -> Result<Vec<GoalInfo>, CancelError> {
        self.shared
            .cancel(GoalId::default(), Time::default(), timeout)
    }

    /// Asks the server to cancel every goal accepted at or before `stamp` (a zero goal id),
    /// waiting at most `timeout`: the goals it is canceling.
    pub fn cancel_before(
        &self,
        stamp: Time,
        timeout: Duration,
    ) -> Result<Vec<GoalInfo>, CancelError> {
        self.shared.cancel(GoalId::default(), stamp, timeout)
    }

    /// Goals sent by this client and not yet forgotten (their handles live).
    pub fn goals_in_flight(&self) -> usize {
        lock(&self.shared.goals).len()
    }
}

/// What the client knows of one goal.
struct GoalSlot<A: Action> {
    feedback: VecDeque<A::Feedback>,
    status: Option<GoalState>,
    server_gone: bool,
}

impl<A: Action> GoalSlot<A> {
    fn new() -> Self {
        Self {
            feedback: VecDeque::new(),
            status: None,
            server_gone: false,
        }
    }
}

struct Shared<A: Action> {
    action: String,
    node: Node,
    send_goal: AsyncServiceClient<A::SendGoal>,
    cancel_goal: AsyncServiceClient<CancelGoal>,
    get_result: AsyncServiceClient<A::GetResult>,
    goals: Mutex<HashMap<GoalId, GoalSlot<A>>>,
    /// Notified on feedback, status and server changes.
    changed: Condvar,
    feedback_capacity: usize,
    stop: AtomicBool,
    graph: Arc<Graph>,
    /// The feedback subscription's GID: matched with a publisher, the server is ready.
    feedback_gid: Gid,
}

impl<A: Action> Shared<A> {
    fn server_available(&self) -> bool {
        self.send_goal.server_available()
            && self.cancel_goal.server_available()
            && self.get_result.server_available()
    }

    /// Whether the feedback subscription is matched with a publisher (rcl
    /// `rcl_action_server_is_available`: `rcl_subscription_get_publisher_count` of the feedback
    /// subscription not 0). A publisher of this same context reports its own side of the match
    /// apart from the subscription's, so it counts once it has both: only then does its next
    /// message reach us.
    fn feedback_matched(&self) -> bool {
        let own = self.node.context().gid().prefix();
        let reader = self.feedback_gid;
        self.graph
            .matched_with(reader)
            .into_iter()
            .any(|writer| writer.prefix() != own || self.graph.is_matched(writer, reader))
    }

    /// Waits until [`feedback_matched`](Self::feedback_matched), at most until `deadline`;
    /// woken by graph changes (matches are graph changes).
    fn wait_for_feedback_match(&self, deadline: Instant) -> bool {
        loop {
            let seen = self.graph.generation();
            if self.feedback_matched() {
                return true;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() || !self.graph.wait_for_graph_change_since(seen, left) {
                return self.feedback_matched();
            }
        }
    }

    /// [`wait_for_feedback_match`](Self::wait_for_feedback_match) as a future, woken by the
    /// graph's event stream.
    #[cfg(feature = "tokio")]
    async fn feedback_match_async(&self, deadline: Instant) -> bool {
        use futures_core::Stream;
        // Subscribed before looking: a match made in between is an event.
        let mut events = self.graph.events_with_capacity(1);
        let next = std::future::poll_fn(|cx| {
            loop {
                if self.feedback_matched() {
                    return Poll::Ready(());
                }
                // Every event is one more look; the stream ends only with the graph.
                match Pin::new(&mut events).poll_next(cx) {
                    Poll::Ready(Some(_)) => continue,
                    Poll::Ready(None) | Poll::Pending => return Poll::Pending,
                }
            }
        });
        tokio::time::timeout_at(deadline.into(), next).await.is_ok() || self.feedback_matched()
    }

    /// Tells every goal whether the server is there.
    fn check_server(&self) {
        let gone = !self.get_result.server_available();
        let mut goals = lock(&self.goals);
        let mut changed = false;
        for slot in goals.values_mut() {
            if slot.server_gone != gone {
                slot.server_gone = gone;
                changed = true;
            }
        }
        drop(goals);
        if changed {
            self.changed.notify_all();
        }
    }

    fn follow_graph(&self, events: GraphSubscription) {
        while !self.stop.load(Ordering::SeqCst) {
            if events.recv(None).is_err() {
                break;
            }
            // Every event held now is one look at the graph.
            for _ in events.try_iter() {}
            self.check_server();
        }
    }

    fn read_feedback(&self, mut feedback: Subscription<A::FeedbackMessage>) {
        while !self.stop.load(Ordering::SeqCst) {
            loop {
                match feedback.try_take() {
                    Ok(Some(message)) => {
                        let (id, fb) = A::split_feedback_message(message);
                        let mut goals = lock(&self.goals);
                        if let Some(slot) = goals.get_mut(&GoalId(id)) {
                            if slot.feedback.len() >= self.feedback_capacity {
                                slot.feedback.pop_front();
                            }
                            slot.feedback.push_back(fb);
                            drop(goals);
                            self.changed.notify_all();
                        }
                    }
                    Ok(None) => break,
                    Err(e) => tracing::warn!(action = %self.action, "feedback: {e}"),
                }
            }
            feedback.wait(None);
        }
    }

    fn read_status(&self, mut status: Subscription<GoalStatusArray>) {
        while !self.stop.load(Ordering::SeqCst) {
            loop {
                match status.try_take() {
                    Ok(Some(array)) => {
                        let mut goals = lock(&self.goals);
                        for s in &array.status_list {
                            if let Some(slot) = goals.get_mut(&GoalId(s.goal_info.goal_id.uuid)) {
                                slot.status = GoalState::from_status(s.status);
                            }
                        }
                        drop(goals);
                        self.changed.notify_all();
                    }
                    Ok(None) => break,
                    Err(e) => tracing::warn!(action = %self.action, "status: {e}"),
                }
            }
            status.wait(None);
        }
    }

    fn cancel(
        &self,
        id: GoalId,
        stamp: Time,
        timeout: Duration,
    ) -> Result<Vec<GoalInfo>, CancelError> {
        let request = CancelGoalRequest {
            goal_info: GoalInfo {
                goal_id: UUID { uuid: id.0 },
                stamp,
            },
        };
        // The client's lock is held while the call starts only, not while it is waited on.
        let pending = self.cancel_goal.call_async(request, timeout);
        cancel_outcome(pending.wait())
    }
}

fn cancel_outcome(
    response: Result<CancelGoalResponse, ServiceError>,
) -> Result<Vec<GoalInfo>, CancelError> {
    let response = response.map_err(|e| {
        from_service_error(
            e,
            CancelError::Timeout,
            CancelError::NoServer,
            CancelError::Transport,
        )
    })?;
    match response.return_code {
        CancelGoalResponse::ERROR_NONE => Ok(response.goals_canceling),
        CancelGoalResponse::ERROR_REJECTED => Err(CancelError::Rejected),
        CancelGoalResponse::ERROR_UNKNOWN_GOAL_ID => Err(CancelError::UnknownGoal),
        CancelGoalResponse::ERROR_GOAL_TERMINATED => Err(CancelError::GoalTerminated),
        other => Err(CancelError::Other(other)),
    }
}

/// A goal sent and not yet answered ([`ActionClient::send_goal_pending`]): check it from a
/// loop, wait on it, or `.await` it (any executor). Dropping it abandons the goal (a goal the
/// server accepts meanwhile runs on unfollowed).
#[must_use = "dropping a pending goal abandons it"]
pub struct PendingGoal<A: Action> {
    shared: Arc<Shared<A>>,
    id: GoalId,
    response: Option<PendingResponse<A::SendGoal>>,
    outcome: Option<Result<ClientGoalHandle<A>, SendGoalError>>,
}

impl<A: Action> std::fmt::Debug for PendingGoal<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PendingGoal")
            .field("goal_id", &self.id)
            .finish()
    }
}

impl<A: Action> PendingGoal<A> {
    /// The id the goal was sent with.
    pub fn goal_id(&self) -> GoalId {
        self.id
    }

    /// Turns the goal response into the outcome.
    fn finish(
        &mut self,
        response: Result<<A::SendGoal as Service>::Response, ServiceError>,
    ) -> Result<ClientGoalHandle<A>, SendGoalError> {
        self.response = None;
        let outcome = match response {
            Ok(r) if A::goal_response_accepted(&r) => {
                let (sec, nanosec) = A::goal_response_stamp(&r);
                Ok(ClientGoalHandle {
                    shared: Arc::clone(&self.shared),
                    id: self.id,
                    stamp: Time { sec, nanosec },
                })
            }
            Ok(_) => Err(SendGoalError::Rejected),
            Err(e) => Err(from_service_error(
                e,
                SendGoalError::Timeout,
                SendGoalError::NoServer,
                SendGoalError::Transport,
            )),
        };
        if outcome.is_err() {
            lock(&self.shared.goals).remove(&self.id);
        }
        outcome
    }

    fn poll_outcome(&mut self) {
        if self.outcome.is_some() {
            return;
        }
        let Some(response) = self.response.as_mut() else {
            return;
        };
        match response.check() {
            Ok(Some(r)) => self.outcome = Some(self.finish(Ok(r))),
            Ok(None) => {}
            Err(e) => self.outcome = Some(self.finish(Err(e))),
        }
    }

    /// Whether the server's answer (or an error) is in (non-blocking).
    pub fn is_ready(&mut self) -> bool {
        self.poll_outcome();
        self.outcome.is_some()
    }

    /// The outcome if it is in (non-blocking): `None` while waiting; `Some` once, then `None`.
    pub fn try_take(&mut self) -> Option<Result<ClientGoalHandle<A>, SendGoalError>> {
        self.poll_outcome();
        self.outcome.take()
    }

    /// Blocks until the server's answer, an error, or the timeout.
    pub fn wait(mut self) -> Result<ClientGoalHandle<A>, SendGoalError> {
        if let Some(outcome) = self.outcome.take() {
            return outcome;
        }
        match self.response.take() {
            Some(response) => {
                let r = response.wait();
                self.finish(r)
            }
            None => Err(SendGoalError::Transport(TransportError::CallCompleted)),
        }
    }
}

impl<A: Action> Drop for PendingGoal<A> {
    fn drop(&mut self) {
        if self.response.is_some() {
            lock(&self.shared.goals).remove(&self.id);
        }
    }
}

impl<A: Action> Unpin for PendingGoal<A> {}

impl<A: Action> Future for PendingGoal<A> {
    type Output = Result<ClientGoalHandle<A>, SendGoalError>;

    fn poll(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Self::Output> {
        let this = self.get_mut();
        if let Some(outcome) = this.outcome.take() {
            return Poll::Ready(outcome);
        }
        let Some(response) = this.response.as_mut() else {
            return Poll::Ready(Err(SendGoalError::Transport(TransportError::CallCompleted)));
        };
        match Pin::new(response).poll(cx) {
            Poll::Ready(r) => Poll::Ready(this.finish(r)),
            Poll::Pending => Poll::Pending,
        }
    }
}

/// An accepted goal, followed by the client that sent it (rclpy `ClientGoalHandle`): its
/// feedback (in order, bounded), its status, its result, and cancel. Dropping it stops
/// following the goal (the goal goes on at the server).
pub struct ClientGoalHandle<A: Action> {
    shared: Arc<Shared<A>>,
    id: GoalId,
    stamp: Time,
}

impl<A: Action> std::fmt::Debug for ClientGoalHandle<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ClientGoalHandle")
            .field("goal_id", &self.id)
            .field("stamp", &self.stamp)
            .finish()
    }
}

impl<A: Action> Drop for ClientGoalHandle<A> {
    fn drop(&mut self) {
        lock(&self.shared.goals).remove(&self.id);
    }
}

impl<A: Action> ClientGoalHandle<A> {
    /// The goal's id.
    pub fn goal_id(&self) -> GoalId {
        self.id
    }

    /// When the server accepted the goal (the `stamp` of its response).
    pub fn stamp(&self) -> Time {
        self.stamp
    }

    /// The goal's state as the status topic last told it (`None` before the first status
    /// naming it).
    pub fn status(&self) -> Option<GoalState> {
        lock(&self.shared.goals)
            .get(&self.id)
            .and_then(|s| s.status)
    }

    /// Whether the action server has left the graph.
    pub fn server_gone(&self) -> bool {
        lock(&self.shared.goals)
            .get(&self.id)
            .is_some_and(|s| s.server_gone)
    }

    /// The next feedback if one is held (non-blocking).
    pub fn try_recv_feedback(&self) -> Option<A::Feedback> {
        lock(&self.shared.goals)
            .get_mut(&self.id)
            .and_then(|s| s.feedback.pop_front())
    }

    /// The next feedback, in the order the server published them, waiting at most `timeout`:
    /// woken by feedback, status and graph changes. Once the goal has ended and every feedback
    /// held was taken, [`FeedbackError::GoalEnded`]; once the server has left,
    /// [`FeedbackError::ServerGone`].
    pub fn recv_feedback(&self, timeout: Duration) -> Result<A::Feedback, FeedbackError> {
        let deadline = Instant::now() + timeout;
        let mut goals = lock(&self.shared.goals);
        loop {
            let Some(slot) = goals.get_mut(&self.id) else {
                return Err(FeedbackError::GoalEnded);
            };
            if let Some(fb) = slot.feedback.pop_front() {
                return Ok(fb);
            }
            if slot.status.is_some_and(GoalState::is_terminal) {
                return Err(FeedbackError::GoalEnded);
            }
            if slot.server_gone {
                return Err(FeedbackError::ServerGone);
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(FeedbackError::Timeout);
            }
            goals = self
                .shared
                .changed
                .wait_timeout(goals, deadline - now)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
    }

    /// Waits until the goal's status is `state` or terminal, at most `timeout`; returns the
    /// status then (`None` if none came).
    pub fn wait_for_status(&self, state: GoalState, timeout: Duration) -> Option<GoalState> {
        let deadline = Instant::now() + timeout;
        let mut goals = lock(&self.shared.goals);
        loop {
            let status = goals.get(&self.id).and_then(|s| s.status);
            let gone = goals.get(&self.id).is_none_or(|s| s.server_gone);
            if status.is_some_and(|s| s == state || s.is_terminal()) || gone {
                return status;
            }
            let now = Instant::now();
            if now >= deadline {
                return status;
            }
            goals = self
                .shared
                .changed
                .wait_timeout(goals, deadline - now)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
    }

    /// Asks for the goal's result and waits for it, at most `timeout` (the server answers when
    /// the goal ends): its final state and result.
    pub fn get_result(&self, timeout: Duration) -> Result<(GoalState, A::Result), GetResultError> {
        self.get_result_pending(timeout).wait()
    }

    /// Asks for the goal's result without blocking: a [`PendingResult`] to check, wait on or
    /// `.await`.
    pub fn get_result_pending(&self, timeout: Duration) -> PendingResult<A> {
        let response = self
            .shared
            .get_result
            .call_async(A::create_result_request(self.id.0), timeout);
        PendingResult {
            response: Some(response),
            _action: PhantomData,
        }
    }

    /// Asks the server to cancel this goal, waiting at most `timeout`: `Ok` once the server is
    /// canceling it (the goal then ends, usually CANCELED: see [`get_result`](Self::get_result)).
    pub fn cancel(&self, timeout: Duration) -> Result<Vec<GoalInfo>, CancelError> {
        self.shared.cancel(self.id, Time::default(), timeout)
    }

    /// Asks the server to cancel this goal without blocking.
    pub fn cancel_pending(&self, timeout: Duration) -> PendingCancel {
        let request = CancelGoalRequest {
            goal_info: GoalInfo {
                goal_id: UUID { uuid: self.id.0 },
                stamp: Time::default(),
            },
        };
        PendingCancel {
            response: Some(self.shared.cancel_goal.call_async(request, timeout)),
        }
    }
}

fn result_outcome<A: Action>(
    response: Result<<A::GetResult as Service>::Response, ServiceError>,
) -> Result<(GoalState, A::Result), GetResultError> {
    let response = response.map_err(|e| match e {
        ServiceError::Transport(TransportError::ServerGone) => GetResultError::ServerGone,
        e => from_service_error(
            e,
            GetResultError::Timeout,
            GetResultError::NoServer,
            GetResultError::Transport,
        ),
    })?;
    let (status, result) = A::split_result_response(response);
    match GoalState::from_status(status) {
        Some(state) => Ok((state, result)),
        None => Err(GetResultError::UnknownGoal),
    }
}

/// A result asked for and not yet answered ([`ClientGoalHandle::get_result_pending`]).
#[must_use = "dropping a pending result abandons the request"]
pub struct PendingResult<A: Action> {
    response: Option<PendingResponse<A::GetResult>>,
    _action: PhantomData<fn() -> A>,
}

impl<A: Action> std::fmt::Debug for PendingResult<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PendingResult")
    }
}

impl<A: Action> PendingResult<A> {
    /// The outcome if it is in (non-blocking): `None` while waiting; `Some` once.
    pub fn try_take(&mut self) -> Option<Result<(GoalState, A::Result), GetResultError>> {
        let response = self.response.as_mut()?;
        let outcome = match response.check() {
            Ok(Some(r)) => Some(result_outcome::<A>(Ok(r))),
            Ok(None) => None,
            Err(e) => Some(result_outcome::<A>(Err(e))),
        };
        if outcome.is_some() {
            self.response = None;
        }
        outcome
    }

    /// Blocks until the result, an error, or the timeout.
    pub fn wait(mut self) -> Result<(GoalState, A::Result), GetResultError> {
        match self.response.take() {
            Some(r) => result_outcome::<A>(r.wait()),
            None => Err(GetResultError::Transport(TransportError::CallCompleted)),
        }
    }
}

impl<A: Action> Unpin for PendingResult<A> {}

impl<A: Action> Future for PendingResult<A> {
    type Output = Result<(GoalState, A::Result), GetResultError>;

    fn poll(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Self::Output> {
        let this = self.get_mut();
        let Some(response) = this.response.as_mut() else {
            return Poll::Ready(Err(GetResultError::Transport(
                TransportError::CallCompleted,
            )));
        };
        match Pin::new(response).poll(cx) {
            Poll::Ready(r) => {
                this.response = None;
                Poll::Ready(result_outcome::<A>(r))
            }
            Poll::Pending => Poll::Pending,
        }
    }
}

/// A cancel request not yet answered ([`ClientGoalHandle::cancel_pending`]).
#[must_use = "dropping a pending cancel abandons the request"]
#[derive(Debug)]
pub struct PendingCancel {
    response: Option<PendingResponse<CancelGoal>>,
}

impl PendingCancel {
    /// The outcome if it is in (non-blocking): `None` while waiting; `Some` once.
    pub fn try_take(&mut self) -> Option<Result<Vec<GoalInfo>, CancelError>> {
        let response = self.response.as_mut()?;
        let outcome = match response.check() {
            Ok(Some(r)) => Some(cancel_outcome(Ok(r))),
            Ok(None) => None,
            Err(e) => Some(cancel_outcome(Err(e))),
        };
        if outcome.is_some() {
            self.response = None;
        }
        outcome
    }

    /// Blocks until the answer, an error, or the timeout.
    pub fn wait(mut self) -> Result<Vec<GoalInfo>, CancelError> {
        match self.response.take() {
            Some(r) => cancel_outcome(r.wait()),
            None => Err(CancelError::Transport(TransportError::CallCompleted)),
        }
    }
}

impl Unpin for PendingCancel {}

impl Future for PendingCancel {
    type Output = Result<Vec<GoalInfo>, CancelError>;

    fn poll(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Self::Output> {
        let this = self.get_mut();
        let Some(response) = this.response.as_mut() else {
            return Poll::Ready(Err(CancelError::Transport(TransportError::CallCompleted)));
        };
        match Pin::new(response).poll(cx) {
            Poll::Ready(r) => {
                this.response = None;
                Poll::Ready(cancel_outcome(r))
            }
            Poll::Pending => Poll::Pending,
        }
    }
}
