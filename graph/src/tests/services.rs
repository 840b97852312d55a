//! Servers and clients info by service.

use horus_ros_msgs::TypeHash;

use super::fixtures::*;
use crate::{GraphCache, GraphError, ServiceEndpointType, NODE_NAME_UNKNOWN};

#[test]
fn servers_and_clients_paired_reader_then_writer() {
    let g = sample_graph();
    let servers = g.servers_info_by_service("/add_two_ints", false);
    let Ok(servers) = servers else {
        panic!("servers query failed: {servers:?}");
    };
    assert_eq!(servers.len(), 1);
    let s = &servers[0];
    assert_eq!(
        (s.node_name.as_str(), s.node_namespace.as_str()),
        ("server", "/")
    );
    assert_eq!(s.service_type, "example_interfaces/srv/AddTwoInts");
    assert_eq!(s.endpoint_type, ServiceEndpointType::Server);
    assert_eq!(s.endpoint_count(), 2);
    assert_eq!(s.endpoint_gids, vec![gid("server_req"), gid("server_rep")]);
    assert_eq!(s.qos_profiles, vec![remote_qos(), remote_qos()]);
    assert_eq!(s.service_type_hash, TypeHash::ZERO);

    let clients = g.clients_info_by_service("/add_two_ints", false);
    let Ok(clients) = clients else {
        panic!("clients query failed: {clients:?}");
    };
    assert_eq!(clients.len(), 1);
    let c = &clients[0];
    assert_eq!(
        (c.node_name.as_str(), c.node_namespace.as_str()),
        ("client", "/ns")
    );
    assert_eq!(c.endpoint_type, ServiceEndpointType::Client);
    // Response reader, then request writer.
    assert_eq!(c.endpoint_gids, vec![gid("client_rep"), gid("client_req")]);
}

#[test]
fn unknown_service_is_empty_and_no_mangle_is_an_error() {
    let g = sample_graph();
    assert_eq!(g.servers_info_by_service("/nothing", false), Ok(vec![]));
    assert_eq!(g.clients_info_by_service("/nothing", false), Ok(vec![]));
    assert_eq!(
        g.servers_info_by_service("/add_two_ints", true),
        Err(GraphError::NoMangleUnsupported)
    );
    assert_eq!(
        g.clients_info_by_service("/add_two_ints", true),
        Err(GraphError::NoMangleUnsupported)
    );
}

#[test]
fn half_visible_server_is_counted_but_not_listed() {
    let mut g = GraphCache::new();
    g.update_participant_entities(msg("p", vec![node("/", "srv", &["req"], &["rep"])]));
    // Reply writer first: counted as a service (rmw_count.cpp), listed by name, not ready.
    g.add_entity(writer("rep", "p", ADD_RR, ADD_RES));
    assert_eq!(g.count_services("/add_two_ints"), 1);
    assert!(g
        .service_names_and_types(false)
        .contains_key("/add_two_ints"));
    assert_eq!(
        g.servers_info_by_service("/add_two_ints", false),
        Ok(vec![])
    );
    assert!(!g.service_is_available("/add_two_ints"));
    // Then the request reader: one complete server.
    g.add_entity(reader("req", "p", ADD_RQ, ADD_REQ));
    assert!(g.service_is_available("/add_two_ints"));
    let servers = g.servers_info_by_service("/add_two_ints", false);
    assert_eq!(servers.map(|s| s.len()), Ok(1));
    // Request reader alone (writer lost): not listed again.
    g.remove_entity(gid("rep"));
    assert_eq!(
        g.servers_info_by_service("/add_two_ints", false),
        Ok(vec![])
    );
    assert_eq!(g.count_services("/add_two_ints"), 0);
}

#[test]
fn duplicate_node_names_pair_within_their_participant() {
    let mut g = GraphCache::new();
    for p in ["pa", "pb"] {
        let (rq, rr) = (format!("{p}_req"), format!("{p}_rep"));
        g.add_entity(reader(&rq, p, ADD_RQ, ADD_REQ));
        g.add_entity(writer(&rr, p, ADD_RR, ADD_RES));
        g.update_participant_entities(msg(p, vec![node("/", "dup", &[&rq], &[&rr])]));
    }
    let names: Vec<_> = g.node_names().into_iter().map(|n| n.name).collect();
    assert_eq!(names, vec!["dup", "dup"]);
    let Ok(servers) = g.servers_info_by_service("/add_two_ints", false) else {
        panic!("servers query failed");
    };
    let gids: Vec<_> = servers.iter().map(|s| s.endpoint_gids.clone()).collect();
    assert_eq!(
        gids,
        vec![
            vec![gid("pa_req"), gid("pa_rep")],
            vec![gid("pb_req"), gid("pb_rep")],
        ]
    );
    assert!(servers.iter().all(|s| s.node_name == "dup"));
}

#[test]
fn two_servers_in_one_node_pair_in_gid_order() {
    let mut g = GraphCache::new();
    g.add_entity(reader("req1", "p", ADD_RQ, ADD_REQ));
    g.add_entity(reader("req2", "p", ADD_RQ, ADD_REQ));
    g.add_entity(writer("rep1", "p", ADD_RR, ADD_RES));
    g.add_entity(writer("rep2", "p", ADD_RR, ADD_RES));
    g.update_participant_entities(msg(
        "p",
        vec![node("/", "n", &["req1", "req2"], &["rep1", "rep2"])],
    ));
    let Ok(servers) = g.servers_info_by_service("/add_two_ints", false) else {
        panic!("servers query failed");
    };
    let gids: Vec<_> = servers.iter().map(|s| s.endpoint_gids.clone()).collect();
    assert_eq!(
        gids,
        vec![
            vec![gid("req1"), gid("rep1")],
            vec![gid("req2"), gid("rep2")]
        ]
    );
}

#[test]
fn unknown_node_endpoints_pair_by_participant() {
    // Late ros_discovery_info: both endpoints of the participant's server are unlisted.
    let mut g = GraphCache::new();
    g.add_participant(gid("p"), None);
    g.add_entity(reader("req", "p", ADD_RQ, ADD_REQ));
    g.add_entity(writer("rep", "p", ADD_RR, ADD_RES));
    let Ok(servers) = g.servers_info_by_service("/add_two_ints", false) else {
        panic!("servers query failed");
    };
    assert_eq!(servers.len(), 1);
    assert_eq!(servers[0].node_name, NODE_NAME_UNKNOWN);
    // An endpoint of another participant does not pair with them.
    g.add_entity(writer("rep_other", "q", ADD_RR, ADD_RES));
    assert_eq!(
        g.servers_info_by_service("/add_two_ints", false)
            .map(|s| s.len()),
        Ok(1)
    );
}

#[test]
fn service_type_hash_when_registered() {
    let mut g = sample_graph();
    let Ok(hash) =
        TypeHash::parse("RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a")
    else {
        panic!("bad test hash");
    };
    g.set_service_type_hash("example_interfaces/srv/AddTwoInts", hash);
    let servers = g.servers_info_by_service("/add_two_ints", false);
    assert_eq!(servers.map(|s| s[0].service_type_hash), Ok(hash));
}
