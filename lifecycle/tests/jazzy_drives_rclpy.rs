//! Our [`LifecycleClient`] drives a real rclpy 7.1 `rclpy.lifecycle.LifecycleNode` on the run's
//! RMW (`HORUS_ROS_PEER_RMW`: rmw_fastrtps_cpp by default, or rmw_cyclonedds_cpp;
//! `peers/jazzy_lifecycle.py`) through every transition — successes, failures and the error
//! paths — and our subscription takes its `~/transition_event`s: what rcl_lifecycle under rclpy
//! answers and publishes is what ours does (`jazzy_drives_ours.rs` checks ours the same way).
//!
//! Each test has its own domain (204-205). Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-lifecycle --test jazzy_drives_rclpy`. Our side runs on
//! the backend HORUS_ROS_BACKEND chooses, but on the rustdds backend when the peer runs on
//! rmw_fastrtps and that backend is Cyclone (which cannot speak rmw_fastrtps' service
//! convention).

mod common;

use common::{service_context, wait_matched, Peer, CALL, LIMIT};
use horus_ros_graph::Graph;
use horus_ros_lifecycle::lifecycle_msgs::msg::TransitionEvent;
use horus_ros_lifecycle::{
    transition_event_qos, LifecycleClient, State, Transition, TransitionRequest,
};
use horus_ros_rmw::Subscription;
use serde_json::{json, Value};

const NODE: &str = "/py_managed";

/// Takes the next transition event within [`LIMIT`] as (start, goal) ids, after checking the
/// fields rcl leaves zero.
fn next_event(events: &mut Subscription<TransitionEvent>) -> (u8, u8) {
    let deadline = std::time::Instant::now() + LIMIT;
    loop {
        if let Some(e) = events.try_take().expect("take") {
            assert_eq!(
                (e.timestamp, e.transition.id, e.transition.label.as_str()),
                (0, 0, "")
            );
            let start = State::from_id(e.start_state.id).expect("a known state");
            let goal = State::from_id(e.goal_state.id).expect("a known state");
            assert_eq!(
                (e.start_state.label.as_str(), e.goal_state.label.as_str()),
                (start.label(), goal.label())
            );
            return (e.start_state.id, e.goal_state.id);
        }
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        assert!(!left.is_zero(), "no transition event within {LIMIT:?}");
        events.wait(left);
    }
}

struct Driver {
    client: LifecycleClient,
    events: Subscription<TransitionEvent>,
    peer: Peer,
}

impl Driver {
    fn start(domain: u32) -> (Driver, horus_ros_rmw::Context) {
        let context = service_context(domain);
        let node = context.create_node("driver", "/").expect("node");
        let events = node
            .create_subscription::<TransitionEvent>(
                &format!("{NODE}/transition_event"),
                &transition_event_qos(),
            )
            .expect("subscription");
        let peer = Peer::start(&json!({"domain": domain, "name": "py_managed", "lifecycle": true}));
        let mut client = LifecycleClient::builder()
            .node(&node)
            .target("py_managed")
            .build()
            .expect("client");
        assert!(
            client.wait_for_services(LIMIT).expect("clients"),
            "the rclpy node's services"
        );
        let graph = Graph::of(&context).expect("graph");
        wait_matched(
            &graph,
            events.gid(),
            &format!("{NODE}/transition_event"),
            false,
        );
        (
            Driver {
                client,
                events,
                peer,
            },
            context,
        )
    }

    /// One change_state; checks the reply, the state, the events and the callback rclpy ran.
    fn change(
        &mut self,
        request: impl Into<TransitionRequest>,
        success: bool,
        after: State,
        events: &[(State, State)],
    ) {
        let request = request.into();
        let callbacks_before = self.peer.all("callback").len();
        assert_eq!(
            self.client
                .change_state(request.clone(), CALL)
                .unwrap_or_else(|e| panic!(
                    "change_state {request:?}: {e:?}\n{}",
                    self.peer.fail()
                )),
            success,
            "{request:?}"
        );
        let state = self.client.get_state(CALL).expect("get_state");
        assert_eq!(
            (state.id, state.label.as_str()),
            (after.id(), after.label()),
            "{request:?}"
        );
        for (start, goal) in events {
            assert_eq!(
                next_event(&mut self.events),
                (start.id(), goal.id()),
                "{request:?}"
            );
        }
        // No other event (rclpy publishes them before it answers).
        assert!(
            self.events.try_take().expect("take").is_none(),
            "{request:?}"
        );
        // The callbacks rclpy ran are those of the transition states entered.
        let entered: Vec<&str> = events
            .iter()
            .filter_map(|(_, g)| match g {
                State::Configuring => Some("on_configure"),
                State::CleaningUp => Some("on_cleanup"),
                State::ShuttingDown => Some("on_shutdown"),
                State::Activating => Some("on_activate"),
                State::Deactivating => Some("on_deactivate"),
                State::ErrorProcessing => Some("on_error"),
                _ => None,
            })
            .collect();
        let callbacks = self
            .peer
            .wait_count("callback", callbacks_before + entered.len());
        let ran: Vec<&str> = callbacks[callbacks_before..]
            .iter()
            .filter_map(|c| c["name"].as_str())
            .collect();
        assert_eq!(ran, entered, "{request:?}");
    }

    fn behave(&mut self, behaviour: Value) {
        self.peer.behave(behaviour);
    }
}

#[test]
fn we_drive_an_rclpy_lifecycle_node_through_every_transition() {
    use State::*;
    let (mut d, _context) = Driver::start(204);

    // rcl's state machine under rclpy answers exactly as ours.
    let states = d.client.available_states(CALL).expect("states");
    let ours: Vec<(u8, String)> = State::ALL
        .iter()
        .map(|s| (s.id(), s.label().to_owned()))
        .collect();
    assert_eq!(
        states
            .into_iter()
            .map(|s| (s.id, s.label))
            .collect::<Vec<_>>(),
        ours
    );
    let graph = d.client.transition_graph(CALL).expect("graph");
    let ours: Vec<_> = Transition::ALL.iter().map(|t| t.description()).collect();
    assert_eq!(graph, ours);
    let available = d.client.available_transitions(CALL).expect("transitions");
    assert_eq!(
        available,
        [
            Transition::Configure.description(),
            Transition::UnconfiguredShutdown.description()
        ]
    );

    d.behave(json!({"on_configure": "failure"}));
    d.change(
        "configure",
        false,
        Unconfigured,
        &[(Unconfigured, Configuring), (Configuring, Unconfigured)],
    );
    d.behave(json!({"on_configure": "success"}));
    d.change(
        Transition::Configure,
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
    );
    let available = d.client.available_transitions(CALL).expect("transitions");
    let ours: Vec<_> = Inactive
        .transitions()
        .map(Transition::description)
        .collect();
    assert_eq!(available, ours);

    d.behave(json!({"on_activate": "failure"}));
    d.change(
        "activate",
        false,
        Inactive,
        &[(Inactive, Activating), (Activating, Inactive)],
    );
    d.behave(json!({"on_activate": "success"}));
    d.change(
        3,
        true,
        Active,
        &[(Inactive, Activating), (Activating, Active)],
    );
    let available = d.client.available_transitions(CALL).expect("transitions");
    let ours: Vec<_> = Active.transitions().map(Transition::description).collect();
    assert_eq!(available, ours);

    d.behave(json!({"on_deactivate": "failure"}));
    d.change(
        4,
        false,
        Active,
        &[(Active, Deactivating), (Deactivating, Active)],
    );
    d.behave(json!({"on_deactivate": "success"}));
    d.change(
        "deactivate",
        true,
        Inactive,
        &[(Active, Deactivating), (Deactivating, Inactive)],
    );

    d.behave(json!({"on_cleanup": "failure"}));
    d.change(
        "cleanup",
        false,
        Inactive,
        &[(Inactive, CleaningUp), (CleaningUp, Inactive)],
    );
    d.behave(json!({"on_cleanup": "success"}));
    d.change(
        2,
        true,
        Unconfigured,
        &[(Inactive, CleaningUp), (CleaningUp, Unconfigured)],
    );

    // Transitions the state does not have change nothing. By label only: rclpy 7.1.6's
    // `__change_state` lets rcl's error for an unknown id escape the service callback (no reply,
    // and the exception stops its executor), where rclcpp and ours answer `success: false`
    // (`jazzy_drives_ours.rs`).
    d.change("deactivate", false, Unconfigured, &[]);
    d.change("no_such_transition", false, Unconfigured, &[]);

    d.change(
        "configure",
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
    );
    d.change(
        "shutdown",
        true,
        Finalized,
        &[(Inactive, ShuttingDown), (ShuttingDown, Finalized)],
    );
    assert_eq!(
        d.client.available_transitions(CALL).expect("transitions"),
        []
    );

    // rclpy passed each callback the state its transition started from.
    let previous: Vec<(String, u64)> = d
        .peer
        .all("callback")
        .iter()
        .map(|c| {
            (
                c["name"].as_str().unwrap_or("").to_owned(),
                c["previous"][0].as_u64().unwrap_or(99),
            )
        })
        .collect();
    assert_eq!(previous.first(), Some(&("on_configure".to_owned(), 1)));
    assert_eq!(previous.last(), Some(&("on_shutdown".to_owned(), 2)));
}

#[test]
fn we_drive_an_rclpy_lifecycle_node_through_the_error_paths() {
    use State::*;
    let (mut d, _context) = Driver::start(205);
    d.behave(json!({"on_configure": "error"}));
    d.change(
        "configure",
        false,
        Unconfigured,
        &[
            (Unconfigured, Configuring),
            (Configuring, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
    );
    // An exception in an rclpy callback is taken as ERROR too.
    d.behave(json!({"on_configure": "raise"}));
    d.change(
        1,
        false,
        Unconfigured,
        &[
            (Unconfigured, Configuring),
            (Configuring, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
    );
    d.behave(json!({"on_configure": "success", "on_activate": "error"}));
    d.change(
        1,
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
    );
    d.change(
        3,
        false,
        Unconfigured,
        &[
            (Inactive, Activating),
            (Activating, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
    );
    d.behave(json!({"on_activate": "success", "on_deactivate": "error"}));
    d.change(
        1,
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
    );
    d.change(
        3,
        true,
        Active,
        &[(Inactive, Activating), (Activating, Active)],
    );
    d.change(
        4,
        false,
        Unconfigured,
        &[
            (Active, Deactivating),
            (Deactivating, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
    );
    d.behave(json!({"on_cleanup": "error"}));
    d.change(
        1,
        true,
        Inactive,
        &[(Unconfigured, Configuring), (Configuring, Inactive)],
    );
    d.change(
        2,
        false,
        Unconfigured,
        &[
            (Inactive, CleaningUp),
            (CleaningUp, ErrorProcessing),
            (ErrorProcessing, Unconfigured),
        ],
    );
    // shutdown ERROR, then on_error FAILURE: finalized.
    d.behave(json!({"on_shutdown": "error", "on_error": "failure"}));
    d.change(
        5,
        false,
        Finalized,
        &[
            (Unconfigured, ShuttingDown),
            (ShuttingDown, ErrorProcessing),
            (ErrorProcessing, Finalized),
        ],
    );
    // From finalized nothing leaves.
    d.change("configure", false, Finalized, &[]);
}
