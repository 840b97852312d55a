//! `NodeServices` called over DDS by clients on another node in another context (run inside the
//! test network namespace). Each test has its own domain (151-156).

use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_msgs::rcl_interfaces::msg::{
    IntegerRange, Parameter, ParameterDescriptor, ParameterEvent, ParameterType, ParameterValue,
    SetParametersResult,
};
use horus_ros_msgs::rcl_interfaces::srv::{
    DescribeParameters, DescribeParametersRequest, GetParameterTypes, GetParameterTypesRequest,
    GetParameters, GetParametersRequest, ListParameters, ListParametersRequest, SetParameters,
    SetParametersAtomically, SetParametersAtomicallyRequest, SetParametersRequest,
};
use horus_ros_msgs::type_description_interfaces::srv::{
    GetTypeDescription, GetTypeDescriptionRequest,
};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Subscription;
use horus_ros_services::prelude::*;
use horus_ros_services::{
    NodeServices, NodeServicesOptions, ParameterValueExt, FAILURE_NOT_IN_USE, FAILURE_PARSE_HASH,
    REASON_ATOMICALLY_NOT_DECLARED,
};

const SECOND: Duration = Duration::from_secs(1);

/// A node in its own context on `domain`.
fn node(domain: u32, name: &str, namespace: &str) -> Node {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    context.create_node(name, namespace).expect("node")
}

/// A client of `/ns/params_node/<service>` on `peer`, once the server is seen.
fn client<S: Service>(peer: &Node, service: &str) -> ServiceClient<S> {
    let c = ServiceClient::<S>::builder()
        .node(peer)
        .name(format!("/ns/params_node/{service}"))
        .build()
        .expect("client");
    assert!(c.wait_for_service(15 * SECOND), "{service} not found");
    c
}

fn strings(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| (*s).to_owned()).collect()
}

/// `NodeServices` on `/ns/params_node` with `speed` (integer 0..=10 step 2), `mode` (string),
/// `frozen` (read-only double), `a.b.c`, `a.b.d`, `a.x` (bools).
fn served(domain: u32, options: NodeServicesOptions) -> (Node, NodeServices) {
    let n = node(domain, "params_node", "/ns");
    let services = NodeServices::start_with(&n, options).expect("node services");
    services
        .declare_parameter(
            "speed",
            ParameterValue::from_integer(4),
            ParameterDescriptor {
                description: "how fast".into(),
                integer_range: vec![IntegerRange {
                    from_value: 0,
                    to_value: 10,
                    step: 2,
                }],
                ..Default::default()
            },
        )
        .expect("speed");
    services
        .declare_parameter(
            "mode",
            ParameterValue::from_string("auto"),
            ParameterDescriptor::default(),
        )
        .expect("mode");
    services
        .declare_parameter(
            "frozen",
            ParameterValue::from_double(1.5),
            ParameterDescriptor {
                read_only: true,
                ..Default::default()
            },
        )
        .expect("frozen");
    for name in ["a.b.c", "a.b.d", "a.x"] {
        services
            .declare_parameter(name, ParameterValue::from_bool(true), Default::default())
            .expect("nested");
    }
    (n, services)
}

fn param(name: &str, value: ParameterValue) -> Parameter {
    Parameter {
        name: name.to_owned(),
        value,
    }
}

#[test]
fn list_parameters_follows_prefixes_and_depth() {
    let (_n, services) = served(151, NodeServicesOptions::default());
    let names: Vec<String> = services
        .service_names()
        .iter()
        .map(|s| s.as_str().to_owned())
        .collect();
    assert_eq!(
        names,
        [
            "/ns/params_node/describe_parameters",
            "/ns/params_node/get_parameter_types",
            "/ns/params_node/get_parameters",
            "/ns/params_node/list_parameters",
            "/ns/params_node/set_parameters",
            "/ns/params_node/set_parameters_atomically",
            "/ns/params_node/get_type_description",
        ]
    );
    let peer = node(151, "caller", "/");
    let mut c = client::<ListParameters>(&peer, "list_parameters");
    let mut list = |prefixes: &[&str], depth: u64| {
        c.call(
            ListParametersRequest {
                prefixes: strings(prefixes),
                depth,
            },
            5 * SECOND,
        )
        .expect("list_parameters")
        .result
    };
    let all = list(&[], ListParametersRequest::DEPTH_RECURSIVE);
    assert_eq!(
        all.names,
        [
            "a.b.c",
            "a.b.d",
            "a.x",
            "frozen",
            "mode",
            "speed",
            "start_type_description_service",
            "use_sim_time"
        ]
    );
    assert_eq!(all.prefixes, ["a.b", "a"]);
    assert_eq!(
        list(&[], 1).names,
        [
            "frozen",
            "mode",
            "speed",
            "start_type_description_service",
            "use_sim_time"
        ]
    );
    assert_eq!(list(&["a"], 0).names, ["a.b.c", "a.b.d", "a.x"]);
    let a1 = list(&["a"], 1);
    assert_eq!(a1.names, ["a.x"]);
    assert_eq!(a1.prefixes, ["a"]);
    assert_eq!(list(&["a.b", "mode"], 1).names, ["a.b.c", "a.b.d", "mode"]);
    assert!(list(&["nothing"], 0).names.is_empty());
}

#[test]
fn get_describe_and_types_of_declared_and_unknown_parameters() {
    let (_n, _services) = served(152, NodeServicesOptions::default());
    let peer = node(152, "caller", "/");
    let mut get = client::<GetParameters>(&peer, "get_parameters");
    let values = get
        .call(
            GetParametersRequest {
                names: strings(&["speed", "mode", "use_sim_time"]),
            },
            5 * SECOND,
        )
        .expect("get")
        .values;
    assert_eq!(
        values,
        [
            ParameterValue::from_integer(4),
            ParameterValue::from_string("auto"),
            ParameterValue::from_bool(false)
        ]
    );
    // rclcpp (allow_undeclared_parameters false): any undeclared name empties the reply, which
    // `ros2 param get` prints as "Parameter not set".
    let values = get
        .call(
            GetParametersRequest {
                names: strings(&["speed", "unknown"]),
            },
            5 * SECOND,
        )
        .expect("get unknown")
        .values;
    assert!(values.is_empty(), "{values:?}");

    let mut types = client::<GetParameterTypes>(&peer, "get_parameter_types");
    let reply = types
        .call(
            GetParameterTypesRequest {
                names: strings(&["speed", "frozen", "a.x"]),
            },
            5 * SECOND,
        )
        .expect("types");
    assert_eq!(
        reply.types,
        [
            ParameterType::PARAMETER_INTEGER,
            ParameterType::PARAMETER_DOUBLE,
            ParameterType::PARAMETER_BOOL
        ]
    );
    let reply = types
        .call(
            GetParameterTypesRequest {
                names: strings(&["unknown"]),
            },
            5 * SECOND,
        )
        .expect("types unknown");
    assert!(reply.types.is_empty());

    let mut describe = client::<DescribeParameters>(&peer, "describe_parameters");
    let descriptors = describe
        .call(
            DescribeParametersRequest {
                names: strings(&["speed", "start_type_description_service"]),
            },
            5 * SECOND,
        )
        .expect("describe")
        .descriptors;
    assert_eq!(descriptors.len(), 2);
    assert_eq!(descriptors[0].name, "speed");
    assert_eq!(descriptors[0].r#type, ParameterType::PARAMETER_INTEGER);
    assert_eq!(descriptors[0].description, "how fast");
    assert_eq!(descriptors[0].integer_range.len(), 1);
    assert!(descriptors[1].read_only);
    assert_eq!(descriptors[1].r#type, ParameterType::PARAMETER_BOOL);
}

#[test]
fn set_parameters_checks_declaration_type_range_and_read_only() {
    let (_n, services) = served(153, NodeServicesOptions::default());
    let peer = node(153, "caller", "/");
    let mut set = client::<SetParameters>(&peer, "set_parameters");
    let results = set
        .call(
            SetParametersRequest {
                parameters: vec![
                    param("speed", ParameterValue::from_integer(8)),
                    param("speed", ParameterValue::from_string("fast")),
                    param("nope", ParameterValue::from_integer(1)),
                    param("frozen", ParameterValue::from_double(2.0)),
                    param("speed", ParameterValue::from_integer(7)),
                    param("use_sim_time", ParameterValue::from_bool(true)),
                ],
            },
            5 * SECOND,
        )
        .expect("set")
        .results;
    let ok = SetParametersResult {
        successful: true,
        reason: String::new(),
    };
    let failed = |reason: &str| SetParametersResult {
        successful: false,
        reason: reason.to_owned(),
    };
    assert_eq!(
        results,
        [
            ok.clone(),
            failed(
                "Wrong parameter type, parameter {speed} is of type {integer}, setting it to \
                 {string} is not allowed."
            ),
            failed("parameter 'nope' cannot be set because it was not declared"),
            failed("parameter 'frozen' cannot be set because it is read-only"),
            failed("Parameter {speed} doesn't comply with integer range."),
            ok,
        ]
    );
    assert_eq!(
        services.get_parameter("speed"),
        Ok(ParameterValue::from_integer(8))
    );
    assert_eq!(
        services.get_parameter("use_sim_time"),
        Ok(ParameterValue::from_bool(true))
    );
    assert!(!services.parameters().has("nope"));

    // All or nothing.
    let mut atomically = client::<SetParametersAtomically>(&peer, "set_parameters_atomically");
    let mut set_all = |parameters: Vec<Parameter>| {
        atomically
            .call(SetParametersAtomicallyRequest { parameters }, 5 * SECOND)
            .expect("set atomically")
            .result
    };
    let result = set_all(vec![
        param("mode", ParameterValue::from_string("manual")),
        param("speed", ParameterValue::from_bool(false)),
    ]);
    assert!(!result.successful);
    assert!(
        result.reason.starts_with("Wrong parameter type"),
        "{result:?}"
    );
    let result = set_all(vec![
        param("mode", ParameterValue::from_string("manual")),
        param("missing", ParameterValue::from_integer(1)),
    ]);
    assert_eq!(result, failed(REASON_ATOMICALLY_NOT_DECLARED));
    assert_eq!(
        services.get_parameter("mode"),
        Ok(ParameterValue::from_string("auto")),
        "a failed atomic set changes nothing"
    );
    let result = set_all(vec![
        param("mode", ParameterValue::from_string("manual")),
        param("speed", ParameterValue::from_integer(10)),
    ]);
    assert_eq!(
        result,
        SetParametersResult {
            successful: true,
            reason: String::new()
        }
    );
    assert_eq!(
        services.get_parameter("mode"),
        Ok(ParameterValue::from_string("manual"))
    );
    assert_eq!(
        services.get_parameter("speed"),
        Ok(ParameterValue::from_integer(10))
    );
}

#[test]
fn get_type_description_answers_by_hash_as_rcl() {
    let n = node(154, "params_node", "/ns");
    let services = NodeServices::start(&n).expect("node services");
    let hash = services.register_service::<AddTwoInts>();
    assert_eq!(hash, AddTwoInts::type_hash());
    let peer = node(154, "caller", "/");
    let mut c = client::<GetTypeDescription>(&peer, "get_type_description");
    let reply = c
        .call(
            GetTypeDescriptionRequest {
                type_name: "example_interfaces/srv/AddTwoInts".into(),
                type_hash: hash.to_string(),
                include_type_sources: true,
            },
            5 * SECOND,
        )
        .expect("get_type_description");
    assert!(reply.successful, "{}", reply.failure_reason);
    assert!(reply.failure_reason.is_empty());
    assert_eq!(
        reply.type_description.type_description.type_name,
        "example_interfaces/srv/AddTwoInts"
    );
    assert_eq!(reply.type_description.compute_type_hash(), hash);

    // The node's own service types are registered, as rcl registers every service's type.
    let own = c
        .call(
            GetTypeDescriptionRequest {
                type_name: String::new(),
                type_hash: GetTypeDescription::type_hash().to_string(),
                include_type_sources: false,
            },
            5 * SECOND,
        )
        .expect("own type");
    assert!(own.successful);
    assert_eq!(
        own.type_description.compute_type_hash(),
        GetTypeDescription::type_hash()
    );

    let unknown = c
        .call(
            GetTypeDescriptionRequest {
                type_name: "example_interfaces/srv/AddTwoInts".into(),
                type_hash: format!("RIHS01_{}", "ab".repeat(32)),
                include_type_sources: true,
            },
            5 * SECOND,
        )
        .expect("unknown hash");
    assert!(!unknown.successful);
    assert_eq!(unknown.failure_reason, FAILURE_NOT_IN_USE);
    let garbage = c
        .call(
            GetTypeDescriptionRequest {
                type_name: String::new(),
                type_hash: "not a hash".into(),
                include_type_sources: true,
            },
            5 * SECOND,
        )
        .expect("bad hash");
    assert!(!garbage.successful);
    assert_eq!(garbage.failure_reason, FAILURE_PARSE_HASH);

    // Dropping NodeServices takes the services off the graph.
    drop(services);
    let graph = Graph::of(peer.context()).expect("graph");
    let gone = graph.wait_until(10 * SECOND, |cache| {
        cache
            .servers_info_by_service(c.name().as_str(), false)
            .is_ok_and(|servers| servers.is_empty())
    });
    assert!(
        gone && !c.server_available(),
        "the server is still seen after drop"
    );
}

/// [`served`] with rclcpp's `allow_undeclared_parameters`.
fn served_allowing_undeclared(domain: u32) -> (Node, NodeServices) {
    let options = NodeServicesOptions {
        allow_undeclared_parameters: true,
        ..Default::default()
    };
    served(domain, options)
}

#[test]
fn allow_undeclared_parameters_answers_not_set_and_declares_on_set() {
    let (_n, services) = served_allowing_undeclared(155);
    let peer = node(155, "caller", "/");
    let mut get = client::<GetParameters>(&peer, "get_parameters");
    let values = get
        .call(
            GetParametersRequest {
                names: strings(&["speed", "unknown"]),
            },
            5 * SECOND,
        )
        .expect("get")
        .values;
    assert_eq!(
        values,
        [ParameterValue::from_integer(4), ParameterValue::not_set()]
    );
    let mut types = client::<GetParameterTypes>(&peer, "get_parameter_types");
    let reply = types
        .call(
            GetParameterTypesRequest {
                names: strings(&["unknown"]),
            },
            5 * SECOND,
        )
        .expect("types");
    assert_eq!(reply.types, [ParameterType::PARAMETER_NOT_SET]);
    let mut set = client::<SetParameters>(&peer, "set_parameters");
    let results = set
        .call(
            SetParametersRequest {
                parameters: vec![param("fresh", ParameterValue::from_integer(3))],
            },
            5 * SECOND,
        )
        .expect("set")
        .results;
    assert!(results[0].successful, "{results:?}");
    let descriptor = services.parameters().describe("fresh").expect("declared");
    assert!(descriptor.dynamic_typing);
    assert_eq!(
        services.get_parameter("fresh"),
        Ok(ParameterValue::from_integer(3))
    );
}

/// The next event on `events` (at most 10 s).
fn next_event(events: &mut Subscription<ParameterEvent>) -> ParameterEvent {
    let deadline = Instant::now() + 10 * SECOND;
    loop {
        if let Some(event) = events.try_take().expect("take") {
            return event;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(
            !left.is_zero() && events.wait(left),
            "no parameter event within 10 s"
        );
    }
}

#[test]
fn parameter_events_tell_each_change_as_rclcpp() {
    let (_n, services) = served_allowing_undeclared(156);
    // The watcher follows the graph of its context, so the clients are on another one.
    let watcher = node(156, "watcher", "/");
    let peer = node(156, "caller", "/");
    let mut events = watcher
        .create_subscription::<ParameterEvent>("/parameter_events", &Qos::parameter_events())
        .expect("subscription");
    // The events published from now on reach the watcher once its reader is matched with the
    // node's writer.
    let graph = Graph::of(watcher.context()).expect("graph");
    let mut writer = None;
    assert!(
        graph.wait_until(15 * SECOND, |g| {
            writer = g
                .publishers_info_by_topic("/parameter_events", false)
                .into_iter()
                .find(|i| i.node_name == "params_node" && i.node_namespace == "/ns")
                .map(|i| i.endpoint_gid);
            writer.is_some()
        }),
        "/ns/params_node's /parameter_events writer not discovered"
    );
    let writer = writer.expect("writer");
    assert!(graph.wait_for_match(events.gid(), writer, 15 * SECOND));

    // Set over the service: one declared implicitly (new), one changed.
    let mut set_atomically = client::<SetParametersAtomically>(&peer, "set_parameters_atomically");
    let result = set_atomically
        .call(
            SetParametersAtomicallyRequest {
                parameters: vec![
                    param("speed", ParameterValue::from_integer(6)),
                    param("extra", ParameterValue::from_bool(true)),
                ],
            },
            5 * SECOND,
        )
        .expect("set atomically")
        .result;
    assert!(result.successful, "{result:?}");
    let event = next_event(&mut events);
    assert_eq!(event.node, "/ns/params_node");
    assert!(event.stamp.sec > 0, "{event:?}");
    assert_eq!(
        event.new_parameters,
        [param("extra", ParameterValue::from_bool(true))]
    );
    assert_eq!(
        event.changed_parameters,
        [param("speed", ParameterValue::from_integer(6))]
    );
    assert!(event.deleted_parameters.is_empty(), "{event:?}");

    // A refused set publishes nothing; setting a dynamically typed parameter to NOT_SET deletes
    // it (listed with that value).
    let mut set = client::<SetParameters>(&peer, "set_parameters");
    let results = set
        .call(
            SetParametersRequest {
                parameters: vec![
                    param("speed", ParameterValue::from_integer(7)),
                    param("extra", ParameterValue::default()),
                ],
            },
            5 * SECOND,
        )
        .expect("set")
        .results;
    assert_eq!(
        results.iter().map(|r| r.successful).collect::<Vec<_>>(),
        [false, true]
    );
    let event = next_event(&mut events);
    assert!(event.new_parameters.is_empty(), "{event:?}");
    assert!(event.changed_parameters.is_empty(), "{event:?}");
    assert_eq!(
        event.deleted_parameters,
        [param("extra", ParameterValue::default())]
    );

    // A declaration by the application is new; undeclaring publishes nothing (as rclcpp).
    services
        .declare_parameter(
            "late",
            ParameterValue::from_integer(1),
            ParameterDescriptor {
                dynamic_typing: true,
                ..Default::default()
            },
        )
        .expect("declare");
    services.undeclare_parameter("late").expect("undeclare");
    services
        .set_parameter("mode", ParameterValue::from_string("manual"))
        .expect("set mode");
    let event = next_event(&mut events);
    assert_eq!(
        event.new_parameters,
        [param("late", ParameterValue::from_integer(1))]
    );
    let event = next_event(&mut events);
    assert_eq!(
        event.changed_parameters,
        [param("mode", ParameterValue::from_string("manual"))]
    );
    assert!(event.new_parameters.is_empty() && event.deleted_parameters.is_empty());
}
