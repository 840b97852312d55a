//! The live graph against a real ROS 2 Jazzy node (rclpy 7.1.6 on the run's RMW: rmw_fastrtps_cpp
//! 8.4.3 / Fast DDS 2.14.5, rmw_cyclonedds_cpp 2.2.2, or rmw_zenoh_cpp 0.2.10 beside rmw_zenohd)
//! with servers, a client, a publisher, a subscription and parameters, next to a node of ours with
//! the same kinds of entities: what we see equals what rclpy's own graph API sees, on every
//! backend.
//!
//! - Every query rclpy makes: the node list (with enclaves), topic and service names and types,
//!   each node's services and clients, and for every topic it lists (DDS topics on DDS, ROS names
//!   on Zenoh) the publishers and subscriptions with node, namespace, type, type hash, GID and
//!   QoS, as `ros2 topic info -v` prints them (`peers::view`).
//! - Our servers and clients info by service, for rclpy's services and for ours, equals what
//!   rclpy says of the same `rq/`/`rr/` endpoints on DDS; on Zenoh, where rclpy (Jazzy) has no
//!   query by service and rmw_zenoh lists no endpoint per service topic, each one's node and type
//!   are the ones rclpy gives for that node's services or clients.
//! - Every type hash on the graph — rclpy's endpoints' from their USER_DATA or tokens, ours as our
//!   types compute them — equals the wheels' own (`share/<pkg>/srv/<Name>.json`; on Zenoh a
//!   server's or client's token carries its service type's hash).
//! - When the rclpy node leaves, its node and services leave our graph.

use std::time::Duration;

use horus_ros_graph::{Graph, GraphCache, ServiceEndpointInfo, ServiceEndpointType};
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_msgs::std_srvs::srv::Trigger;
use horus_ros_rmw::names::ROS_TOPIC_PREFIX;
use horus_ros_rmw::qos::Qos;
use horus_ros_services::prelude::*;
use interop_tests::peers::{
    as_compared, lists, service_endpoint_text, service_topics, wait_for_same_view, wheels,
    RclpyPeer, Us,
};
use serde_json::{json, Value};

const DOMAIN: u32 = 110;
/// "Did not hang" bound for discovery on a loaded machine (Fast DDS 2.14 may send its endpoints
/// and `ros_discovery_info` only at its next heartbeat).
const WAIT: Duration = Duration::from_secs(60);

/// The texts rclpy lists for `side` (`publishers`/`subscriptions`) of a DDS topic.
fn listed<'a>(view: &'a Value, topic: &str, side: &str) -> Vec<&'a str> {
    view["endpoints"][topic][side]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default()
}

/// Each server or client of `service` (by our graph) is, endpoint by endpoint, what rclpy lists
/// on the service's DDS topics.
fn service_info_is_rclpys(
    cache: &GraphCache,
    us: &Us,
    view: &Value,
    service: &str,
    kind: ServiceEndpointType,
    node: (&str, &str),
    dds_type: &str,
) {
    let infos: Vec<ServiceEndpointInfo> = match kind {
        ServiceEndpointType::Server => cache.servers_info_by_service(service, false),
        ServiceEndpointType::Client => cache.clients_info_by_service(service, false),
    }
    .expect("a ROS service name");
    assert_eq!(infos.len(), 1, "{kind} of {service}: {infos:?}");
    let info = &infos[0];
    assert_eq!(
        (info.node_name.as_str(), info.node_namespace.as_str()),
        node
    );
    if us.on_zenoh() {
        // rclpy's view of the node's services or clients (see the module documentation).
        let side = match kind {
            ServiceEndpointType::Server => "services",
            ServiceEndpointType::Client => "clients",
        };
        let (name, namespace) = node;
        let qualified = format!("{}/{name}", namespace.trim_end_matches('/'));
        assert_eq!(
            view["node_services"][&qualified][side][service],
            json!([info.service_type]),
            "{kind} of {service}: rclpy's {side} of {qualified}:\n{view:#}"
        );
        assert_eq!(
            info.service_type.replace("/srv/", "::srv::dds_::"),
            dds_type,
            "{kind} of {service}"
        );
        return;
    }
    let (request, reply) = service_topics(service);
    // A server reads requests and writes replies; a client reads replies and writes requests.
    let (reader_topic, writer_topic) = match kind {
        ServiceEndpointType::Server => (&request, &reply),
        ServiceEndpointType::Client => (&reply, &request),
    };
    let (reader_type, writer_type) = match kind {
        ServiceEndpointType::Server => (
            format!("{dds_type}_Request_"),
            format!("{dds_type}_Response_"),
        ),
        ServiceEndpointType::Client => (
            format!("{dds_type}_Response_"),
            format!("{dds_type}_Request_"),
        ),
    };
    let mut shown = info.clone();
    if us.owns(info.endpoint_gids[0]) {
        // Ours, as they announce themselves (see `peers::view`).
        for (index, kind) in [
            horus_ros_graph::TopicEndpointType::Subscription,
            horus_ros_graph::TopicEndpointType::Publisher,
        ]
        .into_iter()
        .enumerate()
        {
            let announced = interop_tests::peers::announced(
                us,
                horus_ros_graph::TopicEndpointInfo {
                    node_name: String::new(),
                    node_namespace: String::new(),
                    topic_type: String::new(),
                    topic_type_hash: info.endpoint_type_hashes[index],
                    endpoint_type: kind,
                    endpoint_gid: info.endpoint_gids[index],
                    qos_profile: info.qos_profiles[index],
                },
            );
            shown.qos_profiles[index] = announced.qos_profile;
            shown.endpoint_type_hashes[index] = announced.topic_type_hash;
        }
    }
    let reader = as_compared(us, &service_endpoint_text(&shown, 0, &reader_type));
    let writer = as_compared(us, &service_endpoint_text(&shown, 1, &writer_type));
    assert!(
        listed(view, reader_topic, "subscriptions").contains(&reader.as_str()),
        "{kind} of {service}: rclpy lists no such reader on {reader_topic}:\n{reader}\n{view:#}"
    );
    assert!(
        listed(view, writer_topic, "publishers").contains(&writer.as_str()),
        "{kind} of {service}: rclpy lists no such writer on {writer_topic}:\n{writer}\n{view:#}"
    );
}

/// Every type hash set on the graph (ours as computed, rclpy's from USER_DATA or its tokens) is
/// the wheels' one for that type; returns how many were compared.
fn hashes_are_the_wheels(cache: &GraphCache, us: &Us, view: &Value) -> usize {
    let mut compared = 0;
    let ours = us.owned_in(cache);
    // On Zenoh the view's topics are ROS names (see `peers::view`).
    let no_mangle = !us.on_zenoh();
    for topic in view["endpoints"].as_object().expect("endpoints").keys() {
        let infos = cache
            .publishers_info_by_topic(topic, no_mangle)
            .into_iter()
            .chain(cache.subscriptions_info_by_topic(topic, no_mangle));
        for info in infos {
            if !info.topic_type_hash.is_set() {
                continue;
            }
            let ros_type = info.topic_type.replace("::dds_::", "::").replace("::", "/");
            let ros_type = ros_type.strip_suffix('_').unwrap_or(&ros_type);
            assert_eq!(
                Ok(info.topic_type_hash.to_string()),
                wheels::wheel_hash(ros_type),
                "{topic}: {info}"
            );
            compared += 1;
        }
    }
    if us.on_zenoh() {
        // rclpy's servers and clients: an `SS`/`SC` token carries the hash of the service type
        // (rmw_zenoh_cpp 0.2.10 `rmw_create_service`/`rmw_create_client`), which our graph gives
        // both endpoints of the entity.
        for (service, types) in cache.service_names_and_types(true) {
            let infos = cache
                .servers_info_by_service(&service, false)
                .into_iter()
                .chain(cache.clients_info_by_service(&service, false))
                .flatten()
                .filter(|i| !ours(i.endpoint_gids[0]));
            for info in infos {
                assert!(types.contains(&info.service_type), "{service}: {info:?}");
                for hash in &info.endpoint_type_hashes {
                    assert_eq!(
                        Ok(hash.to_string()),
                        wheels::wheel_hash(&info.service_type),
                        "{service}: {info:?}"
                    );
                    compared += 1;
                }
            }
        }
    }
    compared
}

#[test]
fn our_graph_is_what_rclpy_sees() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let us = Us::of(&context);
    let graph = Graph::of(&context).expect("graph");
    let node = context
        .create_node("horus_node", "/horus_ns")
        .expect("node");
    let _server = interop_tests::peers::clients::set_bool_server(&node, "/horus_ns/set");
    let _client = ServiceClient::<Trigger>::builder()
        .node(&node)
        .name("/rclpy_ns/trigger")
        .build()
        .expect("client");
    let _publisher = node
        .create_publisher::<StringMsg>("/chatter", &Qos::default())
        .expect("publisher");
    let _subscription = node
        .create_subscription::<StringMsg>("/chatter", &Qos::default())
        .expect("subscription");

    let mut peer = RclpyPeer::start(&json!({
        "domain": DOMAIN, "namespace": "/rclpy_ns", "name": "rclpy_node",
        "servers": [
            {"service": "/rclpy_ns/set", "type": "std_srvs/srv/SetBool"},
            {"service": "/rclpy_ns/trigger", "type": "std_srvs/srv/Trigger"},
        ],
        "clients": [{"service": "/horus_ns/set", "type": "std_srvs/srv/SetBool"}],
        "publishers": [{"topic": "/chatter", "type": "std_msgs/msg/String", "period_s": 1.0}],
        "subscriptions": [{"topic": "/chatter", "type": "std_msgs/msg/String"}],
        "parameters": {"gain": 1.5},
        "graph": true,
    }))
    .expect("start the rclpy peer");
    peer.ready(WAIT).expect("the rclpy node is up");

    // Complete: every endpoint each node made, as both sides see it.
    let rclpy_services = [
        "/rclpy_ns/set",
        "/rclpy_ns/trigger",
        "/rclpy_ns/rclpy_node/describe_parameters",
        "/rclpy_ns/rclpy_node/get_parameter_types",
        "/rclpy_ns/rclpy_node/get_parameters",
        "/rclpy_ns/rclpy_node/get_type_description",
        "/rclpy_ns/rclpy_node/list_parameters",
        "/rclpy_ns/rclpy_node/set_parameters",
        "/rclpy_ns/rclpy_node/set_parameters_atomically",
    ];
    // On Zenoh: by ROS names, and services by node (see `peers::view`).
    let complete_on_zenoh = |view: &Value| {
        let by_node = |node: &str, side: &str, service: &str| {
            view["node_services"][node][side].get(service).is_some()
        };
        rclpy_services
            .iter()
            .all(|s| by_node("/rclpy_ns/rclpy_node", "services", s))
            && by_node("/rclpy_ns/rclpy_node", "clients", "/horus_ns/set")
            && by_node("/horus_ns/horus_node", "services", "/horus_ns/set")
            && by_node("/horus_ns/horus_node", "clients", "/rclpy_ns/trigger")
            && ["horus_node", "rclpy_node"].iter().all(|n| {
                lists(view, "/chatter", "publishers", n)
                    && lists(view, "/chatter", "subscriptions", n)
            })
            && lists(view, "/rosout", "publishers", "rclpy_node")
            && lists(view, "/parameter_events", "publishers", "rclpy_node")
    };
    let complete = |view: &Value| {
        if us.on_zenoh() {
            return complete_on_zenoh(view);
        }
        let (request, reply) = service_topics("/horus_ns/set");
        rclpy_services.iter().all(|s| {
            let (request, reply) = service_topics(s);
            lists(view, &request, "subscriptions", "rclpy_node")
                && lists(view, &reply, "publishers", "rclpy_node")
        }) && lists(view, &request, "subscriptions", "horus_node")
            && lists(view, &reply, "publishers", "horus_node")
            && lists(view, &request, "publishers", "rclpy_node")
            && lists(view, &reply, "subscriptions", "rclpy_node")
            && ["horus_node", "rclpy_node"].iter().all(|n| {
                lists(view, "rt/chatter", "publishers", n)
                    && lists(view, "rt/chatter", "subscriptions", n)
            })
            && lists(view, "rt/rosout", "publishers", "rclpy_node")
            && lists(view, "rt/parameter_events", "publishers", "rclpy_node")
    };
    let view = wait_for_same_view(&mut peer, &graph, &us, WAIT, complete)
        .unwrap_or_else(|e| panic!("{e}"));
    // Both nodes, each with the entities it made (rclpy's adds its parameter and type
    // description services, /rosout and /parameter_events).
    let nodes: Vec<&Value> = view["nodes"].as_array().expect("nodes").iter().collect();
    assert_eq!(nodes.len(), 2, "{view:#}");
    assert!(view["topics"]["/chatter"] == json!(["std_msgs/msg/String"]));
    for service in [
        "/horus_ns/set",
        "/rclpy_ns/set",
        "/rclpy_ns/trigger",
        "/rclpy_ns/rclpy_node/get_parameters",
        "/rclpy_ns/rclpy_node/get_type_description",
    ] {
        assert!(
            view["services"].get(service).is_some(),
            "{service}: {view:#}"
        );
    }

    graph.read(|cache| {
        let rclpy_node = ("rclpy_node", "/rclpy_ns");
        let horus_node = ("horus_node", "/horus_ns");
        for (service, kind, node, dds_type) in [
            (
                "/rclpy_ns/set",
                ServiceEndpointType::Server,
                rclpy_node,
                "std_srvs::srv::dds_::SetBool",
            ),
            (
                "/rclpy_ns/trigger",
                ServiceEndpointType::Server,
                rclpy_node,
                "std_srvs::srv::dds_::Trigger",
            ),
            (
                "/rclpy_ns/trigger",
                ServiceEndpointType::Client,
                horus_node,
                "std_srvs::srv::dds_::Trigger",
            ),
            (
                "/horus_ns/set",
                ServiceEndpointType::Server,
                horus_node,
                "std_srvs::srv::dds_::SetBool",
            ),
            (
                "/horus_ns/set",
                ServiceEndpointType::Client,
                rclpy_node,
                "std_srvs::srv::dds_::SetBool",
            ),
            (
                "/rclpy_ns/rclpy_node/get_parameters",
                ServiceEndpointType::Server,
                rclpy_node,
                "rcl_interfaces::srv::dds_::GetParameters",
            ),
        ] {
            service_info_is_rclpys(cache, &us, &view, service, kind, node, dds_type);
        }
        let compared = hashes_are_the_wheels(cache, &us, &view);
        // At least rclpy's 11 services (22 endpoints) and both sides' /chatter endpoints.
        assert!(compared >= 26, "only {compared} hashes compared");
    });
    let chatter = if us.on_zenoh() {
        "/chatter".to_owned()
    } else {
        format!("{ROS_TOPIC_PREFIX}/chatter")
    };
    assert!(view["endpoints"][chatter].is_object(), "{view:#}");

    // It leaves: its node and services leave our graph.
    peer.leave();
    assert!(
        graph.wait_until(WAIT, |c| {
            !c.service_is_available("/rclpy_ns/set")
                && c.node_names().iter().all(|n| n.name != "rclpy_node")
        }),
        "the rclpy node never left our graph"
    );
    assert_eq!(peer.finish(WAIT), Ok(Some(0)), "{}", peer.output());
}
