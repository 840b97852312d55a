//! An rclpy 7.1 client on the run's RMW (`HORUS_ROS_PEER_RMW`: rmw_fastrtps_cpp by default, or
//! rmw_cyclonedds_cpp; `peers/jazzy_lifecycle.py`, calling lifecycle_msgs' services as
//! ros2lifecycle's api does) drives our [`LifecycleNode`] through every transition
//! of the default state machine — successes, failures, errors, a panicking callback, unknown
//! labels and ids — and takes its `~/transition_event`s, as a real Jazzy peer would.
//!
//! Each test has its own domain (201-203). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-lifecycle --test jazzy_drives_ours`.
//! The service tests run our side on the backend HORUS_ROS_BACKEND chooses, but on the rustdds
//! backend when the peer runs on rmw_fastrtps and that backend is Cyclone (which cannot speak
//! rmw_fastrtps' service convention); the transition-event test runs on the backend
//! HORUS_ROS_BACKEND chooses.

mod common;

use common::{context, event, pair, service_context, wait_matched, Behave, Peer, Scripted};
use horus_ros_graph::Graph;
use horus_ros_lifecycle::{CallbackReturn, LifecycleNode, State, Transition, TransitionError};
use serde_json::{json, Value};

const NODE: &str = "/managed";

/// Our managed node `/managed` in `context`, and the peer watching its transition events
/// (matched before anything happens, so that no event is lost).
fn setup(context: &horus_ros_rmw::Context, domain: u32) -> (LifecycleNode, Scripted, Peer) {
    let node = context.create_node("managed", "/").expect("node");
    let scripted = Scripted::default();
    let managed = LifecycleNode::builder()
        .node(&node)
        .callbacks(scripted.clone())
        .build()
        .expect("lifecycle node");
    let peer = Peer::start(&json!({"domain": domain, "name": "driver", "watch": [NODE]}));
    let graph = Graph::of(context).expect("graph");
    wait_matched(
        &graph,
        managed.transition_event_gid().expect("publisher"),
        "/managed/transition_event",
        true,
    );
    (managed, scripted, peer)
}

/// One change_state call from rclpy: checks the reply, the state after it and the events it
/// caused (appended to `events`: every event so far, in order).
fn change(
    peer: &mut Peer,
    request: Value,
    success: bool,
    after: State,
    caused: &[(State, State)],
    events: &mut Vec<Value>,
) {
    assert_eq!(
        peer.call(NODE, "change_state", request.clone()),
        json!(success),
        "change_state {request}"
    );
    assert_eq!(
        peer.call(NODE, "get_state", json!({})),
        pair(after.id(), after.label()),
        "after {request}"
    );
    events.extend(
        caused
            .iter()
            .map(|(s, g)| event(NODE, (s.id(), s.label()), (g.id(), g.label()))),
    );
    let got = peer.wait_count("event", events.len());
    assert_eq!(&got, events, "events after {request}");
}

fn transitions_json(ts: impl IntoIterator<Item = Transition>) -> Value {
    ts.into_iter()
        .map(|t| {
            json!({"transition": [t.id(), t.label()],
                   "start": [t.start().id(), t.start().label()],
                   "goal": [t.goal().id(), t.goal().label()]})
        })
        .collect()
}

#[test]
fn rclpy_drives_every_transition_and_the_failure_paths() {
    use CallbackReturn::*;
    use State::*;
    let domain = 201;
    let context = service_context(domain);
    let (managed, scripted, mut peer) = setup(&context, domain);
    let mut events = Vec::new();

    // What a Jazzy client reads of the state machine: rcl's states and transitions, in order.
    let states: Value = State::ALL.iter().map(|s| pair(s.id(), s.label())).collect();
    assert_eq!(peer.call(NODE, "get_available_states", json!({})), states);
    assert_eq!(
        peer.call(NODE, "get_transition_graph", json!({})),
        transitions_json(Transition::ALL)
    );
    assert_eq!(
        peer.call(NODE, "get_state", json!({})),
        pair(1, "unconfigured")
    );
    assert_eq!(
        peer.call(NODE, "get_available_transitions", json!({})),
        transitions_json([Transition::Configure, Transition::UnconfiguredShutdown])
    );

    // configure: FAILURE (11) back to unconfigured, then SUCCESS (10) by id.
    scripted.set("on_configure", Behave::Return(Failure));
    let configure = json!({"label": "configure"});
    change(
        &mut peer,
        configure.clone(),
        false,
        Unconfigured,
        &[(Unconfigured, Configuring), (Configuring, Unconfigured)],
        &mut events,
    );
    scripted.set("on_configure", Behave::Return(Success));
    change(
        &mut peer,
        json!({"id": 1}),
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
        &mut events,
    );
    assert_eq!(
        peer.call(NODE, "get_available_transitions", json!({})),
        transitions_json([
            Transition::Cleanup,
            Transition::Activate,
            Transition::InactiveShutdown
        ])
    );

    // activate: FAILURE (31) back to inactive, then SUCCESS (30).
    scripted.set("on_activate", Behave::Return(Failure));
    change(
        &mut peer,
        json!({"label": "activate"}),
        false,
        Inactive,
        &[(Inactive, Activating), (Activating, Inactive)],
        &mut events,
    );
    scripted.set("on_activate", Behave::Return(Success));
    change(
        &mut peer,
        json!({"id": 3}),
        true,
        Active,
        &[(Inactive, Activating), (Activating, Active)],
        &mut events,
    );
    assert_eq!(
        peer.call(NODE, "get_available_transitions", json!({})),
        transitions_json([Transition::Deactivate, Transition::ActiveShutdown])
    );

    // deactivate: FAILURE (41) stays active, then SUCCESS (40).
    scripted.set("on_deactivate", Behave::Return(Failure));
    change(
        &mut peer,
        json!({"id": 4}),
        false,
        Active,
        &[(Active, Deactivating), (Deactivating, Active)],
        &mut events,
    );
    scripted.set("on_deactivate", Behave::Return(Success));
    change(
        &mut peer,
        json!({"label": "deactivate"}),
        true,
        Inactive,
        &[(Active, Deactivating), (Deactivating, Inactive)],
        &mut events,
    );

    // cleanup: FAILURE (21) stays inactive, then SUCCESS (20).
    scripted.set("on_cleanup", Behave::Return(Failure));
    change(
        &mut peer,
        json!({"label": "cleanup"}),
        false,
        Inactive,
        &[(Inactive, CleaningUp), (CleaningUp, Inactive)],
        &mut events,
    );
    scripted.set("on_cleanup", Behave::Return(Success));
    change(
        &mut peer,
        json!({"id": 2}),
        true,
        Unconfigured,
        &[(Inactive, CleaningUp), (CleaningUp, Unconfigured)],
        &mut events,
    );

    // Nothing happens for a transition the state does not have, by id or by label; a label
    // takes precedence over the id (rclcpp's and rclpy's on_change_state).
    change(
        &mut peer,
        json!({"id": 3}),
        false,
        Unconfigured,
        &[],
        &mut events,
    );
    change(
        &mut peer,
        json!({"label": "activate"}),
        false,
        Unconfigured,
        &[],
        &mut events,
    );
    change(
        &mut peer,
        json!({"label": "no_such_transition"}),
        false,
        Unconfigured,
        &[],
        &mut events,
    );
    change(
        &mut peer,
        json!({"id": 99}),
        false,
        Unconfigured,
        &[],
        &mut events,
    );
    change(
        &mut peer,
        json!({"id": 3, "label": "configure"}),
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
        &mut events,
    );

    // Up to active, then shutdown by label from active (7): on_shutdown SUCCESS (50).
    change(
        &mut peer,
        json!({"label": "activate"}),
        true,
        Active,
        &[(Inactive, Activating), (Activating, Active)],
        &mut events,
    );
    change(
        &mut peer,
        json!({"label": "shutdown"}),
        true,
        Finalized,
        &[(Active, ShuttingDown), (ShuttingDown, Finalized)],
        &mut events,
    );
    assert_eq!(
        peer.call(NODE, "get_available_transitions", json!({})),
        json!([])
    );
    change(
        &mut peer,
        json!({"label": "configure"}),
        false,
        Finalized,
        &[],
        &mut events,
    );

    // Every callback ran with the state its transition started from.
    let calls = scripted.calls();
    assert_eq!(
        calls,
        [
            ("on_configure", Unconfigured),
            ("on_configure", Unconfigured),
            ("on_activate", Inactive),
            ("on_activate", Inactive),
            ("on_deactivate", Active),
            ("on_deactivate", Active),
            ("on_cleanup", Inactive),
            ("on_cleanup", Inactive),
            ("on_configure", Unconfigured),
            ("on_activate", Inactive),
            ("on_shutdown", Active),
        ]
    );
    assert_eq!(managed.current_state(), Finalized);
}

#[test]
fn rclpy_drives_the_error_paths() {
    use CallbackReturn::*;
    use State::*;
    let domain = 202;
    let context = service_context(domain);
    let (managed, scripted, mut peer) = setup(&context, domain);
    let mut events = Vec::new();

    // configure: ERROR (12), on_error SUCCESS (60): back to unconfigured.
    scripted.set("on_configure", Behave::Return(Error));
    change(
        &mut peer,
        json!({"label": "configure"}),
        false,
        Unconfigured,
        &[
            (Unconfigured, Configuring),
            (Configuring, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
        &mut events,
    );
    // configure panics: taken as ERROR; on_error SUCCESS.
    scripted.set("on_configure", Behave::Panic);
    change(
        &mut peer,
        json!({"id": 1}),
        false,
        Unconfigured,
        &[
            (Unconfigured, Configuring),
            (Configuring, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
        &mut events,
    );
    scripted.set("on_configure", Behave::Return(Success));
    change(
        &mut peer,
        json!({"id": 1}),
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
        &mut events,
    );
    // cleanup: ERROR (22), on_error SUCCESS.
    scripted.set("on_cleanup", Behave::Return(Error));
    change(
        &mut peer,
        json!({"label": "cleanup"}),
        false,
        Unconfigured,
        &[
            (Inactive, CleaningUp),
            (CleaningUp, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
        &mut events,
    );
    change(
        &mut peer,
        json!({"id": 1}),
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
        &mut events,
    );
    // activate: ERROR (32), on_error SUCCESS.
    scripted.set("on_activate", Behave::Return(Error));
    change(
        &mut peer,
        json!({"label": "activate"}),
        false,
        Unconfigured,
        &[
            (Inactive, Activating),
            (Activating, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
        &mut events,
    );
    scripted.set("on_activate", Behave::Return(Success));
    change(
        &mut peer,
        json!({"id": 1}),
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
        &mut events,
    );
    change(
        &mut peer,
        json!({"id": 3}),
        true,
        Active,
        &[(Inactive, Activating), (Activating, Active)],
        &mut events,
    );
    // deactivate: ERROR (42), on_error SUCCESS.
    scripted.set("on_deactivate", Behave::Return(Error));
    change(
        &mut peer,
        json!({"id": 4}),
        false,
        Unconfigured,
        &[
            (Active, Deactivating),
            (Deactivating, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
        &mut events,
    );
    // shutdown from unconfigured (5): ERROR (52), on_error ERROR (62): finalized.
    scripted.set("on_shutdown", Behave::Return(Error));
    scripted.set("on_error", Behave::Return(Error));
    change(
        &mut peer,
        json!({"id": 5}),
        false,
        Finalized,
        &[
            (Unconfigured, ShuttingDown),
            (ShuttingDown, ErrorProcessing),
            (ErrorProcessing, Finalized),
        ],
        &mut events,
    );
    assert_eq!(managed.current_state(), Finalized);
    assert_eq!(
        scripted
            .calls()
            .iter()
            .filter(|(n, _)| *n == "on_error")
            .count(),
        6
    );

    // A second node: shutdown from inactive (6) with on_shutdown FAILURE (51): finalized too;
    // then a third: on_configure ERROR with on_error FAILURE (61): finalized.
    drop(peer);
    let node = context.create_node("managed2", "/").expect("node");
    let second = Scripted::default();
    let managed2 = LifecycleNode::builder()
        .node(&node)
        .callbacks(second.clone())
        .build()
        .expect("lifecycle node");
    assert_eq!(managed2.configure(), Ok(Inactive));
    second.set("on_shutdown", Behave::Return(Failure));
    assert_eq!(
        managed2.shutdown(),
        Err(TransitionError::Failed {
            transition: Transition::InactiveShutdown,
            state: Finalized
        })
    );
    let node = context.create_node("managed3", "/").expect("node");
    let third = Scripted::default();
    let managed3 = LifecycleNode::builder()
        .node(&node)
        .callbacks(third.clone())
        .build()
        .expect("lifecycle node");
    third.set("on_configure", Behave::Return(Error));
    third.set("on_error", Behave::Return(Failure));
    assert_eq!(
        managed3.configure(),
        Err(TransitionError::Error {
            transition: Transition::Configure,
            state: Finalized
        })
    );
    assert_eq!(
        managed3.activate(),
        Err(TransitionError::NotAvailable {
            requested: "activate".into(),
            state: Finalized
        })
    );
}

/// The transition events of a node driven by its own calls reach an rclpy subscription, on the
/// backend the environment chooses (pub/sub speaks with both DDS RMWs on both).
#[test]
fn rclpy_takes_the_transition_events_of_programmatic_transitions() {
    use State::*;
    let domain = 203;
    let context = context(domain);
    let (managed, _scripted, mut peer) = setup(&context, domain);
    assert_eq!(managed.configure(), Ok(Inactive));
    assert_eq!(managed.activate(), Ok(Active));
    assert_eq!(managed.deactivate(), Ok(Inactive));
    assert_eq!(managed.cleanup(), Ok(Unconfigured));
    assert_eq!(managed.shutdown(), Ok(Finalized));
    let expected: Vec<Value> = [
        (Unconfigured, Configuring),
        (Configuring, Inactive),
        (Inactive, Activating),
        (Activating, Active),
        (Active, Deactivating),
        (Deactivating, Inactive),
        (Inactive, CleaningUp),
        (CleaningUp, Unconfigured),
        (Unconfigured, ShuttingDown),
        (ShuttingDown, Finalized),
    ]
    .iter()
    .map(|(s, g)| event(NODE, (s.id(), s.label()), (g.id(), g.label())))
    .collect();
    assert_eq!(peer.wait_count("event", expected.len()), expected);
}
