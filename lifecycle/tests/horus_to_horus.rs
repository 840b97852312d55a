//! Our [`LifecycleClient`] drives our [`LifecycleNode`] in another context, on the backend the
//! environment chooses (HORUS_ROS_BACKEND: both backends speak both sides here), and a
//! [`LifecyclePublisher`](horus_ros_lifecycle::LifecyclePublisher) publishes only while active.
//!
//! Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-lifecycle --test horus_to_horus` (domain 206).

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
