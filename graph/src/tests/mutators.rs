//! Mutators: change reporting, events, participant loss, node removal, late discovery info.

use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::EndpointKind;

use super::fixtures::*;
use crate::{
    participant_gid_from_prefix, EndpointRole, GraphCache, GraphEndpoint, GraphEvent, NodeName,
    ParticipantKind, RosEndpoint, CREATED_BY_BARE_DDS_APP, NODE_NAME_UNKNOWN,
};

fn node_added(name: &str, namespace: &str) -> GraphEvent {
    GraphEvent::NodeAdded {
        name: name.to_owned(),
        namespace: namespace.to_owned(),
    }
}

fn node_removed(name: &str, namespace: &str) -> GraphEvent {
    GraphEvent::NodeRemoved {
        name: name.to_owned(),
        namespace: namespace.to_owned(),
    }
}

/// A `std_msgs/msg/String` publisher on `topic` (`rt/…`) of no known node, as events report it.
fn string_publisher(g: &str, topic: &str) -> GraphEndpoint {
    GraphEndpoint {
        node: None,
        ros: Some(RosEndpoint {
            role: EndpointRole::Publisher,
            name: topic.trim_start_matches("rt").to_owned(),
        }),
        gid: gid(g),
        kind: EndpointKind::Writer,
        dds_topic: topic.to_owned(),
        dds_type: STRING.to_owned(),
        type_name: "std_msgs/msg/String".to_owned(),
        type_hash: TypeHash::ZERO,
        qos: remote_qos(),
    }
}

#[test]
fn mutators_report_changes() {
    let mut g = GraphCache::new();
    assert!(g.add_participant(gid("p"), None));
    assert!(!g.add_participant(gid("p"), None));
    assert!(g.add_participant(gid("p"), Some("/".to_owned())));
    let e = writer("w", "p", "rt/t", STRING);
    assert!(g.add_entity(e.clone()));
    assert!(!g.add_entity(e.clone()));
    let mut moved = e;
    moved.dds_topic_name = "rt/u".to_owned();
    assert!(g.add_entity(moved));
    assert!(g.remove_entity(gid("w")));
    assert!(!g.remove_entity(gid("w")));
    let m = msg("p", vec![node("/", "n", &[], &[])]);
    assert!(g.update_participant_entities(m.clone()));
    assert!(!g.update_participant_entities(m));
    assert!(g.remove_participant(gid("p")));
    assert!(!g.remove_participant(gid("p")));
}

#[test]
fn events_are_recorded_only_when_enabled() {
    let mut g = GraphCache::new();
    g.add_entity(writer("w0", "p", "rt/t", STRING));
    assert!(g.drain_events().is_empty());
    g.record_events(true);
    let e = writer("w", "p", "rt/t", STRING);
    g.add_entity(e.clone());
    g.add_entity(e.clone()); // no change, no event
    let mut moved = e;
    moved.dds_topic_name = "rt/u".to_owned();
    g.add_entity(moved);
    g.update_participant_entities(msg("p", vec![node("/", "a", &[], &["w"])]));
    let a = NodeName {
        name: "a".to_owned(),
        namespace: "/".to_owned(),
    };
    assert_eq!(
        g.drain_events(),
        vec![
            GraphEvent::EndpointAdded(string_publisher("w", "rt/t")),
            GraphEvent::EndpointRemoved(string_publisher("w", "rt/t")),
            GraphEvent::EndpointAdded(string_publisher("w", "rt/u")),
            node_added("a", "/"),
            GraphEvent::EndpointNodeChanged {
                endpoint: GraphEndpoint {
                    node: Some(a),
                    ..string_publisher("w", "rt/u")
                },
                previous: None,
            },
        ]
    );
    assert!(g.drain_events().is_empty());
    g.record_events(false);
    g.remove_entity(gid("w"));
    assert!(g.drain_events().is_empty());
}

#[test]
fn participant_loss_removes_nodes_and_endpoints() {
    let mut g = sample_graph();
    g.record_events(true);
    assert!(g.remove_participant(gid("participant1")));
    let names: Vec<_> = g.node_names().into_iter().map(|n| n.name).collect();
    assert_eq!(names, vec!["client", "listener"]);
    assert_eq!(g.count_publishers("/chatter"), 1); // only the bare DDS writer is left
    assert_eq!(
        g.publishers_info_by_topic("/chatter", false)[0].node_name,
        CREATED_BY_BARE_DDS_APP
    );
    assert_eq!(g.count_services("/add_two_ints"), 0);
    assert_eq!(
        g.servers_info_by_service("/add_two_ints", false),
        Ok(vec![])
    );
    assert!(g
        .clients_info_by_service("/add_two_ints", false)
        .is_ok_and(|c| c.len() == 1));
    let events = g.drain_events();
    // Six endpoints of participant1 (with its ros_discovery_info writer), in GID order, then
    // its nodes.
    assert_eq!(
        events[6..],
        [node_removed("talker", "/"), node_removed("server", "/")]
    );
    let removed: Vec<_> = events[..6]
        .iter()
        .map(|e| match e {
            GraphEvent::EndpointRemoved(e) => e.gid,
            other => panic!("unexpected event {other:?}"),
        })
        .collect();
    assert_eq!(
        removed,
        [
            "discovery",
            "server_rep",
            "server_req",
            "talker_hid",
            "talker_pub",
            "unlisted1"
        ]
        .map(gid)
    );
}

#[test]
fn node_missing_from_new_message_is_gone() {
    let mut g = sample_graph();
    g.record_events(true);
    assert!(g.update_participant_entities(msg(
        "participant1",
        vec![node("/", "talker", &[], &["talker_pub", "talker_hid"])],
    )));
    let server = Some(NodeName {
        name: "server".to_owned(),
        namespace: "/".to_owned(),
    });
    let events = g.drain_events();
    // Its two endpoints, of no node now (GID order: `server_rep` < `server_req`), then the node.
    let unlisted: Vec<_> = events[..2]
        .iter()
        .map(|e| match e {
            GraphEvent::EndpointNodeChanged { endpoint, previous } => {
                (endpoint.gid, endpoint.node.clone(), previous.clone())
            }
            other => panic!("unexpected event {other:?}"),
        })
        .collect();
    assert_eq!(
        unlisted,
        [
            (gid("server_rep"), None, server.clone()),
            (gid("server_req"), None, server)
        ]
    );
    assert_eq!(events[2..], [node_removed("server", "/")]);
    assert!(g.service_names_and_types_by_node("server", "/").is_err());
    // Its endpoints are still discovered, now of an unknown node.
    assert_eq!(g.count_services("/add_two_ints"), 1);
    let Ok(servers) = g.servers_info_by_service("/add_two_ints", false) else {
        panic!("servers query failed");
    };
    assert_eq!(servers[0].node_name, NODE_NAME_UNKNOWN);
}

#[test]
fn duplicate_nodes_added_and_removed_one_for_one() {
    let mut g = GraphCache::new();
    g.record_events(true);
    let dup = || node("/", "dup", &[], &[]);
    g.update_participant_entities(msg("p", vec![dup(), dup()]));
    g.update_participant_entities(msg("p", vec![dup()]));
    assert_eq!(
        g.drain_events(),
        vec![
            node_added("dup", "/"),
            node_added("dup", "/"),
            node_removed("dup", "/")
        ]
    );
    assert_eq!(g.node_count(), 1);
}

#[test]
fn late_discovery_info_resolves_endpoints_seen_first() {
    let mut g = GraphCache::new();
    g.add_entity(writer("w", "p", "rt/t", STRING));
    // Participant not seen at all: a bare DDS app, but still counted and listed.
    assert_eq!(g.count_publishers("/t"), 1);
    assert!(g.topic_names_and_types(false).contains_key("/t"));
    assert_eq!(
        g.publishers_info_by_topic("/t", false)[0].node_name,
        CREATED_BY_BARE_DDS_APP
    );
    // Participant seen in SPDP, no ros_discovery_info yet.
    g.add_participant(gid("p"), Some("/".to_owned()));
    assert_eq!(
        g.publishers_info_by_topic("/t", false)[0].node_name,
        NODE_NAME_UNKNOWN
    );
    assert!(g.node_names().is_empty());
    // Its message arrives.
    g.update_participant_entities(msg("p", vec![node("/x", "late", &[], &["w"])]));
    let info = &g.publishers_info_by_topic("/t", false)[0];
    assert_eq!(
        (info.node_name.as_str(), info.node_namespace.as_str()),
        ("late", "/x")
    );
    assert_eq!(g.node_names()[0].enclave.as_deref(), Some("/"));
}

#[test]
fn discovery_info_before_spdp_creates_the_participant() {
    let mut g = GraphCache::new();
    g.update_participant_entities(msg("p", vec![node("/", "n", &[], &["w"])]));
    g.add_entity(writer("w", "p", "rt/t", STRING));
    assert_eq!(g.publishers_info_by_topic("/t", false)[0].node_name, "n");
    assert_eq!(g.node_names()[0].enclave, None);
    // SPDP then adds the enclave without losing the nodes.
    g.add_participant(gid("p"), Some("/secure".to_owned()));
    assert_eq!(g.node_names()[0].enclave.as_deref(), Some("/secure"));
    assert_eq!(g.node_count(), 1);
}

#[test]
fn participant_gid_from_guid_prefix() {
    let prefix = [1, 15, 200, 182, 254, 67, 179, 68, 0, 0, 0, 0];
    assert_eq!(
        participant_gid_from_prefix(prefix).to_string(),
        "01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.01.c1"
    );
    // Endpoints are matched to a participant by GUID prefix.
    let mut g = GraphCache::new();
    g.add_participant(participant_gid_from_prefix(prefix), None);
    let mut e = writer("w", "p", "rt/t", STRING);
    let mut data = [0u8; 16];
    data[..12].copy_from_slice(&prefix);
    data[12..].copy_from_slice(&[0, 0, 0x12, 0x03]);
    e.participant_gid = crate::Gid::from_bytes(data);
    g.add_entity(e);
    assert_eq!(
        g.publishers_info_by_topic("/t", false)[0].node_name,
        NODE_NAME_UNKNOWN
    );
    assert!(g.remove_participant(participant_gid_from_prefix(prefix)));
    assert_eq!(g.count_publishers("/t"), 0);
}

#[test]
fn consistency_needs_every_participant_announced_and_its_endpoints_known() {
    let mut c = GraphCache::new();
    assert!(c.is_consistent(), "nothing known is consistent");
    c.add_participant(participant_gid_from_prefix(gid("p1").prefix()), None);
    assert!(
        !c.is_consistent(),
        "a participant without ros_discovery_info"
    );
    c.update_participant_entities(msg("p1", vec![node("/", "n", &["r1"], &["w1"])]));
    assert!(
        !c.is_consistent(),
        "its node lists endpoints not discovered yet"
    );
    c.add_entity(reader("r1", "p1", "rt/a", "std_msgs::msg::dds_::String_"));
    assert!(!c.is_consistent());
    c.add_entity(writer("w1", "p1", "rt/b", "std_msgs::msg::dds_::String_"));
    assert!(c.is_consistent());
    // An empty message counts as announced too.
    assert!(
        c.update_participant_entities(msg("p2", vec![])),
        "a first, empty message is a change"
    );
    assert!(c.is_consistent());
}

#[test]
fn endpoints_of_a_participant_not_reported_yet_keep_the_cache_unsettled() {
    let mut c = GraphCache::new();
    // DDS reported the participant's ros_discovery_info writer before the participant: that
    // participant has not announced its nodes either.
    c.add_entity(writer("info", "p1", "ros_discovery_info", INFO));
    c.add_entity(writer("w1", "p1", "rt/b", "std_msgs::msg::dds_::String_"));
    let p1 = participant_gid_from_prefix(gid("p1").prefix());
    let unsettled = c.unsettled();
    assert_eq!(unsettled.unannounced, vec![p1]);
    assert_eq!(unsettled.missing_endpoints, 0);
    assert!(!c.is_consistent());
    c.update_participant_entities(msg("p1", vec![node("/", "n", &["r1"], &["w1"])]));
    assert_eq!(c.unsettled().unannounced, vec![]);
    assert_eq!(c.unsettled().incomplete, vec![p1]);
    assert_eq!(
        c.unsettled().missing_endpoints,
        1,
        "r1 is listed, not discovered"
    );
    c.add_entity(reader("r1", "p1", "rt/a", "std_msgs::msg::dds_::String_"));
    assert!(c.unsettled().is_empty());
}

#[test]
fn participants_that_are_not_ros_do_not_keep_the_cache_unsettled() {
    let prefix = |s: &str| gid(s).prefix();
    let p = |s: &str| participant_gid_from_prefix(prefix(s));
    let mut c = GraphCache::new();
    // SPDP alone, no USER_DATA read: undecided.
    c.add_participant(p("bare"), None);
    assert_eq!(
        c.participant_kind(prefix("bare")),
        ParticipantKind::Undecided
    );
    assert_eq!(c.unsettled().undecided, vec![p("bare")]);
    assert!(!c.is_consistent());
    // Readers tell nothing (a ROS participant's readers can come before its writers)...
    c.add_entity(reader("r", "bare", "rt/x", STRING));
    assert_eq!(
        c.participant_kind(prefix("bare")),
        ParticipantKind::Undecided
    );
    // ...a writer that is not on ros_discovery_info does: an rmw creates that one first.
    c.add_entity(writer("w", "bare", "pong", "DDSPerf::Pong"));
    assert_eq!(c.participant_kind(prefix("bare")), ParticipantKind::NotRos);
    assert!(c.is_consistent(), "{:?}", c.unsettled());

    // USER_DATA without an enclave: not ROS at once.
    c.add_participant(p("plain"), None);
    assert!(c.mark_not_ros(p("plain")));
    assert!(!c.mark_not_ros(p("plain")), "no change the second time");
    assert_eq!(c.participant_kind(prefix("plain")), ParticipantKind::NotRos);
    assert!(c.is_consistent());
    // ...unless it turns out to have a ros_discovery_info writer after all.
    c.add_entity(writer("plain_info", "plain", "ros_discovery_info", INFO));
    assert_eq!(c.participant_kind(prefix("plain")), ParticipantKind::Ros);
    assert_eq!(c.unsettled().unannounced, vec![p("plain")]);

    // An enclave makes a ROS participant, awaited until it announces.
    c.add_participant(p("ros"), Some("/".to_owned()));
    assert_eq!(c.participant_kind(prefix("ros")), ParticipantKind::Ros);
    assert_eq!(c.unsettled().unannounced, vec![p("plain"), p("ros")]);
    assert!(c.unsettled().ros_outstanding());
    c.update_participant_entities(msg("ros", vec![]));
    c.update_participant_entities(msg("plain", vec![]));
    assert!(c.is_consistent());
    // The snapshot keeps what USER_DATA said.
    let rebuilt = GraphCache::from_snapshot(c.snapshot());
    assert_eq!(
        rebuilt.participant_kind(prefix("bare")),
        ParticipantKind::NotRos
    );
    assert!(rebuilt.is_consistent());
}
