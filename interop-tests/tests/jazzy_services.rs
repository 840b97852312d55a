//! horus-ros services against real ROS 2 Jazzy nodes (rclpy 7.1.6 on the run's RMW:
//! rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5, whose request ids come from the
//! related_sample_identity, rmw_cyclonedds_cpp 2.2.2, whose request ids ride in a header
//! before the payload, or rmw_zenoh_cpp 0.2.10, whose request ids ride in each query's
//! attachment: the client's GID and its own sequence number).
//!
//! - Our clients call an rclpy node's servers: `std_srvs/srv/SetBool` (with service
//!   introspection on: the request id the peer's RMW computed for each of our requests, from its
//!   `_service_event`s, names our client and our request's number, see `peers::request_ids`),
//!   `test_msgs/srv/BasicTypes` (a `service!` type of ours, and a dynamic client built from the
//!   description its `~/get_type_description` serves) and its parameter services.
//! - An rclpy node's clients call our servers: SetBool, BasicTypes, and the parameter services of
//!   our `NodeServices` (rclpy's `AsyncParameterClient`).
//!
//! rmw_fastrtps' convention needs `related_sample_identity`, which only the rustdds backend can
//! send and read. With rmw_fastrtps peers on the Cyclone backend (like rmw_cyclonedds itself)
//! the tests check the refusal instead: our calls fail at once with a `Transport` error naming
//! rmw_fastrtps and the rustdds backend, and the rclpy clients get no answer from our servers.
//! rmw_cyclonedds peers are called and served on both DDS backends, rmw_zenoh peers on the
//! Zenoh backend.

use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_msgs::rcl_interfaces::msg::{Parameter, ParameterType, ParameterValue};
use horus_ros_msgs::rcl_interfaces::srv::{
    GetParameters, GetParametersRequest, ListParameters, ListParametersRequest, SetParameters,
    SetParametersRequest,
};
use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolRequest, SetBoolResponse};
use horus_ros_msgs::type_description_interfaces::srv::{
    GetTypeDescription, GetTypeDescriptionRequest,
};
use horus_ros_msgs::{Byte, Message};
use horus_ros_services::prelude::*;
use horus_ros_services::{DynamicServiceClient, NodeServices, ParameterValueExt, ServiceType};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::{request_ids, wheels, RclpyPeer};
use serde_json::{json, Value};

const SECOND: Duration = Duration::from_secs(1);
/// "Did not hang" bound for discovery and calls on a loaded machine.
const WAIT: Duration = Duration::from_secs(30);
/// How long a refusal may take once the server is on the graph ("at once": no call timeout).
const REFUSAL_LIMIT: Duration = Duration::from_secs(2);

service! {
    /// test_msgs' BasicTypes (test_msgs jazzy `srv/BasicTypes.srv`): every basic type each way.
    test_msgs/BasicTypes {
        request {
            bool_value: bool, byte_value: Byte, char_value: u8, float32_value: f32,
            float64_value: f64, int8_value: i8, uint8_value: u8, int16_value: i16,
            uint16_value: u16, int32_value: i32, uint32_value: u32, int64_value: i64,
            uint64_value: u64, string_value: String,
        }
        response {
            bool_value: bool, byte_value: Byte, char_value: u8, float32_value: f32,
            float64_value: f64, int8_value: i8, uint8_value: u8, int16_value: i16,
            uint16_value: u16, int32_value: i32, uint32_value: u32, int64_value: i64,
            uint64_value: u64, string_value: String,
        }
    }
}

/// A request that uses every field, with values at the edges of their types.
fn basic_request() -> BasicTypesRequest {
    BasicTypesRequest {
        bool_value: true,
        byte_value: Byte(0xa5),
        char_value: b'Z',
        float32_value: 1.5,
        float64_value: -2.25e300,
        int8_value: i8::MIN,
        uint8_value: u8::MAX,
        int16_value: i16::MIN,
        uint16_value: u16::MAX,
        int32_value: i32::MIN,
        uint32_value: u32::MAX,
        int64_value: i64::MIN,
        uint64_value: u64::MAX,
        string_value: "horus ↔ rclpy".to_owned(),
    }
}

/// The same request as the JSON the rclpy peer fills it from (and prints it as).
fn basic_request_json() -> Value {
    let r = basic_request();
    json!({
        "bool_value": r.bool_value, "byte_value": r.byte_value.0, "char_value": r.char_value,
        "float32_value": r.float32_value, "float64_value": r.float64_value,
        "int8_value": r.int8_value, "uint8_value": r.uint8_value,
        "int16_value": r.int16_value, "uint16_value": r.uint16_value,
        "int32_value": r.int32_value, "uint32_value": r.uint32_value,
        "int64_value": r.int64_value, "uint64_value": r.uint64_value,
        "string_value": r.string_value,
    })
}

fn echo(r: BasicTypesRequest) -> BasicTypesResponse {
    BasicTypesResponse {
        bool_value: r.bool_value,
        byte_value: r.byte_value,
        char_value: r.char_value,
        float32_value: r.float32_value,
        float64_value: r.float64_value,
        int8_value: r.int8_value,
        uint8_value: r.uint8_value,
        int16_value: r.int16_value,
        uint16_value: r.uint16_value,
        int32_value: r.int32_value,
        uint32_value: r.uint32_value,
        int64_value: r.int64_value,
        uint64_value: r.uint64_value,
        string_value: r.string_value,
    }
}

/// Our `service!` BasicTypes hashes as the wheels' test_msgs does.
fn basic_types_hash_is_the_wheels() {
    for (name, hash) in [
        (BasicTypes::TYPE_NAME, BasicTypes::type_hash()),
        (BasicTypesRequest::TYPE_NAME, BasicTypesRequest::type_hash()),
        (
            BasicTypesResponse::TYPE_NAME,
            BasicTypesResponse::type_hash(),
        ),
    ] {
        assert_eq!(Ok(hash.to_string()), wheels::wheel_hash(name), "{name}");
    }
}

fn double(v: f64) -> ParameterValue {
    ParameterValue::from_double(v)
}

/// A client on the Cyclone backend is refused at once, once the rclpy server (on rmw_fastrtps) is
/// on the graph.
fn refused<T: std::fmt::Debug>(what: &str, asked: Instant, reply: Result<T, ServiceError>) {
    match &reply {
        Err(ServiceError::Transport(cause @ TransportError::NoUsableServer { .. })) => {
            let m = cause.to_string();
            assert!(
                m.contains("rmw_fastrtps") && m.contains("rustdds"),
                "{what}: the refusal must name rmw_fastrtps and the rustdds backend: {m}"
            )
        }
        other => panic!("{what}: expected a Transport refusal, got {other:?}"),
    }
    assert!(
        asked.elapsed() < REFUSAL_LIMIT,
        "{what}: refused only after {:?}",
        asked.elapsed()
    );
}

#[test]
fn our_clients_call_rclpy_servers() {
    const DOMAIN: u32 = 111;
    basic_types_hash_is_the_wheels();
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("horus_caller", "/").expect("node");
    let graph = Graph::of(&context).expect("graph");
    let rmw = Rmw::of_peers();
    let refusing = !context.capabilities().carries_sample_identity && rmw.needs_sample_identity();
    let mut peer = RclpyPeer::start(&json!({
        "domain": DOMAIN, "namespace": "/rclpy_ns", "name": "rclpy_server",
        "servers": [
            {"service": "/rclpy_ns/set", "type": "std_srvs/srv/SetBool", "introspection": true},
            {"service": "/rclpy_ns/basic", "type": "test_msgs/srv/BasicTypes",
             "introspection": true},
        ],
        "parameters": {"gain": 1.5, "label": "rclpy"},
    }))
    .expect("start the rclpy peer");
    peer.ready(WAIT).expect("the rclpy node is up");

    let mut set = ServiceClient::<SetBool>::builder()
        .node(&node)
        .name("/rclpy_ns/set")
        .build()
        .expect("client");
    let mut get_parameters = ServiceClient::<GetParameters>::builder()
        .node(&node)
        .name("/rclpy_ns/rclpy_server/get_parameters")
        .build()
        .expect("client");
    if refusing {
        for service in ["/rclpy_ns/set", "/rclpy_ns/rclpy_server/get_parameters"] {
            assert!(
                graph.wait_until(WAIT, |c| c.service_is_available(service)),
                "{service} never showed up on the graph"
            );
        }
        let asked = Instant::now();
        refused(
            "SetBool",
            asked,
            set.call(SetBoolRequest { data: true }, 5 * SECOND),
        );
        let asked = Instant::now();
        refused(
            "GetParameters",
            asked,
            get_parameters.call(
                GetParametersRequest {
                    names: vec!["gain".into()],
                },
                5 * SECOND,
            ),
        );
        assert!(!set.wait_for_service(WAIT));
        assert_eq!(set.pending_requests(), 0);
        // Nothing reached the rclpy servers.
        assert_eq!(peer.finish(WAIT), Ok(Some(0)), "{}", peer.output());
        assert!(peer.all("served").is_empty(), "{}", peer.output());
        return;
    }

    // SetBool, three calls; the request ids the peer's RMW took them with, from the server's
    // introspection events.
    assert!(set.wait_for_service(WAIT), "{}", peer.output());
    for (k, data) in [true, false, true].into_iter().enumerate() {
        let reply = set.call(SetBoolRequest { data }, 5 * SECOND);
        assert_eq!(
            reply,
            Ok(SetBoolResponse {
                success: data,
                message: format!("set to {}", if data { "True" } else { "False" }),
            }),
            "call {k}\n{}",
            peer.output()
        );
    }
    let received = peer
        .wait_for(WAIT, "3 REQUEST_RECEIVED events", |lines| {
            let got: Vec<Value> = lines
                .iter()
                .filter_map(|l| l.get("event"))
                .filter(|e| e["service"] == "/rclpy_ns/set" && e["event_type"] == 1)
                .cloned()
                .collect();
            (got.len() == 3).then_some(got)
        })
        .unwrap_or_else(|e| panic!("{e}"));
    for event in &received {
        assert!(
            event["client_gid"]
                .as_str()
                .is_some_and(|gid| request_ids::names_our_client(rmw, set.gids(), gid)),
            "{event}: not our client {:?} as {} names it",
            set.gids(),
            rmw.name()
        );
    }
    // No other client of this process calls meanwhile: rmw_cyclonedds' numbers are consecutive.
    let numbers: Vec<i64> = received
        .iter()
        .map(|e| e["sequence_number"].as_i64().unwrap_or_default())
        .collect();
    assert!(
        request_ids::sequence_numbers_are_ours(rmw, &numbers, true),
        "{numbers:?} are not the numbers of our 3 requests on {}",
        rmw.name()
    );

    // BasicTypes, typed: every field comes back as sent.
    let mut basic = ServiceClient::<BasicTypes>::builder()
        .node(&node)
        .name("/rclpy_ns/basic")
        .build()
        .expect("client");
    assert!(basic.wait_for_service(WAIT), "{}", peer.output());
    assert_eq!(
        basic.call(basic_request(), 5 * SECOND),
        Ok(echo(basic_request()))
    );

    // BasicTypes, dynamic: from the description rclpy's node serves for the type its event
    // publisher announces (rcl's node type cache holds the service's and the event's types).
    let event_hash = graph
        .wait_until(WAIT, |c| {
            c.publishers_info_by_topic("/rclpy_ns/basic/_service_event", false)
                .iter()
                .any(|p| p.topic_type_hash.is_set())
        })
        .then(|| {
            graph.read(|c| {
                c.publishers_info_by_topic("/rclpy_ns/basic/_service_event", false)[0]
                    .topic_type_hash
            })
        })
        .expect("the event publisher of /rclpy_ns/basic");
    assert_eq!(
        Ok(event_hash.to_string()),
        wheels::wheel_hash("test_msgs/srv/BasicTypes_Event")
    );
    let mut describe = ServiceClient::<GetTypeDescription>::builder()
        .node(&node)
        .name("/rclpy_ns/rclpy_server/get_type_description")
        .build()
        .expect("client");
    assert!(describe.wait_for_service(WAIT));
    let described = describe
        .call(
            GetTypeDescriptionRequest {
                type_name: "test_msgs/srv/BasicTypes_Event".into(),
                type_hash: event_hash.to_string(),
                include_type_sources: false,
            },
            5 * SECOND,
        )
        .expect("rclpy describes the event type");
    assert!(described.successful, "{}", described.failure_reason);
    // The description it sent hashes, by our RIHS01, to the hash it announced.
    assert_eq!(
        described.type_description.compute_type_hash(),
        event_hash,
        "{:?}",
        described.type_description
    );
    let service_type =
        ServiceType::from_descriptions("test_msgs/srv/BasicTypes", &[described.type_description])
            .expect("BasicTypes from its event's description");
    assert_eq!(
        service_type.part_hashes(),
        (
            BasicTypesRequest::type_hash(),
            BasicTypesResponse::type_hash()
        )
    );
    let mut dynamic = DynamicServiceClient::builder(service_type)
        .name("/rclpy_ns/basic")
        .node(&node)
        .build()
        .expect("dynamic client");
    assert!(dynamic.wait_for_service(WAIT));
    let reply = dynamic
        .call_json(&basic_request_json(), 5 * SECOND)
        .expect("dynamic call");
    assert_eq!(reply, basic_request_json());

    // Parameters: list, get, set, get.
    let mut list = ServiceClient::<ListParameters>::builder()
        .node(&node)
        .name("/rclpy_ns/rclpy_server/list_parameters")
        .build()
        .expect("client");
    let mut set_parameters = ServiceClient::<SetParameters>::builder()
        .node(&node)
        .name("/rclpy_ns/rclpy_server/set_parameters")
        .build()
        .expect("client");
    for ready in [
        list.wait_for_service(WAIT),
        get_parameters.wait_for_service(WAIT),
        set_parameters.wait_for_service(WAIT),
    ] {
        assert!(ready, "{}", peer.output());
    }
    let names = list
        .call(ListParametersRequest::default(), 5 * SECOND)
        .expect("list")
        .result
        .names;
    for name in ["gain", "label", "use_sim_time"] {
        assert!(names.contains(&name.to_owned()), "{names:?}");
    }
    let get = |client: &mut ServiceClient<GetParameters>| {
        client
            .call(
                GetParametersRequest {
                    names: vec!["gain".into(), "label".into()],
                },
                5 * SECOND,
            )
            .expect("get")
            .values
    };
    assert_eq!(
        get(&mut get_parameters),
        [double(1.5), ParameterValue::from_string("rclpy")]
    );
    let results = set_parameters
        .call(
            SetParametersRequest {
                parameters: vec![Parameter {
                    name: "gain".into(),
                    value: double(2.5),
                }],
            },
            5 * SECOND,
        )
        .expect("set")
        .results;
    assert!(results.len() == 1 && results[0].successful, "{results:?}");
    assert_eq!(get(&mut get_parameters)[0], double(2.5));
    assert_eq!(
        get(&mut get_parameters)[0].r#type,
        ParameterType::PARAMETER_DOUBLE
    );
    assert_eq!(peer.finish(WAIT), Ok(Some(0)), "{}", peer.output());
}

#[test]
fn rclpy_clients_call_our_servers() {
    const DOMAIN: u32 = 112;
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let refusing =
        !context.capabilities().carries_sample_identity && Rmw::of_peers().needs_sample_identity();
    let node = context
        .create_node("horus_node", "/horus_ns")
        .expect("node");
    let set = ServiceServer::<SetBool>::builder()
        .node(&node)
        .name("/horus_ns/set")
        .on_request(|r| {
            Ok(SetBoolResponse {
                success: !r.data,
                message: format!("horus got {}", r.data),
            })
        })
        .build()
        .expect("server");
    let basic = ServiceServer::<BasicTypes>::builder()
        .node(&node)
        .name("/horus_ns/basic")
        .on_request(|r| Ok(echo(r)))
        .build()
        .expect("server");
    let services = NodeServices::start(&node).expect("node services");
    services
        .declare_parameter("gain", double(0.5), Default::default())
        .expect("declare");

    // Refused, each call waits for its reply until its timeout.
    let timeout_s = if refusing { 1.0 } else { 10.0 };
    let mut peer = RclpyPeer::start(&json!({
        "domain": DOMAIN, "namespace": "/rclpy_ns", "name": "rclpy_client",
        "clients": [
            {"service": "/horus_ns/set", "type": "std_srvs/srv/SetBool", "wait_s": 30,
             "timeout_s": timeout_s, "calls": [{"data": true}, {"data": false}, {"data": true}]},
            {"service": "/horus_ns/basic", "type": "test_msgs/srv/BasicTypes", "wait_s": 30,
             "timeout_s": timeout_s, "calls": [basic_request_json()]},
        ],
        "parameter_client": {"node": "/horus_ns/horus_node", "list": true, "get": ["gain"],
                             "set": {"gain": 2.0}, "wait_s": 30, "timeout_s": timeout_s},
        "leave_when_done": true,
    }))
    .expect("start the rclpy peer");
    let code = peer.wait_exit(WAIT + WAIT).expect("the peer's exit");
    let output = peer.output();
    let done = peer.all("calls_done");
    assert_eq!(done.len(), 2, "{output}");
    if refusing {
        // Our servers were there for it (their endpoints matched), but its requests, which
        // need an answer through related_sample_identity, were dropped: no reply ever came,
        // and no handler ran.
        assert_eq!(code, Some(1), "{output}");
        for d in done {
            assert_eq!(
                (&d["available"], &d["answered"]),
                (&json!(true), &json!(0)),
                "{d}"
            );
        }
        assert!(peer.all("reply").is_empty(), "{output}");
        assert!(
            peer.all("parameters")[0].get("timeout").is_some(),
            "{output}"
        );
        assert_eq!((set.served_count(), basic.served_count()), (0, 0));
        assert_eq!(services.get_parameter("gain"), Ok(double(0.5)));
        return;
    }
    assert_eq!(code, Some(0), "{output}");
    let replies: Vec<&Value> = peer.all("reply");
    let of = |service: &str| -> Vec<Value> {
        replies
            .iter()
            .filter(|r| r["service"] == service)
            .map(|r| r["response"].clone())
            .collect()
    };
    // Each reply is the answer to its own request (rclpy matches them by sequence number).
    assert_eq!(
        of("/horus_ns/set"),
        [
            json!({"success": false, "message": "horus got true"}),
            json!({"success": true, "message": "horus got false"}),
            json!({"success": false, "message": "horus got true"}),
        ],
        "{output}"
    );
    // rclpy prints a byte as a list of its one byte.
    let mut basic_json = basic_request_json();
    basic_json["byte_value"] = json!([basic_request().byte_value.0]);
    assert_eq!(of("/horus_ns/basic"), [basic_json], "{output}");
    assert_eq!((set.served_count(), basic.served_count()), (3, 1));
    let parameters = peer.all("parameters");
    let parameters = parameters[0];
    assert!(
        parameters["list"]
            .as_array()
            .is_some_and(|l| l.contains(&json!("gain"))),
        "{parameters}"
    );
    assert_eq!(parameters["get"][0]["double_value"], 0.5, "{parameters}");
    assert_eq!(parameters["set"][0]["successful"], true, "{parameters}");
    assert_eq!(services.get_parameter("gain"), Ok(double(2.0)));
}
