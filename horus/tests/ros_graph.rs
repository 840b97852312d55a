//! Scheduled nodes are ROS 2 nodes: on `ros_discovery_info` with their topics and services, on
//! `/rosout`, with the node services and the parameters of `--ros-args`, remapped by it. Seen
//! from a second context (another DDS participant), inside the test network namespace. Each
//! test has its own domain.

#[path = "common/chatter_nodes.rs"]
mod chatter_nodes;

use std::sync::mpsc;
use std::time::Duration;

use chatter_nodes::{Listener, Talker};
use horus::prelude::*;
use horus::ros::{Arguments, Context};
use horus_ros_graph::Graph;
use horus_ros_msgs::rcl_interfaces::msg::{Log, ParameterType};
use horus_ros_msgs::rcl_interfaces::srv::{GetParameters, GetParametersRequest};
use horus_ros_rmw::qos::Qos;
use horus_ros_services::ServiceClient;

const WAIT: Duration = Duration::from_secs(20);

fn context(domain: u32, args: &[&str]) -> Context {
    let argv: Vec<&str> = std::iter::once("prog")
        .chain(args.iter().copied())
        .collect();
    Context::builder()
        .domain_id(domain)
        .arguments(Arguments::parse_strict(&argv).expect("arguments"))
        .build()
        .expect("context")
}

#[test]
fn scheduled_nodes_are_ros_nodes_with_their_topics_services_parameters_and_rosout() {
    let domain = 171;
    let observer = context(domain, &[]);
    let graph = Graph::of(&observer).expect("graph");
    let observer_node = observer.create_node("observer", "/").expect("node");
    let mut rosout = observer_node
        .create_subscription::<Log>("/rosout", &Qos::rosout_default())
        .expect("rosout");

    let ctx = context(
        domain,
        &[
            "--ros-args",
            "-r",
            "__ns:=/robot1",
            "-r",
            "chatter:=babble",
            // A node prefix (`talker:rate:=5`) would name the node `/talker` (rcl keeps one
            // token; rclcpp matches it against the fully-qualified name): not this /robot1/talker.
            "-p",
            "rate:=5",
        ],
    );
    let (heard_tx, heard) = mpsc::channel();
    let mut sched = Scheduler::new()
        .context(ctx)
        .tick_rate(50_u64.hz())
        .print_report(false);
    sched
        .add(Talker::on_chatter())
        .order(1)
        .build()
        .expect("talker");
    sched
        .add(Listener::new(heard_tx))
        .order(0)
        .build()
        .expect("listener");
    let stop = sched.stop_handle();
    let runner = std::thread::spawn(move || {
        let outcome = sched.run();
        (outcome.map_err(|e| e.to_string()), sched)
    });

    // The listener hears the talker, in the same process, through DDS.
    let first = heard
        .recv_timeout(WAIT)
        .expect("the listener heard the talker");
    assert!(first.starts_with("Hello World: "), "{first}");

    // Both are nodes in /robot1, with the remapped topic, /rosout and the node services.
    assert!(
        graph.wait_until(WAIT, |g| {
            let pubs = g.publisher_names_and_types_by_node("talker", "/robot1");
            let subs = g.subscription_names_and_types_by_node("listener", "/robot1");
            let srvs = g.service_names_and_types_by_node("talker", "/robot1");
            pubs.is_ok_and(|p| {
                p.get("/robot1/babble")
                    .is_some_and(|t| t.contains("std_msgs/msg/String"))
                    && p.contains_key("/rosout")
            }) && subs.is_ok_and(|s| s.contains_key("/robot1/babble"))
                && srvs.is_ok_and(|s| {
                    s.contains_key("/robot1/talker/get_parameters")
                        && s.contains_key("/robot1/talker/get_type_description")
                })
        }),
        "nodes, topics and services in the graph: {:?}",
        graph.read(|g| g.node_names())
    );

    // `-p rate:=5` is a parameter of /robot1/talker (as `ros2 param get` reads it).
    let mut client = ServiceClient::<GetParameters>::builder()
        .node(&observer_node)
        .name("/robot1/talker/get_parameters")
        .build()
        .expect("client");
    assert!(client.wait_for_service(WAIT));
    let values = client
        .call(
            GetParametersRequest {
                names: vec!["rate".into()],
            },
            WAIT,
        )
        .expect("get_parameters");
    assert_eq!(values.values[0].r#type, ParameterType::PARAMETER_INTEGER);
    assert_eq!(values.values[0].integer_value, 5);

    // hlog! reached /rosout with the node's logger name (transient local: still there).
    let mut found = None;
    for _ in 0..200 {
        match rosout.try_take().expect("take") {
            Some(log) if log.name == "robot1.talker" => {
                found = Some(log);
                break;
            }
            Some(_) => continue,
            None => {
                rosout.wait(WAIT);
            }
        }
    }
    let log = found.expect("a /rosout message from robot1.talker");
    assert_eq!(log.level, Log::INFO);
    assert_eq!(log.msg, "talker starting, rate parameter 5");

    stop.stop();
    let (outcome, sched) = runner.join().expect("scheduler thread");
    assert_eq!(outcome, Ok(()));
    let talker = sched.get_node_metrics("talker").expect("metrics");
    let listener = sched.get_node_metrics("listener").expect("metrics");
    assert!(talker.messages_sent >= 1);
    assert!(listener.messages_received >= 1);
    assert!(listener.messages_received <= talker.messages_sent);
    assert_eq!(talker.messages_received, 0);

    // After the scheduler stopped, its nodes left the graph.
    drop(sched);
    assert!(graph.wait_until(WAIT, |g| !g
        .node_names()
        .iter()
        .any(|n| n.namespace == "/robot1")));
}

#[test]
fn malformed_ros_args_are_rejected_with_rcls_message() {
    let err =
        Arguments::parse_strict(&["prog", "--ros-args", "-r", "foo:="]).expect_err("malformed");
    assert_eq!(
        err.to_string(),
        "Couldn't parse remap rule: '-r foo:='. Error: Expected lexeme type 18, got 1 at index 5"
    );
}

#[test]
fn unmappable_topic_names_are_errors_not_panics() {
    let err = Topic::<StringMsg>::new("motor-cmd").expect_err("unmappable");
    assert!(
        err.to_string()
            .starts_with("topic name 'motor-cmd' cannot be mapped to a ROS topic name"),
        "{err}"
    );
    assert_eq!(
        Topic::<StringMsg>::new("motor.cmd")
            .expect("maps")
            .ros_name(),
        "motor/cmd"
    );
}
