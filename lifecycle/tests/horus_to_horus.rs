//! Our [`LifecycleClient`] drives our [`LifecycleNode`] in another context, on the backend the
//! environment chooses (HORUS_ROS_BACKEND: both backends speak both sides here), and a
//! [`LifecyclePublisher`](horus_ros_lifecycle::LifecyclePublisher) publishes only while active.
//!
//! Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-lifecycle --test horus_to_horus` (domains 206-207).

mod common;

use common::{context, wait_matched, Behave, Scripted, CALL, LIMIT};
use horus_ros_graph::Graph;
use horus_ros_lifecycle::lifecycle_msgs::msg::TransitionEvent;
use horus_ros_lifecycle::{
    transition_event_qos, CallbackReturn, LifecycleClient, LifecycleNode, State, Transition,
};
use horus_ros_msgs::std_msgs::msg::String as RosString;
use horus_ros_rmw::qos::Qos;

#[test]
fn a_client_drives_a_node_and_managed_publishers_follow_the_state() {
    let domain = 206;
    let server_context = context(domain);
    let node = server_context.create_node("managed", "/").expect("node");
    let scripted = Scripted::default();
    let managed = LifecycleNode::builder()
        .node(&node)
        .callbacks(scripted.clone())
        .build()
        .expect("lifecycle node");
    let chatter = managed
        .create_publisher::<RosString>("chatter", &Qos::default_profile())
        .expect("publisher");

    let client_context = context(domain);
    let driver = client_context.create_node("driver", "/").expect("node");
    let mut events = driver
        .create_subscription::<TransitionEvent>(
            "/managed/transition_event",
            &transition_event_qos(),
        )
        .expect("subscription");
    let mut heard = driver
        .create_subscription::<RosString>("/chatter", &Qos::default_profile())
        .expect("subscription");
    let mut client = LifecycleClient::builder()
        .node(&driver)
        .target("managed")
        .build()
        .expect("client");
    assert!(client.wait_for_services(LIMIT).expect("clients"));
    let graph = Graph::of(&client_context).expect("graph");
    wait_matched(&graph, events.gid(), "/managed/transition_event", false);
    wait_matched(&graph, heard.gid(), "/chatter", false);

    let say = |text: &str| {
        chatter.publish(RosString {
            data: text.to_owned(),
        })
    };
    assert!(!chatter.is_activated());
    assert_eq!(say("unconfigured").ok(), Some(false));
    assert!(client.change_state("configure", CALL).expect("call"));
    assert_eq!(say("inactive").ok(), Some(false));
    assert!(client
        .change_state(Transition::Activate, CALL)
        .expect("call"));
    assert!(chatter.is_activated());
    assert_eq!(say("active").ok(), Some(true));
    assert!(heard.wait(LIMIT));
    assert_eq!(
        heard.try_take().expect("take").map(|m| m.data),
        Some("active".to_owned())
    );
    // A failed deactivation leaves it active; an error deactivates it (unconfigured).
    scripted.set("on_deactivate", Behave::Return(CallbackReturn::Failure));
    assert!(!client.change_state(4, CALL).expect("call"));
    assert!(chatter.is_activated());
    scripted.set("on_deactivate", Behave::Return(CallbackReturn::Error));
    assert!(!client.change_state("deactivate", CALL).expect("call"));
    assert!(!chatter.is_activated());
    assert_eq!(say("unconfigured again").ok(), Some(false));
    let state = client.get_state(CALL).expect("get_state");
    assert_eq!((state.id, state.label.as_str()), (1, "unconfigured"));
    assert_eq!(managed.current_state(), State::Unconfigured);

    // Every step published its events, in order.
    let mut got = Vec::new();
    while got.len() < 9 {
        match events.try_take().expect("take") {
            Some(e) => got.push((e.start_state.id, e.goal_state.id)),
            None => assert!(events.wait(LIMIT), "events so far: {got:?}"),
        }
    }
    assert_eq!(
        got,
        [
            (1, 10),
            (10, 2),
            (2, 13),
            (13, 3),
            (3, 14),
            (14, 3),
            (3, 14),
            (14, 15),
            (15, 1)
        ]
    );
    assert!(events.try_take().expect("take").is_none());
}

/// `on_configure` waits until the test lets it go, telling the test it has started.
struct Held {
    started: std::sync::mpsc::Sender<()>,
    release: std::sync::mpsc::Receiver<()>,
}

impl horus_ros_lifecycle::LifecycleCallbacks for Held {
    fn on_configure(&mut self, _previous: State) -> CallbackReturn {
        let _ = self.started.send(());
        match self.release.recv_timeout(LIMIT) {
            Ok(()) => CallbackReturn::Success,
            Err(_) => CallbackReturn::Failure,
        }
    }
}

/// While a transition runs, the node is in its transition state and another transition finds
/// nothing to take (as rcl from a transition state); `~/get_state` answers the transition state.
#[test]
fn a_transition_asked_during_another_is_not_available() {
    use horus_ros_lifecycle::TransitionError;
    let domain = 207;
    let context = context(domain);
    let node = context.create_node("held", "/").expect("node");
    let (started_tx, started) = std::sync::mpsc::channel();
    let (release, release_rx) = std::sync::mpsc::channel();
    let managed = std::sync::Arc::new(
        LifecycleNode::builder()
            .node(&node)
            .callbacks(Held {
                started: started_tx,
                release: release_rx,
            })
            .build()
            .expect("lifecycle node"),
    );
    let running = std::sync::Arc::clone(&managed);
    let configure = std::thread::spawn(move || running.configure());
    started.recv_timeout(LIMIT).expect("on_configure started");
    assert_eq!(managed.current_state(), State::Configuring);
    assert_eq!(
        managed.activate(),
        Err(TransitionError::NotAvailable {
            requested: "activate".into(),
            state: State::Configuring
        })
    );
    assert_eq!(
        managed.trigger_transition(Transition::Configure.id()),
        Err(TransitionError::NotAvailable {
            requested: "1".into(),
            state: State::Configuring
        })
    );
    let driver = context.create_node("driver", "/").expect("node");
    let mut client = LifecycleClient::builder()
        .node(&driver)
        .target("/held")
        .build()
        .expect("client");
    let state = client.get_state(CALL).expect("get_state");
    assert_eq!((state.id, state.label.as_str()), (10, "configuring"));
    assert!(!client.change_state("shutdown", CALL).expect("change_state"));
    release.send(()).expect("release");
    assert_eq!(configure.join().expect("thread"), Ok(State::Inactive));
    assert_eq!(
        managed
            .available_transitions()
            .iter()
            .map(|t| t.id())
            .collect::<Vec<_>>(),
        [2, 3, 6]
    );
}
