//! The default lifecycle state machine, exactly as rcl_lifecycle draws it
//! (`rcl_lifecycle/src/default_state_machine.c`, `rcl_lifecycle_init_default_state_machine`):
//! the same states with the same ids and labels, the same transitions with the same ids, labels,
//! start and goal states, registered in the same order (the order `~/get_available_states`,
//! `~/get_available_transitions` and `~/get_transition_graph` answer in), and the same lookups
//! (`rcl_lifecycle_get_transition_by_id` / `_by_label` search the current state's valid
//! transitions only).
//!
//! A pure data structure: no DDS, no callbacks. [`LifecycleNode`](crate::LifecycleNode) drives
//! it as rclcpp_lifecycle's `LifecycleNodeInterfaceImpl::change_state` does.

use horus_ros_msgs::lifecycle_msgs::msg;

/// A state of the default state machine: the five primary states (ids 0–4) and the six
/// transition states (ids 10–15) of `lifecycle_msgs/msg/State`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum State {
    /// `unknown` (0): registered by rcl, never entered.
    Unknown = msg::State::PRIMARY_STATE_UNKNOWN,
    /// `unconfigured` (1): the initial state.
    Unconfigured = msg::State::PRIMARY_STATE_UNCONFIGURED,
    /// `inactive` (2): configured, not processing.
    Inactive = msg::State::PRIMARY_STATE_INACTIVE,
    /// `active` (3): processing.
    Active = msg::State::PRIMARY_STATE_ACTIVE,
    /// `finalized` (4): the end; no transition leaves it.
    Finalized = msg::State::PRIMARY_STATE_FINALIZED,
    /// `configuring` (10): `on_configure` runs.
    Configuring = msg::State::TRANSITION_STATE_CONFIGURING,
    /// `cleaningup` (11): `on_cleanup` runs.
    CleaningUp = msg::State::TRANSITION_STATE_CLEANINGUP,
    /// `shuttingdown` (12): `on_shutdown` runs.
    ShuttingDown = msg::State::TRANSITION_STATE_SHUTTINGDOWN,
    /// `activating` (13): `on_activate` runs.
    Activating = msg::State::TRANSITION_STATE_ACTIVATING,
    /// `deactivating` (14): `on_deactivate` runs.
    Deactivating = msg::State::TRANSITION_STATE_DEACTIVATING,
    /// `errorprocessing` (15): `on_error` runs.
    ErrorProcessing = msg::State::TRANSITION_STATE_ERRORPROCESSING,
}

impl State {
    /// Every state, in rcl's registration order (`_register_primary_states`, then
    /// `_register_transition_states`): what `~/get_available_states` answers.
    pub const ALL: [State; 11] = [
        State::Unknown,
        State::Unconfigured,
        State::Inactive,
        State::Active,
        State::Finalized,
        State::Configuring,
        State::CleaningUp,
        State::ShuttingDown,
        State::Activating,
        State::Deactivating,
        State::ErrorProcessing,
    ];

    /// The state's id (`lifecycle_msgs/msg/State` constants).
    pub const fn id(self) -> u8 {
        self as u8
    }

    /// The state's label, as rcl registers it (`"unconfigured"`, `"cleaningup"`, …).
    pub const fn label(self) -> &'static str {
        match self {
            State::Unknown => "unknown",
            State::Unconfigured => "unconfigured",
            State::Inactive => "inactive",
            State::Active => "active",
            State::Finalized => "finalized",
            State::Configuring => "configuring",
            State::CleaningUp => "cleaningup",
            State::ShuttingDown => "shuttingdown",
            State::Activating => "activating",
            State::Deactivating => "deactivating",
            State::ErrorProcessing => "errorprocessing",
        }
    }

    /// The state with this id, if the default state machine has one.
    pub fn from_id(id: u8) -> Option<State> {
        State::ALL.into_iter().find(|s| s.id() == id)
    }

    /// Whether this is a primary state (ids 0–4); the others are transition states.
    pub const fn is_primary(self) -> bool {
        (self as u8) < 10
    }

    /// The state as a `lifecycle_msgs/msg/State`.
    pub fn to_msg(self) -> msg::State {
        msg::State {
            id: self.id(),
            label: self.label().to_owned(),
        }
    }

    /// The valid transitions out of this state, in rcl's registration order (each transition is
    /// appended to its start state's list as it is registered: `rcl_lifecycle_register_transition`).
    pub fn transitions(self) -> impl Iterator<Item = Transition> {
        Transition::ALL
            .into_iter()
            .filter(move |t| t.start() == self)
    }
}

impl std::fmt::Display for State {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
    }
}

/// rcl_lifecycle's transition labels (`default_state_machine.c`).
pub mod labels {
    /// `rcl_lifecycle_configure_label`.
    pub const CONFIGURE: &str = "configure";
    /// `rcl_lifecycle_cleanup_label`.
    pub const CLEANUP: &str = "cleanup";
    /// `rcl_lifecycle_activate_label`.
    pub const ACTIVATE: &str = "activate";
    /// `rcl_lifecycle_deactivate_label`.
    pub const DEACTIVATE: &str = "deactivate";
    /// `rcl_lifecycle_shutdown_label` (the three shutdown transitions share it).
    pub const SHUTDOWN: &str = "shutdown";
    /// `rcl_lifecycle_transition_success_label`.
    pub const TRANSITION_SUCCESS: &str = "transition_success";
    /// `rcl_lifecycle_transition_failure_label`.
    pub const TRANSITION_FAILURE: &str = "transition_failure";
    /// `rcl_lifecycle_transition_error_label`.
    pub const TRANSITION_ERROR: &str = "transition_error";
}

/// A transition of the default state machine, with its `lifecycle_msgs/msg/Transition` id.
///
/// The ids 1–7 are the transitions a node is asked for (`~/change_state`); 10–62 are taken
/// with the result of a transition state's callback (`on_configure_success` …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Transition {
    /// `configure` (1): unconfigured → configuring.
    Configure = msg::Transition::TRANSITION_CONFIGURE,
    /// `cleanup` (2): inactive → cleaningup.
    Cleanup = msg::Transition::TRANSITION_CLEANUP,
    /// `activate` (3): inactive → activating.
    Activate = msg::Transition::TRANSITION_ACTIVATE,
    /// `deactivate` (4): active → deactivating.
    Deactivate = msg::Transition::TRANSITION_DEACTIVATE,
    /// `shutdown` (5): unconfigured → shuttingdown.
    UnconfiguredShutdown = msg::Transition::TRANSITION_UNCONFIGURED_SHUTDOWN,
    /// `shutdown` (6): inactive → shuttingdown.
    InactiveShutdown = msg::Transition::TRANSITION_INACTIVE_SHUTDOWN,
    /// `shutdown` (7): active → shuttingdown.
    ActiveShutdown = msg::Transition::TRANSITION_ACTIVE_SHUTDOWN,
    /// `transition_success` (10): configuring → inactive.
    OnConfigureSuccess = msg::Transition::TRANSITION_ON_CONFIGURE_SUCCESS,
    /// `transition_failure` (11): configuring → unconfigured.
    OnConfigureFailure = msg::Transition::TRANSITION_ON_CONFIGURE_FAILURE,
    /// `transition_error` (12): configuring → errorprocessing.
    OnConfigureError = msg::Transition::TRANSITION_ON_CONFIGURE_ERROR,
    /// `transition_success` (20): cleaningup → unconfigured.
    OnCleanupSuccess = msg::Transition::TRANSITION_ON_CLEANUP_SUCCESS,
    /// `transition_failure` (21): cleaningup → inactive.
    OnCleanupFailure = msg::Transition::TRANSITION_ON_CLEANUP_FAILURE,
    /// `transition_error` (22): cleaningup → errorprocessing.
    OnCleanupError = msg::Transition::TRANSITION_ON_CLEANUP_ERROR,
    /// `transition_success` (30): activating → active.
    OnActivateSuccess = msg::Transition::TRANSITION_ON_ACTIVATE_SUCCESS,
    /// `transition_failure` (31): activating → inactive.
    OnActivateFailure = msg::Transition::TRANSITION_ON_ACTIVATE_FAILURE,
    /// `transition_error` (32): activating → errorprocessing.
    OnActivateError = msg::Transition::TRANSITION_ON_ACTIVATE_ERROR,
    /// `transition_success` (40): deactivating → inactive.
    OnDeactivateSuccess = msg::Transition::TRANSITION_ON_DEACTIVATE_SUCCESS,
    /// `transition_failure` (41): deactivating → active.
    OnDeactivateFailure = msg::Transition::TRANSITION_ON_DEACTIVATE_FAILURE,
    /// `transition_error` (42): deactivating → errorprocessing.
    OnDeactivateError = msg::Transition::TRANSITION_ON_DEACTIVATE_ERROR,
    /// `transition_success` (50): shuttingdown → finalized.
    OnShutdownSuccess = msg::Transition::TRANSITION_ON_SHUTDOWN_SUCCESS,
    /// `transition_failure` (51): shuttingdown → finalized.
    OnShutdownFailure = msg::Transition::TRANSITION_ON_SHUTDOWN_FAILURE,
    /// `transition_error` (52): shuttingdown → errorprocessing.
    OnShutdownError = msg::Transition::TRANSITION_ON_SHUTDOWN_ERROR,
    /// `transition_success` (60): errorprocessing → unconfigured.
    OnErrorSuccess = msg::Transition::TRANSITION_ON_ERROR_SUCCESS,
    /// `transition_failure` (61): errorprocessing → finalized.
    OnErrorFailure = msg::Transition::TRANSITION_ON_ERROR_FAILURE,
    /// `transition_error` (62): errorprocessing → finalized.
    OnErrorError = msg::Transition::TRANSITION_ON_ERROR_ERROR,
}

impl Transition {
    /// Every transition, in rcl's registration order (`_register_transitions`): what
    /// `~/get_transition_graph` answers.
    pub const ALL: [Transition; 25] = [
        Transition::Configure,
        Transition::OnConfigureSuccess,
        Transition::OnConfigureFailure,
        Transition::OnConfigureError,
        Transition::Cleanup,
        Transition::OnCleanupSuccess,
        Transition::OnCleanupFailure,
        Transition::OnCleanupError,
        Transition::Activate,
        Transition::OnActivateSuccess,
        Transition::OnActivateFailure,
        Transition::OnActivateError,
        Transition::Deactivate,
        Transition::OnDeactivateSuccess,
        Transition::OnDeactivateFailure,
        Transition::OnDeactivateError,
        Transition::UnconfiguredShutdown,
        Transition::InactiveShutdown,
        Transition::ActiveShutdown,
        Transition::OnShutdownSuccess,
        Transition::OnShutdownFailure,
        Transition::OnShutdownError,
        Transition::OnErrorSuccess,
        Transition::OnErrorFailure,
        Transition::OnErrorError,
    ];

    /// The transition's id (`lifecycle_msgs/msg/Transition` constants).
    pub const fn id(self) -> u8 {
        self as u8
    }

    /// The transition with this id, if the default state machine has one.
    pub fn from_id(id: u8) -> Option<Transition> {
        Transition::ALL.into_iter().find(|t| t.id() == id)
    }

    /// The transition's label, as rcl registers it (see [`labels`]).
    pub const fn label(self) -> &'static str {
        use Transition as T;
        match self {
            T::Configure => labels::CONFIGURE,
            T::Cleanup => labels::CLEANUP,
            T::Activate => labels::ACTIVATE,
            T::Deactivate => labels::DEACTIVATE,
            T::UnconfiguredShutdown | T::InactiveShutdown | T::ActiveShutdown => labels::SHUTDOWN,
            T::OnConfigureSuccess
            | T::OnCleanupSuccess
            | T::OnActivateSuccess
            | T::OnDeactivateSuccess
            | T::OnShutdownSuccess
            | T::OnErrorSuccess => labels::TRANSITION_SUCCESS,
            T::OnConfigureFailure
            | T::OnCleanupFailure
            | T::OnActivateFailure
            | T::OnDeactivateFailure
            | T::OnShutdownFailure
            | T::OnErrorFailure => labels::TRANSITION_FAILURE,
            T::OnConfigureError
            | T::OnCleanupError
            | T::OnActivateError
            | T::OnDeactivateError
            | T::OnShutdownError
            | T::OnErrorError => labels::TRANSITION_ERROR,
        }
    }

    /// The state the transition leaves.
    pub const fn start(self) -> State {
        use State as S;
        use Transition as T;
        match self {
            T::Configure | T::UnconfiguredShutdown => S::Unconfigured,
            T::Cleanup | T::Activate | T::InactiveShutdown => S::Inactive,
            T::Deactivate | T::ActiveShutdown => S::Active,
            T::OnConfigureSuccess | T::OnConfigureFailure | T::OnConfigureError => S::Configuring,
            T::OnCleanupSuccess | T::OnCleanupFailure | T::OnCleanupError => S::CleaningUp,
            T::OnActivateSuccess | T::OnActivateFailure | T::OnActivateError => S::Activating,
            T::OnDeactivateSuccess | T::OnDeactivateFailure | T::OnDeactivateError => {
                S::Deactivating
            }
            T::OnShutdownSuccess | T::OnShutdownFailure | T::OnShutdownError => S::ShuttingDown,
            T::OnErrorSuccess | T::OnErrorFailure | T::OnErrorError => S::ErrorProcessing,
        }
    }

    /// The state the transition reaches.
    pub const fn goal(self) -> State {
        use State as S;
        use Transition as T;
        match self {
            T::Configure => S::Configuring,
            T::Cleanup => S::CleaningUp,
            T::Activate => S::Activating,
            T::Deactivate => S::Deactivating,
            T::UnconfiguredShutdown | T::InactiveShutdown | T::ActiveShutdown => S::ShuttingDown,
            T::OnConfigureSuccess | T::OnCleanupFailure | T::OnActivateFailure => S::Inactive,
            T::OnDeactivateSuccess => S::Inactive,
            T::OnConfigureFailure | T::OnCleanupSuccess | T::OnErrorSuccess => S::Unconfigured,
            T::OnActivateSuccess | T::OnDeactivateFailure => S::Active,
            T::OnShutdownSuccess | T::OnShutdownFailure => S::Finalized,
            T::OnErrorFailure | T::OnErrorError => S::Finalized,
            T::OnConfigureError
            | T::OnCleanupError
            | T::OnActivateError
            | T::OnDeactivateError
            | T::OnShutdownError => S::ErrorProcessing,
        }
    }

    /// The transition as a `lifecycle_msgs/msg/Transition`.
    pub fn to_msg(self) -> msg::Transition {
        msg::Transition {
            id: self.id(),
            label: self.label().to_owned(),
        }
    }

    /// The transition as a `lifecycle_msgs/msg/TransitionDescription` (its start and goal).
    pub fn description(self) -> msg::TransitionDescription {
        msg::TransitionDescription {
            transition: self.to_msg(),
            start_state: self.start().to_msg(),
            goal_state: self.goal().to_msg(),
        }
    }
}

impl std::fmt::Display for Transition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} [{}]", self.label(), self.id())
    }
}

/// What a transition callback returns (rclcpp's
/// `LifecycleNodeInterface::CallbackReturn`, rclpy's `TransitionCallbackReturn`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum CallbackReturn {
    /// The transition succeeds (`TRANSITION_CALLBACK_SUCCESS`, 97): the
    /// `transition_success` transition is taken.
    #[default]
    Success = msg::Transition::TRANSITION_CALLBACK_SUCCESS,
    /// The transition fails and the node returns to where it was
    /// (`TRANSITION_CALLBACK_FAILURE`, 98): `transition_failure`.
    Failure = msg::Transition::TRANSITION_CALLBACK_FAILURE,
    /// An error: the node goes to `errorprocessing`, where `on_error` decides between
    /// `unconfigured` and `finalized` (`TRANSITION_CALLBACK_ERROR`, 99): `transition_error`.
    Error = msg::Transition::TRANSITION_CALLBACK_ERROR,
}

impl CallbackReturn {
    /// The label of the transition this result takes (rclcpp's `get_label_for_return_code`,
    /// rclpy's `TransitionCallbackReturn.to_label`).
    pub const fn label(self) -> &'static str {
        match self {
            CallbackReturn::Success => labels::TRANSITION_SUCCESS,
            CallbackReturn::Failure => labels::TRANSITION_FAILURE,
            CallbackReturn::Error => labels::TRANSITION_ERROR,
        }
    }
}

/// Why [`StateMachine::trigger`] did nothing: the transition does not leave the current state
/// (rcl's `No transition matching … found for current state …`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("no transition matching {requested} found for current state {state}")]
pub struct TriggerError {
    /// The id or label asked for.
    pub requested: String,
    /// The state the machine is in (and stays in).
    pub state: State,
}

/// The default state machine's current state, and its transitions (rcl's
/// `rcl_lifecycle_state_machine_t` with the default transition map).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateMachine {
    current: State,
}

impl Default for StateMachine {
    fn default() -> Self {
        Self::new()
    }
}

impl StateMachine {
    /// A state machine in `unconfigured`, as `rcl_lifecycle_init_default_state_machine` leaves it.
    pub const fn new() -> Self {
        Self {
            current: State::Unconfigured,
        }
    }

    /// The current state.
    pub const fn current(&self) -> State {
        self.current
    }

    /// The transitions valid from the current state, in rcl's order (what
    /// `~/get_available_transitions` answers).
    pub fn available_transitions(&self) -> Vec<Transition> {
        self.current.transitions().collect()
    }

    /// `rcl_lifecycle_get_transition_by_id` on the current state.
    pub fn transition_by_id(&self, id: u8) -> Option<Transition> {
        self.current.transitions().find(|t| t.id() == id)
    }

    /// `rcl_lifecycle_get_transition_by_label` on the current state: the first valid transition
    /// with this label (each state has at most one per label).
    pub fn transition_by_label(&self, label: &str) -> Option<Transition> {
        self.current.transitions().find(|t| t.label() == label)
    }

    /// Takes `transition` if it leaves the current state (`_trigger_transition`); returns it.
    pub fn trigger(&mut self, transition: Transition) -> Result<Transition, TriggerError> {
        if transition.start() != self.current {
            return Err(TriggerError {
                requested: transition.id().to_string(),
                state: self.current,
            });
        }
        self.current = transition.goal();
        Ok(transition)
    }

    /// `rcl_lifecycle_trigger_transition_by_id`.
    pub fn trigger_by_id(&mut self, id: u8) -> Result<Transition, TriggerError> {
        let transition = self.transition_by_id(id).ok_or_else(|| TriggerError {
            requested: id.to_string(),
            state: self.current,
        })?;
        self.trigger(transition)
    }

    /// `rcl_lifecycle_trigger_transition_by_label`.
    pub fn trigger_by_label(&mut self, label: &str) -> Result<Transition, TriggerError> {
        let transition = self
            .transition_by_label(label)
            .ok_or_else(|| TriggerError {
                requested: label.to_owned(),
                state: self.current,
            })?;
        self.trigger(transition)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table of `_register_transitions`, as written there: id, label, start, goal.
    const RCL: [(u8, &str, u8, u8); 25] = [
        (1, "configure", 1, 10),
        (10, "transition_success", 10, 2),
        (11, "transition_failure", 10, 1),
        (12, "transition_error", 10, 15),
        (2, "cleanup", 2, 11),
        (20, "transition_success", 11, 1),
        (21, "transition_failure", 11, 2),
        (22, "transition_error", 11, 15),
        (3, "activate", 2, 13),
        (30, "transition_success", 13, 3),
        (31, "transition_failure", 13, 2),
        (32, "transition_error", 13, 15),
        (4, "deactivate", 3, 14),
        (40, "transition_success", 14, 2),
        (41, "transition_failure", 14, 3),
        (42, "transition_error", 14, 15),
        (5, "shutdown", 1, 12),
        (6, "shutdown", 2, 12),
        (7, "shutdown", 3, 12),
        (50, "transition_success", 12, 4),
        (51, "transition_failure", 12, 4),
        (52, "transition_error", 12, 15),
        (60, "transition_success", 15, 1),
        (61, "transition_failure", 15, 4),
        (62, "transition_error", 15, 4),
    ];

    #[test]
    fn transition_table_is_rcls() {
        let ours: Vec<_> = Transition::ALL
            .iter()
            .map(|t| (t.id(), t.label(), t.start().id(), t.goal().id()))
            .collect();
        assert_eq!(ours, RCL.to_vec());
    }

    #[test]
    fn states_are_rcls() {
        let ours: Vec<_> = State::ALL.iter().map(|s| (s.id(), s.label())).collect();
        assert_eq!(
            ours,
            [
                (0, "unknown"),
                (1, "unconfigured"),
                (2, "inactive"),
                (3, "active"),
                (4, "finalized"),
                (10, "configuring"),
                (11, "cleaningup"),
                (12, "shuttingdown"),
                (13, "activating"),
                (14, "deactivating"),
                (15, "errorprocessing"),
            ]
        );
        for s in State::ALL {
            assert_eq!(State::from_id(s.id()), Some(s));
            assert_eq!(s.is_primary(), s.id() < 5);
        }
        assert_eq!(State::from_id(5), None);
        for t in Transition::ALL {
            assert_eq!(Transition::from_id(t.id()), Some(t));
        }
        assert_eq!(Transition::from_id(0), None);
        assert_eq!(Transition::from_id(8), None);
    }

    /// Every transition of the table is taken from its start state and only from there, by id
    /// and by label, and reaches its goal.
    #[test]
    fn every_transition_from_every_state() {
        for state in State::ALL {
            for t in Transition::ALL {
                let mut m = StateMachine { current: state };
                let by_id = m.trigger_by_id(t.id());
                if t.start() == state {
                    assert_eq!(by_id, Ok(t), "{t} from {state}");
                    assert_eq!(m.current(), t.goal());
                } else {
                    assert!(by_id.is_err(), "{t} from {state}");
                    assert_eq!(m.current(), state);
                    assert_eq!(
                        by_id.err().map(|e| e.to_string()),
                        Some(format!(
                            "no transition matching {} found for current state {state}",
                            t.id()
                        ))
                    );
                }
                let mut m = StateMachine { current: state };
                match m.trigger_by_label(t.label()) {
                    // The label names this state's own transition of that label.
                    Ok(taken) => {
                        assert_eq!(taken.start(), state);
                        assert_eq!(taken.label(), t.label());
                        assert_eq!(m.current(), taken.goal());
                    }
                    Err(e) => {
                        assert!(state.transitions().all(|x| x.label() != t.label()));
                        assert_eq!(e.state, state);
                        assert_eq!(m.current(), state);
                    }
                }
            }
        }
    }

    #[test]
    fn available_transitions_per_state() {
        let ids = |s: State| {
            StateMachine { current: s }
                .available_transitions()
                .iter()
                .map(|t| t.id())
                .collect::<Vec<_>>()
        };
        assert_eq!(ids(State::Unknown), Vec::<u8>::new());
        assert_eq!(ids(State::Unconfigured), [1, 5]);
        assert_eq!(ids(State::Inactive), [2, 3, 6]);
        assert_eq!(ids(State::Active), [4, 7]);
        assert_eq!(ids(State::Finalized), Vec::<u8>::new());
        assert_eq!(ids(State::Configuring), [10, 11, 12]);
        assert_eq!(ids(State::CleaningUp), [20, 21, 22]);
        assert_eq!(ids(State::ShuttingDown), [50, 51, 52]);
        assert_eq!(ids(State::Activating), [30, 31, 32]);
        assert_eq!(ids(State::Deactivating), [40, 41, 42]);
        assert_eq!(ids(State::ErrorProcessing), [60, 61, 62]);
    }

    /// SUCCESS, FAILURE and ERROR from every transition state, then on_error's result.
    #[test]
    fn callback_results_lead_where_rcl_says() {
        use CallbackReturn::*;
        let cases = [
            (State::Configuring, Success, State::Inactive),
            (State::Configuring, Failure, State::Unconfigured),
            (State::Configuring, Error, State::ErrorProcessing),
            (State::CleaningUp, Success, State::Unconfigured),
            (State::CleaningUp, Failure, State::Inactive),
            (State::CleaningUp, Error, State::ErrorProcessing),
            (State::Activating, Success, State::Active),
            (State::Activating, Failure, State::Inactive),
            (State::Activating, Error, State::ErrorProcessing),
            (State::Deactivating, Success, State::Inactive),
            (State::Deactivating, Failure, State::Active),
            (State::Deactivating, Error, State::ErrorProcessing),
            (State::ShuttingDown, Success, State::Finalized),
            (State::ShuttingDown, Failure, State::Finalized),
            (State::ShuttingDown, Error, State::ErrorProcessing),
            (State::ErrorProcessing, Success, State::Unconfigured),
            (State::ErrorProcessing, Failure, State::Finalized),
            (State::ErrorProcessing, Error, State::Finalized),
        ];
        for (from, result, to) in cases {
            let mut m = StateMachine { current: from };
            assert!(m.trigger_by_label(result.label()).is_ok());
            assert_eq!(m.current(), to, "{result:?} in {from}");
        }
        assert_eq!(Success as u8, 97);
        assert_eq!(Failure as u8, 98);
        assert_eq!(Error as u8, 99);
    }

    #[test]
    fn starts_unconfigured_and_shutdown_by_label_follows_the_state() {
        let mut m = StateMachine::new();
        assert_eq!(m.current(), State::Unconfigured);
        assert_eq!(
            m.transition_by_label("shutdown"),
            Some(Transition::UnconfiguredShutdown)
        );
        m.current = State::Inactive;
        assert_eq!(
            m.transition_by_label("shutdown"),
            Some(Transition::InactiveShutdown)
        );
        m.current = State::Active;
        assert_eq!(
            m.transition_by_label("shutdown"),
            Some(Transition::ActiveShutdown)
        );
        assert_eq!(m.transition_by_label("configure"), None);
        assert_eq!(m.transition_by_id(0), None);
    }

    #[test]
    fn messages() {
        let d = Transition::OnActivateError.description();
        assert_eq!(
            (d.transition.id, d.transition.label.as_str()),
            (32, "transition_error")
        );
        assert_eq!(
            (d.start_state.id, d.start_state.label.as_str()),
            (13, "activating")
        );
        assert_eq!(
            (d.goal_state.id, d.goal_state.label.as_str()),
            (15, "errorprocessing")
        );
    }
}
