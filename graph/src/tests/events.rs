//! ROS-level graph events: each endpoint with its node (whichever of the endpoint and its
//! node's `ros_discovery_info` comes first), role, ROS name and type; endpoints that are not
//! ROS; and the events alone rebuilding the graph.

use std::collections::BTreeMap;

use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_rmw::qos::EndpointKind;

use super::fixtures::*;
use crate::{EndpointRole, GraphCache, GraphEndpoint, GraphEvent, NodeName, RosEndpoint};

fn node_name(namespace: &str, name: &str) -> NodeName {
    NodeName {
        name: name.to_owned(),
        namespace: namespace.to_owned(),
    }
}

fn node_added(namespace: &str, name: &str) -> GraphEvent {
    GraphEvent::NodeAdded {
        name: name.to_owned(),
        namespace: namespace.to_owned(),
    }
}

fn node_removed(namespace: &str, name: &str) -> GraphEvent {
    GraphEvent::NodeRemoved {
        name: name.to_owned(),
        namespace: namespace.to_owned(),
    }
}

/// The endpoint of `event` (added, removed or moved).
fn endpoint_of(event: &GraphEvent) -> &GraphEndpoint {
    match event {
        GraphEvent::EndpointAdded(e)
        | GraphEvent::EndpointRemoved(e)
        | GraphEvent::EndpointNodeChanged { endpoint: e, .. } => e,
        other => panic!("not an endpoint event: {other:?}"),
    }
}

/// A graph recording events from empty.
fn recording() -> GraphCache {
    let mut g = GraphCache::new();
    g.record_events(true);
    g
}

#[test]
fn an_endpoint_discovered_before_its_nodes_message_gets_its_node_when_it_arrives() {
    let mut g = recording();
    g.add_participant(gid("p"), Some("/".to_owned()));
    g.add_entity(writer("w", "p", "rt/x/t", STRING));
    let events = g.drain_events();
    assert_eq!(events.len(), 1);
    let GraphEvent::EndpointAdded(added) = &events[0] else {
        panic!("{events:?}");
    };
    assert_eq!(added.node, None, "no message of its participant yet");
    assert_eq!(
        added.ros,
        Some(RosEndpoint {
            role: EndpointRole::Publisher,
            name: "/x/t".to_owned()
        })
    );
    assert_eq!(added.type_name, "std_msgs/msg/String");
    assert_eq!(added.dds_type, STRING);
    assert_eq!(added.qos, remote_qos());

    // Its node's message arrives: the node, then the endpoint again with its node.
    g.update_participant_entities(msg("p", vec![node("/x", "late", &[], &["w"])]));
    assert_eq!(
        g.drain_events(),
        vec![
            node_added("/x", "late"),
            GraphEvent::EndpointNodeChanged {
                endpoint: GraphEndpoint {
                    node: Some(node_name("/x", "late")),
                    ..added.clone()
                },
                previous: None,
            },
        ]
    );
    assert_eq!(
        g.endpoint(gid("w")).and_then(|e| e.node),
        Some(node_name("/x", "late"))
    );
    // The same message again changes nothing.
    g.update_participant_entities(msg("p", vec![node("/x", "late", &[], &["w"])]));
    assert!(g.drain_events().is_empty());
}

#[test]
fn an_endpoint_discovered_after_its_nodes_message_comes_with_its_node() {
    let mut g = recording();
    g.update_participant_entities(msg("p", vec![node("/", "early", &["r"], &[])]));
    g.add_entity(reader("r", "p", "rt/t", STRING));
    let events = g.drain_events();
    assert_eq!(events[0], node_added("/", "early"));
    let [_, GraphEvent::EndpointAdded(added)] = events.as_slice() else {
        panic!("{events:?}");
    };
    assert_eq!(added.node, Some(node_name("/", "early")));
    assert_eq!(added.kind, EndpointKind::Reader);
    assert_eq!(
        added.ros.as_ref().map(|r| (r.role, r.name.as_str())),
        Some((EndpointRole::Subscription, "/t"))
    );
    // Removed by itself, it is reported with its node.
    g.remove_entity(gid("r"));
    assert_eq!(
        g.drain_events(),
        vec![GraphEvent::EndpointRemoved(added.clone())]
    );
}

#[test]
fn only_the_endpoints_own_participant_names_its_node() {
    let mut g = recording();
    g.add_entity(writer("w", "p", "rt/t", STRING));
    // Another participant's node listing the GID does not make it that node's.
    g.update_participant_entities(msg("q", vec![node("/", "other", &[], &["w"])]));
    assert_eq!(g.drain_events()[1..], [node_added("/", "other")]);
    assert_eq!(g.endpoint(gid("w")).and_then(|e| e.node), None);
    // A node listing it as a reader does not either (rmw_dds_common matches the kind).
    g.update_participant_entities(msg("p", vec![node("/", "mine", &["w"], &[])]));
    assert_eq!(g.drain_events(), vec![node_added("/", "mine")]);
    assert_eq!(g.endpoint(gid("w")).and_then(|e| e.node), None);
}

#[test]
fn a_service_servers_and_clients_two_endpoints_each_say_which_they_are() {
    let mut g = recording();
    g.update_participant_entities(msg(
        "p",
        vec![
            node("/", "server", &["server_req"], &["server_rep"]),
            node("/", "client", &["client_rep"], &["client_req"]),
        ],
    ));
    g.add_entity(reader("server_req", "p", ADD_RQ, ADD_REQ));
    g.add_entity(writer("server_rep", "p", ADD_RR, ADD_RES));
    g.add_entity(writer("client_req", "p", ADD_RQ, ADD_REQ));
    g.add_entity(reader("client_rep", "p", ADD_RR, ADD_RES));
    let events = g.drain_events();
    assert_eq!(
        events[..2],
        [node_added("/", "server"), node_added("/", "client")]
    );
    let added: Vec<_> = events[2..]
        .iter()
        .map(|e| {
            let GraphEvent::EndpointAdded(e) = e else {
                panic!("{e:?}");
            };
            let ros = e.ros.as_ref().expect("a ROS endpoint");
            assert_eq!(ros.name, "/add_two_ints");
            assert_eq!(e.type_name, "example_interfaces/srv/AddTwoInts");
            assert_eq!(ros.role.kind(), e.kind);
            (
                e.gid,
                ros.role,
                e.node.as_ref().map(|n| n.name.as_str()),
                e.dds_type.as_str(),
            )
        })
        .collect();
    assert_eq!(
        added,
        [
            (
                gid("server_req"),
                EndpointRole::ServerRequestReader,
                Some("server"),
                ADD_REQ
            ),
            (
                gid("server_rep"),
                EndpointRole::ServerResponseWriter,
                Some("server"),
                ADD_RES
            ),
            (
                gid("client_req"),
                EndpointRole::ClientRequestWriter,
                Some("client"),
                ADD_REQ
            ),
            (
                gid("client_rep"),
                EndpointRole::ClientResponseReader,
                Some("client"),
                ADD_RES
            ),
        ]
    );
}

#[test]
fn endpoints_removed_with_their_participant_name_their_nodes_before_the_nodes_go() {
    let mut g = sample_graph();
    g.record_events(true);
    g.remove_participant(gid("participant1"));
    let events = g.drain_events();
    let removed: Vec<_> = events[..6]
        .iter()
        .map(|e| {
            let GraphEvent::EndpointRemoved(e) = e else {
                panic!("{e:?}");
            };
            (
                e.gid,
                e.node.as_ref().map(|n| n.name.as_str()),
                e.ros.as_ref().map(|r| r.role),
            )
        })
        .collect();
    assert_eq!(
        removed,
        [
            (gid("discovery"), None, None),
            (
                gid("server_rep"),
                Some("server"),
                Some(EndpointRole::ServerResponseWriter)
            ),
            (
                gid("server_req"),
                Some("server"),
                Some(EndpointRole::ServerRequestReader)
            ),
            (
                gid("talker_hid"),
                Some("talker"),
                Some(EndpointRole::Publisher)
            ),
            (
                gid("talker_pub"),
                Some("talker"),
                Some(EndpointRole::Publisher)
            ),
            (gid("unlisted1"), None, Some(EndpointRole::Publisher)),
        ]
    );
    assert_eq!(
        events[6..],
        [node_removed("/", "talker"), node_removed("/", "server")]
    );
}

#[test]
fn a_node_renamed_takes_its_endpoints_along() {
    let mut g = recording();
    g.add_entity(writer("w", "p", "rt/t", STRING));
    g.update_participant_entities(msg("p", vec![node("/", "a", &[], &["w"])]));
    g.drain_events();
    g.update_participant_entities(msg("p", vec![node("/", "b", &[], &["w"])]));
    let events = g.drain_events();
    assert_eq!(events.len(), 3, "{events:?}");
    assert_eq!(events[0], node_added("/", "b"));
    assert_eq!(
        events[1],
        GraphEvent::EndpointNodeChanged {
            endpoint: g.endpoint(gid("w")).expect("known"),
            previous: Some(node_name("/", "a")),
        }
    );
    assert_eq!(endpoint_of(&events[1]).node, Some(node_name("/", "b")));
    assert_eq!(events[2], node_removed("/", "a"));
}

#[test]
fn endpoints_that_are_not_ros_are_reported_without_a_role() {
    let mut g = recording();
    g.update_participant_entities(msg("p", vec![]));
    g.add_entity(writer("info", "p", "ros_discovery_info", INFO));
    g.add_entity(writer("pong", "bare", "pong", "DDSPerf::Pong"));
    let events = g.drain_events();
    let reported: Vec<_> = events
        .iter()
        .map(|e| {
            let e = endpoint_of(e);
            (e.ros.clone(), e.node.clone(), e.type_name.as_str())
        })
        .collect();
    assert_eq!(
        reported,
        [
            (None, None, "rmw_dds_common/msg/ParticipantEntitiesInfo"),
            (None, None, "DDSPerf::Pong"),
        ]
    );
    assert_eq!(g.all_endpoints().len(), 2);
}

#[test]
fn all_endpoints_are_in_gid_order_as_events_give_them() {
    let g = sample_graph();
    let all = g.all_endpoints();
    assert_eq!(all.len(), 10);
    assert!(all.windows(2).all(|w| w[0].gid < w[1].gid));
    for e in &all {
        assert_eq!(g.endpoint(e.gid).as_ref(), Some(e));
    }
    let talker = all
        .iter()
        .find(|e| e.gid == gid("talker_pub"))
        .expect("talker_pub");
    assert_eq!(talker.node, Some(node_name("/", "talker")));
    assert_eq!(g.endpoint(gid("nothing")), None);
}

/// What the events tell, replayed: nodes (counted) and endpoints by GID.
#[derive(Default)]
struct Replay {
    nodes: BTreeMap<NodeName, usize>,
    endpoints: BTreeMap<Gid, GraphEndpoint>,
}

impl Replay {
    /// Applies `event`, checking every node it names is present at that point.
    fn apply(&mut self, event: GraphEvent) {
        let present = |nodes: &BTreeMap<NodeName, usize>, node: &Option<NodeName>| {
            node.as_ref()
                .is_none_or(|n| nodes.get(n).is_some_and(|count| *count > 0))
        };
        match event {
            GraphEvent::NodeAdded { name, namespace } => {
                *self.nodes.entry(NodeName { name, namespace }).or_default() += 1;
            }
            GraphEvent::NodeRemoved { name, namespace } => {
                let key = NodeName { name, namespace };
                let count = self.nodes.get_mut(&key).expect("a node removed was added");
                *count -= 1;
                if *count == 0 {
                    self.nodes.remove(&key);
                }
            }
            GraphEvent::EndpointAdded(e) => {
                assert!(present(&self.nodes, &e.node), "{e:?}: its node is absent");
                assert!(self.endpoints.insert(e.gid, e).is_none(), "added twice");
            }
            GraphEvent::EndpointRemoved(e) => {
                assert!(present(&self.nodes, &e.node), "{e:?}: its node is absent");
                assert_eq!(self.endpoints.remove(&e.gid), Some(e), "as it was shown");
            }
            GraphEvent::EndpointNodeChanged { endpoint, previous } => {
                assert!(present(&self.nodes, &endpoint.node), "{endpoint:?}");
                let old = self.endpoints.get_mut(&endpoint.gid).expect("known");
                assert_eq!(old.node, previous);
                *old = endpoint;
            }
        }
    }

    /// Panics unless the replay shows what `g` holds.
    fn assert_shows(&self, g: &GraphCache) {
        let mut nodes: BTreeMap<NodeName, usize> = BTreeMap::new();
        for n in g.node_names() {
            *nodes.entry(node_name(&n.namespace, &n.name)).or_default() += 1;
        }
        assert_eq!(self.nodes, nodes);
        let endpoints: Vec<_> = self.endpoints.values().cloned().collect();
        assert_eq!(endpoints, g.all_endpoints());
    }
}

#[test]
fn the_events_alone_rebuild_the_graph_with_each_endpoints_node() {
    let mut g = recording();
    let mut replay = Replay::default();
    let mut step = |g: &mut GraphCache, change: &dyn Fn(&mut GraphCache)| {
        change(g);
        for event in g.drain_events() {
            replay.apply(event);
        }
        replay.assert_shows(g);
    };
    step(&mut g, &|g| {
        g.add_entity(writer("w1", "p1", "rt/t", STRING));
    });
    step(&mut g, &|g| {
        g.update_participant_entities(msg(
            "p1",
            vec![
                node("/", "a", &["r1"], &["w1"]),
                node("/", "server", &["sq"], &["sp"]),
            ],
        ));
    });
    step(&mut g, &|g| {
        g.add_entity(reader("r1", "p1", "rt/t", STRING));
        g.add_entity(reader("sq", "p1", ADD_RQ, ADD_REQ));
        g.add_entity(writer("sp", "p1", ADD_RR, ADD_RES));
        g.add_entity(writer("info", "p1", "ros_discovery_info", INFO));
    });
    step(&mut g, &|g| {
        let mut moved = writer("w1", "p1", "rt/u", STRING);
        moved.qos.depth = 7;
        g.add_entity(moved);
    });
    step(&mut g, &|g| {
        g.update_participant_entities(msg(
            "p1",
            vec![
                node("/", "b", &["r1"], &["w1"]),
                node("/", "server", &["sq"], &[]),
            ],
        ));
    });
    step(&mut g, &|g| {
        g.add_entity(writer("w2", "p2", "rt/t", STRING));
        g.update_participant_entities(msg("p2", vec![node("/ns", "b", &[], &["w2"])]));
    });
    step(&mut g, &|g| {
        g.remove_entity(gid("sq"));
    });
    step(&mut g, &|g| {
        g.remove_participant(gid("p1"));
    });
    step(&mut g, &|g| {
        g.remove_participant(gid("p2"));
    });
    assert!(replay.nodes.is_empty() && replay.endpoints.is_empty());
}
