//! [`LifecycleNode`]: a ROS node with rcl_lifecycle's communication interface
//! (`rcl_lifecycle/src/com_interface.c`) and rclcpp_lifecycle's transition logic
//! (`rclcpp_lifecycle/src/lifecycle_node_interface_impl.cpp`, `change_state`,
//! `execute_callback`; rclpy's `rclpy/lifecycle/node.py` `__change_state` is the same).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, TryLockError, Weak};

use horus_ros_msgs::lifecycle_msgs::msg::TransitionEvent;
use horus_ros_msgs::lifecycle_msgs::srv::{
    ChangeState, ChangeStateResponse, GetAvailableStates, GetAvailableStatesResponse,
    GetAvailableTransitions, GetAvailableTransitionsResponse, GetState, GetStateResponse,
};
use horus_ros_msgs::{Message, Service};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{EndpointError, Gid, Node, Publisher};
use horus_ros_services::{EndpointBuilder, ServiceServer, SetupError};

use crate::publisher::LifecyclePublisher;
use crate::state_machine::{labels, CallbackReturn, State, StateMachine, Transition};

/// The topic of a node's transition events (`pub_transition_event_topic`).
pub const TRANSITION_EVENT_TOPIC: &str = "~/transition_event";
/// The names of a node's lifecycle services (`com_interface.c`), in the order rcl creates them.
pub const SERVICE_NAMES: [&str; 5] = [
    "~/change_state",
    "~/get_state",
    "~/get_available_states",
    "~/get_available_transitions",
    "~/get_transition_graph",
];

/// The QoS of `~/transition_event`: rcl_lifecycle creates its publisher with
/// `rcl_publisher_get_default_options()`, i.e. `rmw_qos_profile_default` (KEEP_LAST 10,
/// RELIABLE, VOLATILE).
pub fn transition_event_qos() -> Qos {
    Qos::default_profile()
}

/// What a managed node does in each transition state. Every method gets the primary state the
/// transition started from (rclcpp passes `previous_state`) and defaults to
/// [`CallbackReturn::Success`], as rclcpp's `LifecycleNodeInterface` does.
///
/// A panic in a callback is caught and taken as [`CallbackReturn::Error`], as rclcpp takes an
/// exception (`execute_callback`).
pub trait LifecycleCallbacks: Send + 'static {
    /// In `configuring` (transition `configure`).
    fn on_configure(&mut self, _previous: State) -> CallbackReturn {
        CallbackReturn::Success
    }
    /// In `cleaningup` (transition `cleanup`).
    fn on_cleanup(&mut self, _previous: State) -> CallbackReturn {
        CallbackReturn::Success
    }
    /// In `shuttingdown` (transitions `shutdown` from unconfigured, inactive or active).
    fn on_shutdown(&mut self, _previous: State) -> CallbackReturn {
        CallbackReturn::Success
    }
    /// In `activating` (transition `activate`). Managed publishers are already activated.
    fn on_activate(&mut self, _previous: State) -> CallbackReturn {
        CallbackReturn::Success
    }
    /// In `deactivating` (transition `deactivate`). Managed publishers are already deactivated.
    fn on_deactivate(&mut self, _previous: State) -> CallbackReturn {
        CallbackReturn::Success
    }
    /// In `errorprocessing`, after another callback returned [`CallbackReturn::Error`]:
    /// `Success` leads to `unconfigured`, `Failure` and `Error` to `finalized`.
    fn on_error(&mut self, _previous: State) -> CallbackReturn {
        CallbackReturn::Success
    }
}

/// The default callbacks: every one returns [`CallbackReturn::Success`].
impl LifecycleCallbacks for () {}

/// Why a transition asked of a [`LifecycleNode`] did not reach its goal.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TransitionError {
    /// No such transition leaves the current state (or another transition is running, and the
    /// node is in its transition state); nothing happened.
    #[error("no transition matching {requested} found for current state {state}")]
    NotAvailable {
        /// The id or label asked for.
        requested: String,
        /// The node's state (unchanged).
        state: State,
    },
    /// The callback returned [`CallbackReturn::Failure`]; the node went back (`transition_failure`).
    #[error("transition {transition} failed; the node is {state}")]
    Failed {
        /// The transition asked for.
        transition: Transition,
        /// Where the node is now.
        state: State,
    },
    /// The callback returned [`CallbackReturn::Error`] or panicked; `on_error` then decided
    /// where the node is.
    #[error("transition {transition} raised an error; after error processing the node is {state}")]
    Error {
        /// The transition asked for.
        transition: Transition,
        /// Where the node is now (`unconfigured` or `finalized`).
        state: State,
    },
}

/// What one transition did: the callback's result and where the node is now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TransitionOutcome {
    /// The transition asked for.
    pub transition: Transition,
    /// The transition state's callback result.
    pub result: CallbackReturn,
    /// The primary state the node is in afterwards.
    pub state: State,
}

impl TransitionOutcome {
    fn into_result(self) -> Result<State, TransitionError> {
        let (transition, state) = (self.transition, self.state);
        match self.result {
            CallbackReturn::Success => Ok(state),
            CallbackReturn::Failure => Err(TransitionError::Failed { transition, state }),
            CallbackReturn::Error => Err(TransitionError::Error { transition, state }),
        }
    }
}

/// Builds a [`LifecycleNode`]: `LifecycleNode::builder().node(&node).callbacks(c).build()`.
pub struct LifecycleNodeBuilder {
    node: Option<Node>,
    callbacks: Box<dyn LifecycleCallbacks>,
    communication_interface: bool,
}

impl std::fmt::Debug for LifecycleNodeBuilder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LifecycleNodeBuilder")
            .field("node", &self.node.as_ref().map(Node::fully_qualified_name))
            .field("communication_interface", &self.communication_interface)
            .finish_non_exhaustive()
    }
}

impl LifecycleNodeBuilder {
    /// The ROS node to manage (default: horus-ros-services' process default node).
    pub fn node(mut self, node: &Node) -> Self {
        self.node = Some(node.clone());
        self
    }

    /// The transition callbacks (default: `()`, every callback succeeds).
    pub fn callbacks(mut self, callbacks: impl LifecycleCallbacks) -> Self {
        self.callbacks = Box::new(callbacks);
        self
    }

    /// Whether to create the five services and the `~/transition_event` publisher (default
    /// true; rclcpp's `enable_communication_interface`). Without them the node is driven only
    /// by its own calls.
    pub fn communication_interface(mut self, enable: bool) -> Self {
        self.communication_interface = enable;
        self
    }

    /// Creates the services and the transition event publisher; the node starts `unconfigured`.
    pub fn build(self) -> Result<LifecycleNode, SetupError> {
        let node = match self.node {
            Some(n) => n,
            None => horus_ros_services::default_node()?,
        };
        let events = if self.communication_interface {
            Some(node.create_publisher::<TransitionEvent>(
                TRANSITION_EVENT_TOPIC,
                &transition_event_qos(),
            )?)
        } else {
            None
        };
        let shared = Arc::new(Shared {
            machine: Mutex::new(StateMachine::new()),
            transition: Mutex::new(()),
            callbacks: Mutex::new(self.callbacks),
            events,
            entities: Mutex::new(Vec::new()),
            name: node.fully_qualified_name(),
        });
        let servers = if self.communication_interface {
            Servers::start(&node, &shared)?
        } else {
            Servers::default()
        };
        tracing::debug!(node = %shared.name, "lifecycle node ready");
        Ok(LifecycleNode {
            node,
            shared,
            _servers: servers,
        })
    }
}

/// A managed node: a ROS node whose life follows rcl_lifecycle's default state machine, driven
/// by its `~/change_state` service (as `ros2 lifecycle set` calls it) or by its own calls
/// ([`configure`](Self::configure), [`activate`](Self::activate), …), with the services and the
/// `~/transition_event` topic of rclcpp_lifecycle's and rclpy's lifecycle nodes.
///
/// Transitions run one at a time: one asked while another runs finds the node in a transition
/// state, where rcl finds no such transition ([`TransitionError::NotAvailable`]; a change_state
/// call gets `success: false`). Dropping it removes its services and publisher.
pub struct LifecycleNode {
    node: Node,
    shared: Arc<Shared>,
    _servers: Servers,
}

impl std::fmt::Debug for LifecycleNode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LifecycleNode")
            .field("node", &self.shared.name)
            .field("state", &self.current_state())
            .finish_non_exhaustive()
    }
}

impl LifecycleNode {
    /// A builder (see [`LifecycleNodeBuilder`]).
    pub fn builder() -> LifecycleNodeBuilder {
        LifecycleNodeBuilder {
            node: None,
            callbacks: Box::new(()),
            communication_interface: true,
        }
    }

    /// The ROS node.
    pub fn node(&self) -> &Node {
        &self.node
    }

    /// The GID of the `~/transition_event` publisher (none without the communication interface).
    pub fn transition_event_gid(&self) -> Option<Gid> {
        self.shared.events.as_ref().map(Publisher::gid)
    }

    /// The current state (a transition state while a callback runs).
    pub fn current_state(&self) -> State {
        self.shared.machine().current()
    }

    /// Every state of the state machine (`get_available_states`).
    pub fn available_states(&self) -> Vec<State> {
        State::ALL.to_vec()
    }

    /// The transitions valid from the current state (`get_available_transitions`).
    pub fn available_transitions(&self) -> Vec<Transition> {
        self.shared.machine().available_transitions()
    }

    /// Every transition of the state machine (`get_transition_graph`).
    pub fn transition_graph(&self) -> Vec<Transition> {
        Transition::ALL.to_vec()
    }

    /// Runs the transition with this id (rclcpp's `trigger_transition(uint8_t)`): the
    /// transition state's callback, then its result's transition (and `on_error` on an error).
    /// `Ok` with the new state when the callback succeeded.
    pub fn trigger_transition(&self, id: u8) -> Result<State, TransitionError> {
        self.shared.change_state(id)?.into_result()
    }

    /// Runs the transition with this label from the current state (rclcpp's
    /// `trigger_transition(const std::string &)`; `"shutdown"` picks the current state's).
    pub fn trigger_transition_by_label(&self, label: &str) -> Result<State, TransitionError> {
        let (found, state) = {
            let machine = self.shared.machine();
            (machine.transition_by_label(label), machine.current())
        };
        let transition = found.ok_or_else(|| TransitionError::NotAvailable {
            requested: label.to_owned(),
            state,
        })?;
        self.trigger_transition(transition.id())
    }

    /// Runs a transition and returns what happened, whatever the callback returned.
    pub fn change_state(
        &self,
        transition: Transition,
    ) -> Result<TransitionOutcome, TransitionError> {
        self.shared.change_state(transition.id())
    }

    /// `configure`: unconfigured → inactive.
    pub fn configure(&self) -> Result<State, TransitionError> {
        self.trigger_transition_by_label(labels::CONFIGURE)
    }

    /// `cleanup`: inactive → unconfigured.
    pub fn cleanup(&self) -> Result<State, TransitionError> {
        self.trigger_transition_by_label(labels::CLEANUP)
    }

    /// `activate`: inactive → active.
    pub fn activate(&self) -> Result<State, TransitionError> {
        self.trigger_transition_by_label(labels::ACTIVATE)
    }

    /// `deactivate`: active → inactive.
    pub fn deactivate(&self) -> Result<State, TransitionError> {
        self.trigger_transition_by_label(labels::DEACTIVATE)
    }

    /// `shutdown` from the current primary state: → finalized.
    pub fn shutdown(&self) -> Result<State, TransitionError> {
        self.trigger_transition_by_label(labels::SHUTDOWN)
    }

    /// A managed publisher on `topic` (rclcpp's `create_publisher` of a lifecycle node): it
    /// publishes only while the node is `activating` or `active`.
    pub fn create_publisher<M: Message>(
        &self,
        topic: &str,
        qos: &Qos,
    ) -> Result<LifecyclePublisher<M>, EndpointError> {
        let publisher = self.node.create_publisher::<M>(topic, qos)?;
        let active = Arc::new(AtomicBool::new(entities_active(self.current_state())));
        let mut entities = self
            .shared
            .entities
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        entities.retain(|w| w.strong_count() > 0);
        entities.push(Arc::downgrade(&active));
        Ok(LifecyclePublisher::new(publisher, active))
    }
}

/// Managed entities are active while the node is `activating` (so `on_activate` may publish, as
/// rclcpp's demos call `LifecycleNode::on_activate` first) or `active`.
fn entities_active(state: State) -> bool {
    matches!(state, State::Activating | State::Active)
}

struct Shared {
    machine: Mutex<StateMachine>,
    /// Held for a whole transition.
    transition: Mutex<()>,
    callbacks: Mutex<Box<dyn LifecycleCallbacks>>,
    events: Option<Publisher<TransitionEvent>>,
    entities: Mutex<Vec<Weak<AtomicBool>>>,
    name: String,
}

impl Shared {
    fn machine(&self) -> MutexGuard<'_, StateMachine> {
        self.machine.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// `rcl_lifecycle_trigger_transition_by_*` with `publish_notification`: the event carries
    /// only the start and goal states; its `timestamp` and `transition` stay zero, as rcl's
    /// (`rcl_lifecycle_com_interface_publish_notification` sets nothing else).
    fn take(&self, transition: Transition) {
        let Some(events) = &self.events else {
            return;
        };
        let event = TransitionEvent {
            start_state: transition.start().to_msg(),
            goal_state: transition.goal().to_msg(),
            ..TransitionEvent::default()
        };
        if let Err(err) = events.publish(event) {
            tracing::warn!(node = %self.name, "could not publish the transition event: {err}");
        }
    }

    fn sync_entities(&self, state: State) {
        let active = entities_active(state);
        let entities = self.entities.lock().unwrap_or_else(|p| p.into_inner());
        for flag in entities.iter().filter_map(Weak::upgrade) {
            flag.store(active, Ordering::Release);
        }
    }

    /// rclcpp's `execute_callback`: the callback of the transition state, a panic taken as ERROR.
    fn execute_callback(&self, state: State, previous: State) -> CallbackReturn {
        let mut callbacks = self.callbacks.lock().unwrap_or_else(|p| p.into_inner());
        let cb: &mut dyn LifecycleCallbacks = callbacks.as_mut();
        let run = catch_unwind(AssertUnwindSafe(|| match state {
            State::Configuring => cb.on_configure(previous),
            State::CleaningUp => cb.on_cleanup(previous),
            State::ShuttingDown => cb.on_shutdown(previous),
            State::Activating => cb.on_activate(previous),
            State::Deactivating => cb.on_deactivate(previous),
            State::ErrorProcessing => cb.on_error(previous),
            _ => CallbackReturn::Success,
        }));
        run.unwrap_or_else(|panic| {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            tracing::error!(
                node = %self.name,
                "Caught exception in callback for transition {}: {message}",
                state.id()
            );
            CallbackReturn::Error
        })
    }

    /// rclcpp's `LifecycleNodeInterfaceImpl::change_state`.
    fn change_state(&self, id: u8) -> Result<TransitionOutcome, TransitionError> {
        let not_available = |state| TransitionError::NotAvailable {
            requested: id.to_string(),
            state,
        };
        let _running = match self.transition.try_lock() {
            Ok(guard) => guard,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
            // Another transition runs: the node is in its transition state, from which rcl
            // finds no transition `id` asks for.
            Err(TryLockError::WouldBlock) => return Err(not_available(self.machine().current())),
        };
        let (initial, transition) = {
            let mut machine = self.machine();
            let initial = machine.current();
            let transition = machine
                .trigger_by_id(id)
                .map_err(|e| not_available(e.state))?;
            self.take(transition);
            (initial, transition)
        };
        self.sync_entities(transition.goal());
        let result = self.execute_callback(transition.goal(), initial);
        let mut state = self.finish(result);
        if result == CallbackReturn::Error {
            tracing::warn!(node = %self.name, "Error occurred while doing error handling.");
            let on_error = self.execute_callback(state, initial);
            state = self.finish(on_error);
        }
        Ok(TransitionOutcome {
            transition,
            result,
            state,
        })
    }

    /// Takes the callback result's transition from the current transition state.
    fn finish(&self, result: CallbackReturn) -> State {
        let state = {
            let mut machine = self.machine();
            // Every transition state has the three result transitions.
            if let Ok(t) = machine.trigger_by_label(result.label()) {
                self.take(t);
            }
            machine.current()
        };
        self.sync_entities(state);
        state
    }
}

/// The five services; each handler holds the node weakly.
#[derive(Default)]
struct Servers {
    _change_state: Option<ServiceServer<ChangeState>>,
    _get_state: Option<ServiceServer<GetState>>,
    _get_available_states: Option<ServiceServer<GetAvailableStates>>,
    _get_available_transitions: Option<ServiceServer<GetAvailableTransitions>>,
    _get_transition_graph: Option<ServiceServer<GetAvailableTransitions>>,
}

fn server<S: Service>(
    node: &Node,
    name: &str,
    shared: &Arc<Shared>,
    handle: impl Fn(&Shared, S::Request) -> S::Response + Send + 'static,
) -> Result<ServiceServer<S>, SetupError> {
    let weak = Arc::downgrade(shared);
    ServiceServer::<S>::builder()
        .node(node)
        .name(name)
        .qos(Qos::services_default())
        .on_request(move |req| match weak.upgrade() {
            Some(shared) => Ok(handle(&shared, req)),
            None => Err("the lifecycle node is gone".to_owned()),
        })
        .build()
}

impl Servers {
    fn start(node: &Node, shared: &Arc<Shared>) -> Result<Self, SetupError> {
        let [change, get, states, transitions, graph] = SERVICE_NAMES;
        Ok(Self {
            // rclcpp's `on_change_state`: a label takes precedence over the id; an unknown
            // label or id, or a callback result other than SUCCESS, answers `success: false`.
            _change_state: Some(server::<ChangeState>(node, change, shared, |s, req| {
                let id = if req.transition.label.is_empty() {
                    Some(req.transition.id)
                } else {
                    s.machine()
                        .transition_by_label(&req.transition.label)
                        .map(Transition::id)
                };
                let success = id
                    .and_then(|id| s.change_state(id).ok())
                    .is_some_and(|o| o.result == CallbackReturn::Success);
                ChangeStateResponse { success }
            })?),
            _get_state: Some(server::<GetState>(node, get, shared, |s, _| {
                GetStateResponse {
                    current_state: s.machine().current().to_msg(),
                }
            })?),
            _get_available_states: Some(server::<GetAvailableStates>(
                node,
                states,
                shared,
                |_, _| GetAvailableStatesResponse {
                    available_states: State::ALL.iter().map(|s| s.to_msg()).collect(),
                },
            )?),
            _get_available_transitions: Some(server::<GetAvailableTransitions>(
                node,
                transitions,
                shared,
                |s, _| GetAvailableTransitionsResponse {
                    available_transitions: s
                        .machine()
                        .available_transitions()
                        .into_iter()
                        .map(Transition::description)
                        .collect(),
                },
            )?),
            _get_transition_graph: Some(server::<GetAvailableTransitions>(
                node,
                graph,
                shared,
                |_, _| GetAvailableTransitionsResponse {
                    available_transitions: Transition::ALL
                        .iter()
                        .map(|t| t.description())
                        .collect(),
                },
            )?),
        })
    }
}
