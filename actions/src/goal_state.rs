//! The goal state machine, exactly as rcl_action draws it (`rcl_action/src/rcl_action/
//! goal_state_machine.c`, `rcl_action_transition_goal_state`; states and events in
//! `rcl_action/include/rcl_action/types.h`, the state values `action_msgs/msg/GoalStatus`'s
//! `STATUS_*`):
//!
//! ```text
//! ACCEPTED  --EXECUTE-->     EXECUTING
//! ACCEPTED  --CANCEL_GOAL--> CANCELING
//! EXECUTING --CANCEL_GOAL--> CANCELING
//! EXECUTING --SUCCEED-->     SUCCEEDED      CANCELING --SUCCEED--> SUCCEEDED
//! EXECUTING --ABORT-->       ABORTED        CANCELING --ABORT-->   ABORTED
//!                                           CANCELING --CANCELED-> CANCELED
//! ```
//!
//! Every other pair is invalid (rcl returns `GOAL_STATE_UNKNOWN`; here an [`InvalidTransition`]).

use horus_ros_msgs::action_msgs::msg::GoalStatus;

/// The state of a goal: `action_msgs/msg/GoalStatus` `STATUS_*` (but `STATUS_UNKNOWN`, which no
/// goal of a server is in).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GoalState {
    /// Accepted, not yet executing (`STATUS_ACCEPTED`, 1).
    Accepted,
    /// Executing (`STATUS_EXECUTING`, 2).
    Executing,
    /// Cancel requested and accepted; still running until it ends (`STATUS_CANCELING`, 3).
    Canceling,
    /// Ended successfully (`STATUS_SUCCEEDED`, 4).
    Succeeded,
    /// Ended after a cancel request (`STATUS_CANCELED`, 5).
    Canceled,
    /// Ended by the server without success (`STATUS_ABORTED`, 6).
    Aborted,
}

/// An event of the goal state machine (rcl_action `rcl_action_goal_event_t`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GoalEvent {
    /// Execution starts (`GOAL_EVENT_EXECUTE`).
    Execute,
    /// A cancel request was accepted (`GOAL_EVENT_CANCEL_GOAL`).
    CancelGoal,
    /// The goal succeeded (`GOAL_EVENT_SUCCEED`).
    Succeed,
    /// The goal was aborted (`GOAL_EVENT_ABORT`).
    Abort,
    /// The goal ended canceled (`GOAL_EVENT_CANCELED`).
    Canceled,
}

/// An event that the goal's state does not allow (rcl_action: `GOAL_STATE_UNKNOWN`,
/// `RCL_RET_ACTION_GOAL_EVENT_INVALID`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("goal event {event:?} is invalid in state {state:?}")]
pub struct InvalidTransition {
    /// The goal's state.
    pub state: GoalState,
    /// The event refused.
    pub event: GoalEvent,
}

impl GoalState {
    /// The state after `event`, as `rcl_action_transition_goal_state`.
    pub fn transition(self, event: GoalEvent) -> Result<GoalState, InvalidTransition> {
        use GoalEvent as E;
        use GoalState as S;
        match (self, event) {
            (S::Accepted, E::Execute) => Ok(S::Executing),
            (S::Accepted | S::Executing, E::CancelGoal) => Ok(S::Canceling),
            (S::Executing | S::Canceling, E::Succeed) => Ok(S::Succeeded),
            (S::Executing | S::Canceling, E::Abort) => Ok(S::Aborted),
            (S::Canceling, E::Canceled) => Ok(S::Canceled),
            (state, event) => Err(InvalidTransition { state, event }),
        }
    }

    /// Whether the goal is still active (ACCEPTED, EXECUTING, CANCELING): what
    /// `rcl_action_goal_handle_is_active` says.
    pub fn is_active(self) -> bool {
        matches!(self, Self::Accepted | Self::Executing | Self::Canceling)
    }

    /// Whether a cancel request may still move the goal (ACCEPTED or EXECUTING):
    /// `rcl_action_goal_handle_is_cancelable`, which asks whether CANCEL_GOAL is a valid event.
    pub fn is_cancelable(self) -> bool {
        self.transition(GoalEvent::CancelGoal).is_ok()
    }

    /// Whether the goal has ended (SUCCEEDED, CANCELED, ABORTED).
    pub fn is_terminal(self) -> bool {
        !self.is_active()
    }

    /// The `action_msgs/msg/GoalStatus` `STATUS_*` value.
    pub fn status(self) -> i8 {
        match self {
            Self::Accepted => GoalStatus::STATUS_ACCEPTED,
            Self::Executing => GoalStatus::STATUS_EXECUTING,
            Self::Canceling => GoalStatus::STATUS_CANCELING,
            Self::Succeeded => GoalStatus::STATUS_SUCCEEDED,
            Self::Canceled => GoalStatus::STATUS_CANCELED,
            Self::Aborted => GoalStatus::STATUS_ABORTED,
        }
    }

    /// The state of a `STATUS_*` value (`None` for `STATUS_UNKNOWN` and any other value).
    pub fn from_status(status: i8) -> Option<Self> {
        Some(match status {
            GoalStatus::STATUS_ACCEPTED => Self::Accepted,
            GoalStatus::STATUS_EXECUTING => Self::Executing,
            GoalStatus::STATUS_CANCELING => Self::Canceling,
            GoalStatus::STATUS_SUCCEEDED => Self::Succeeded,
            GoalStatus::STATUS_CANCELED => Self::Canceled,
            GoalStatus::STATUS_ABORTED => Self::Aborted,
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STATES: [GoalState; 6] = [
        GoalState::Accepted,
        GoalState::Executing,
        GoalState::Canceling,
        GoalState::Succeeded,
        GoalState::Canceled,
        GoalState::Aborted,
    ];
    const EVENTS: [GoalEvent; 5] = [
        GoalEvent::Execute,
        GoalEvent::CancelGoal,
        GoalEvent::Succeed,
        GoalEvent::Abort,
        GoalEvent::Canceled,
    ];

    /// The whole table of goal_state_machine.c's `_goal_state_transition_map`: 30 pairs, 8 valid.
    #[test]
    fn every_pair_is_as_rcl_action_maps_it() {
        use GoalEvent as E;
        use GoalState as S;
        let valid = [
            (S::Accepted, E::Execute, S::Executing),
            (S::Accepted, E::CancelGoal, S::Canceling),
            (S::Executing, E::CancelGoal, S::Canceling),
            (S::Executing, E::Succeed, S::Succeeded),
            (S::Executing, E::Abort, S::Aborted),
            (S::Canceling, E::Succeed, S::Succeeded),
            (S::Canceling, E::Abort, S::Aborted),
            (S::Canceling, E::Canceled, S::Canceled),
        ];
        for state in STATES {
            for event in EVENTS {
                let expected = valid
                    .iter()
                    .find(|(s, e, _)| *s == state && *e == event)
                    .map(|(_, _, to)| *to);
                match expected {
                    Some(to) => assert_eq!(state.transition(event), Ok(to), "{state:?} {event:?}"),
                    None => assert_eq!(
                        state.transition(event),
                        Err(InvalidTransition { state, event }),
                        "{state:?} {event:?}"
                    ),
                }
            }
        }
    }

    #[test]
    fn accepted_goals_cannot_end_before_executing() {
        // rcl_action has no ACCEPTED --SUCCEED/ABORT/CANCELED--> edge.
        for event in [GoalEvent::Succeed, GoalEvent::Abort, GoalEvent::Canceled] {
            assert!(GoalState::Accepted.transition(event).is_err());
        }
    }

    #[test]
    fn terminal_states_accept_no_event() {
        for state in [
            GoalState::Succeeded,
            GoalState::Canceled,
            GoalState::Aborted,
        ] {
            assert!(state.is_terminal() && !state.is_active() && !state.is_cancelable());
            for event in EVENTS {
                assert!(state.transition(event).is_err());
            }
        }
    }

    #[test]
    fn cancelable_is_accepted_or_executing() {
        let cancelable: Vec<_> = STATES.into_iter().filter(|s| s.is_cancelable()).collect();
        assert_eq!(cancelable, [GoalState::Accepted, GoalState::Executing]);
    }

    #[test]
    fn status_values_round_trip() {
        for (state, value) in STATES.into_iter().zip(1i8..) {
            assert_eq!(state.status(), value);
            assert_eq!(GoalState::from_status(value), Some(state));
        }
        assert_eq!(GoalState::from_status(GoalStatus::STATUS_UNKNOWN), None);
        assert_eq!(GoalState::from_status(7), None);
    }
}
