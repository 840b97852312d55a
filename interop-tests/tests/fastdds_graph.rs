//! The live graph against a Fast DDS 2.9 peer that joins as an rmw_fastrtps_cpp participant with
//! an AddTwoInts server and client: our servers/clients info by service equals the GUIDs and QoS
//! Fast DDS itself reports for those endpoints.

use std::time::Duration;

use horus_ros_graph::{Graph, ServiceEndpointType};
use horus_ros_rmw::qos::{DurabilityPolicy, HistoryPolicy, ReliabilityPolicy};
use horus_ros_rmw::{Context, VendorId};
use interop_tests::fastdds::FastDdsPeer;

const DOMAIN: u32 = 64;
const WAIT: Duration = Duration::from_secs(20);

#[test]
fn servers_and_clients_info_match_what_fast_dds_holds() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let graph = Graph::new(&context).expect("graph");
    let mut peer = FastDdsPeer::start(
        DOMAIN,
        "/fast_ns",
        "fast_node",
        "/fast_ns/add_two_ints",
        // Stays until told to leave below (a loaded machine can take seconds to discover it).
        Duration::from_secs(120),
    )
    .expect("start the Fast DDS peer");
    let created = peer.created(WAIT).expect("the peer's start-up line");
    let service = "/fast_ns/add_two_ints";
    let complete = |c: &horus_ros_graph::GraphCache| {
        let named = |v: Vec<horus_ros_graph::ServiceEndpointInfo>| {
            v.iter().any(|i| i.node_name == "fast_node")
        };
        c.servers_info_by_service(service, false)
            .map(named)
            .unwrap_or(false)
            && c.clients_info_by_service(service, false)
                .map(named)
                .unwrap_or(false)
    };
    assert!(
        graph.wait_until(WAIT, complete),
        "the peer's server and client never showed up with their node"
    );

    let servers = graph
        .read(|c| c.servers_info_by_service(service, false))
        .expect("servers");
    let clients = graph
        .read(|c| c.clients_info_by_service(service, false))
        .expect("clients");
    assert_eq!((servers.len(), clients.len()), (1, 1));
    let (s, c) = (&servers[0], &clients[0]);
    for (info, kind) in [
        (s, ServiceEndpointType::Server),
        (c, ServiceEndpointType::Client),
    ] {
        assert_eq!(
            (info.node_name.as_str(), info.node_namespace.as_str()),
            ("fast_node", "/fast_ns")
        );
        assert_eq!(info.service_type, "example_interfaces/srv/AddTwoInts");
        assert_eq!(info.endpoint_type, kind);
        assert_eq!(info.endpoint_count(), 2);
    }
    let gids = |i: &horus_ros_graph::ServiceEndpointInfo| {
        i.endpoint_gids
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
    };
    // Reader first, then writer (rmw get_service_endpoint_info.h).
    assert_eq!(
        gids(s),
        vec![
            created.server_request_reader.clone(),
            created.server_reply_writer.clone()
        ]
    );
    assert_eq!(
        gids(c),
        vec![
            created.client_reply_reader.clone(),
            created.client_request_writer.clone()
        ]
    );
    let theirs = &created.json["qos"];
    for (info, names) in [
        (s, ["request_reader", "reply_writer"]),
        (c, ["reply_reader", "request_writer"]),
    ] {
        for (qos, name) in info.qos_profiles.iter().zip(names) {
            assert_eq!(
                qos.reliability.to_string(),
                theirs[name]["reliability"].as_str().unwrap_or(""),
                "{name}"
            );
            assert_eq!(qos.reliability, ReliabilityPolicy::Reliable, "{name}");
            assert_eq!(qos.durability, DurabilityPolicy::Volatile, "{name}");
            assert_eq!(
                qos.history,
                HistoryPolicy::Unknown,
                "{name}: depth is not carried by discovery"
            );
        }
    }
    assert_eq!(
        graph.participant_vendor(s.endpoint_gids[0]),
        Some(VendorId::FAST_DDS)
    );
    // The peer leaves: its server and client go away.
    peer.leave().expect("ask the peer to leave");
    assert!(graph.wait_until(WAIT, |c| !c.service_is_available(service)));
    let _ = peer.wait(WAIT);
}
