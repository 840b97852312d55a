//! The cache's indexes (by DDS topic, by participant, nodes by name) stay equal to indexes
//! rebuilt from scratch through every kind of mutation, and leave nothing behind.

use horus_ros_rmw::qos::EndpointKind;

use super::fixtures::*;
use crate::{GraphCache, GraphError};

/// Whether the node index holds a node of this name in any namespace.
fn indexed(g: &GraphCache, name: &str) -> bool {
    g.index.nodes.values().any(|names| names.contains_key(name))
}

#[test]
fn sample_graph_indexes_are_consistent() {
    let g = sample_graph();
    g.assert_indexes_consistent();
    assert_eq!(g.index.node_count, 4);
    assert_eq!(g.index.by_participant.len(), 3); // participant1, participant2, bare
    let chatter = &g.index.topics["rt/chatter"];
    assert_eq!(chatter.writers.len(), 3);
    assert_eq!(chatter.readers.len(), 1);
}

#[test]
fn entity_removal_drops_empty_topics_and_participants() {
    let mut g = sample_graph();
    let gids: Vec<_> = g.endpoints.keys().copied().collect();
    for gid in gids {
        assert!(g.remove_entity(gid));
        g.assert_indexes_consistent();
    }
    assert!(g.index.topics.is_empty());
    assert!(g.index.by_participant.is_empty());
    // Nodes stay: they come from ros_discovery_info, not from endpoints.
    assert_eq!(g.index.node_count, 4);
    assert_eq!(g.count_publishers("/chatter"), 0);
    assert!(g.topic_names_and_types(true).is_empty());
    assert_eq!(
        g.publisher_names_and_types_by_node("talker", "/"),
        Ok(Default::default())
    );
}

#[test]
fn removing_one_of_two_types_keeps_the_other() {
    let mut g = GraphCache::new();
    g.add_entity(writer("w1", "p", "rt/t", STRING));
    g.add_entity(reader("r1", "p", "rt/t", "Plain"));
    g.remove_entity(gid("r1"));
    g.assert_indexes_consistent();
    let types = &g.index.topics["rt/t"].types;
    assert_eq!(types.keys().collect::<Vec<_>>(), vec![STRING]);
    assert_eq!(types[STRING].endpoints, 1);
    assert_eq!(
        g.topic_names_and_types(false)["/t"]
            .iter()
            .collect::<Vec<_>>(),
        vec!["std_msgs/msg/String"]
    );
}

#[test]
fn participant_removal_clears_its_endpoints_and_nodes() {
    let mut g = sample_graph();
    assert!(g.remove_participant(gid("participant1")));
    g.assert_indexes_consistent();
    assert!(!g
        .index
        .by_participant
        .contains_key(&gid("participant1").prefix()));
    assert!(!g.index.topics.contains_key("rt/_hidden/debug"));
    assert!(!g.index.topics.contains_key("ros_discovery_info"));
    assert!(!indexed(&g, "talker"));
    assert!(!indexed(&g, "server"));
    assert_eq!(g.index.node_count, 2);
    // Shared topics keep the other participants' endpoints.
    assert_eq!(g.index.topics["rt/chatter"].writers.len(), 1); // bare1
    assert_eq!(g.index.topics[ADD_RR].readers.len(), 1); // client_rep
    assert!(g.index.topics[ADD_RR].writers.is_empty());

    // A participant never seen in SPDP: its endpoints still go.
    assert!(g.remove_participant(gid("bare_participant")));
    g.assert_indexes_consistent();
    assert!(g.index.topics["rt/chatter"].writers.is_empty());
    assert_eq!(g.count_publishers("/chatter"), 0);

    assert!(g.remove_participant(gid("participant2")));
    g.assert_indexes_consistent();
    assert!(g.index.topics.is_empty());
    assert!(g.index.by_participant.is_empty());
    assert!(g.index.nodes.is_empty());
    assert_eq!(g.node_count(), 0);
}

#[test]
fn participant_entities_updates_reindex_nodes() {
    let mut g = sample_graph();
    // Node renamed, another moved to a new namespace, a third added.
    g.update_participant_entities(msg(
        "participant1",
        vec![
            node("/", "speaker", &[], &["talker_pub", "talker_hid"]),
            node("/moved", "server", &["server_req"], &["server_rep"]),
            node("/", "extra", &[], &["unlisted1"]),
        ],
    ));
    g.assert_indexes_consistent();
    assert_eq!(g.node_count(), 5);
    assert!(matches!(
        g.publisher_names_and_types_by_node("talker", "/"),
        Err(GraphError::NodeNotFound { .. })
    ));
    assert!(g.publisher_names_and_types_by_node("speaker", "/").is_ok());
    assert!(g.service_names_and_types_by_node("server", "/").is_err());
    assert_eq!(
        g.service_names_and_types_by_node("server", "/moved")
            .map(|s| s.len()),
        Ok(1)
    );
    assert_eq!(
        g.publisher_names_and_types_by_node("extra", "/")
            .map(|s| s.len()),
        Ok(1)
    );
    // Then emptied.
    g.update_participant_entities(msg("participant1", vec![]));
    g.assert_indexes_consistent();
    assert_eq!(g.node_count(), 2);
    for name in ["speaker", "server", "extra"] {
        assert!(!indexed(&g, name));
    }
}

#[test]
fn duplicate_nodes_resolve_to_the_first_in_participant_order() {
    let mut g = GraphCache::new();
    g.add_entity(writer("wa", "pa", "rt/a", STRING));
    g.add_entity(writer("wb", "pb", "rt/b", STRING));
    // Listed by pb first: participant order (GUID prefix), not arrival, decides.
    g.update_participant_entities(msg("pb", vec![node("/", "dup", &[], &["wb"])]));
    g.update_participant_entities(msg("pa", vec![node("/", "dup", &[], &["wa"])]));
    g.assert_indexes_consistent();
    let first = g.publisher_names_and_types_by_node("dup", "/");
    assert_eq!(
        first.map(|n| n.into_keys().collect::<Vec<_>>()),
        Ok(vec!["/a".to_owned()])
    );
    // pa's node leaves: pb's is found.
    g.update_participant_entities(msg("pa", vec![]));
    g.assert_indexes_consistent();
    let next = g.publisher_names_and_types_by_node("dup", "/");
    assert_eq!(
        next.map(|n| n.into_keys().collect::<Vec<_>>()),
        Ok(vec!["/b".to_owned()])
    );
    // Two of the same name in one participant: the first index wins, then the second.
    g.update_participant_entities(msg(
        "pa",
        vec![node("/", "dup", &[], &["wa"]), node("/", "dup", &[], &[])],
    ));
    g.assert_indexes_consistent();
    assert_eq!(g.index.nodes["/"]["dup"].len(), 3);
    g.remove_participant(gid("pa"));
    g.remove_participant(gid("pb"));
    g.assert_indexes_consistent();
    assert!(g.index.nodes.is_empty());
}

#[test]
fn replacing_an_entity_moves_it_in_the_indexes() {
    let mut g = GraphCache::new();
    let e = writer("w", "p", "rt/t", STRING);
    g.add_entity(e.clone());
    // Same GID, new topic, type, kind and participant.
    let mut moved = e;
    moved.dds_topic_name = "rt/u".to_owned();
    moved.dds_type_name = "Plain".to_owned();
    moved.kind = EndpointKind::Reader;
    moved.participant_gid = gid("q");
    g.add_entity(moved);
    g.assert_indexes_consistent();
    assert!(!g.index.topics.contains_key("rt/t"));
    assert!(!g.index.by_participant.contains_key(&gid("p").prefix()));
    assert_eq!(g.count_subscribers("/u"), 1);
    assert_eq!(g.count_publishers("/u"), 0);
    assert!(!g.remove_participant(gid("p")));
    assert_eq!(g.count_subscribers("/u"), 1);
    assert!(g.remove_participant(gid("q")));
    g.assert_indexes_consistent();
    assert!(g.index.topics.is_empty());
}

/// A deterministic pseudo-random sequence of every mutator; the indexes are checked after
/// each step.
#[test]
fn random_mutations_keep_indexes_consistent() {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = move |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    };
    let topics = ["rt/a", "rt/_h/b", ADD_RQ, ADD_RR, "ros_discovery_info"];
    let types = [STRING, ADD_REQ, ADD_RES, "Plain"];
    let mut g = GraphCache::new();
    for step in 0..3000 {
        let p = format!("p{}", next(5));
        let e = format!("e{}", next(40));
        match next(6) {
            0 | 1 => {
                let topic = topics[next(5) as usize];
                let ty = types[next(4) as usize];
                if next(2) == 0 {
                    g.add_entity(reader(&e, &p, topic, ty));
                } else {
                    g.add_entity(writer(&e, &p, topic, ty));
                }
            }
            2 => {
                g.remove_entity(gid(&e));
            }
            3 => {
                let nodes = (0..next(4))
                    .map(|_| {
                        let (r, w) = (format!("e{}", next(40)), format!("e{}", next(40)));
                        node(
                            &format!("/ns{}", next(2)),
                            &format!("n{}", next(3)),
                            &[&r],
                            &[&w],
                        )
                    })
                    .collect();
                g.update_participant_entities(msg(&p, nodes));
            }
            4 => {
                g.add_participant(gid(&p), None);
            }
            _ => {
                if next(4) == 0 {
                    g.remove_participant(gid(&p));
                }
            }
        }
        g.assert_indexes_consistent();
        if step % 100 == 0 {
            // The queries agree with the raw maps.
            let writers_on_a = g
                .endpoints
                .values()
                .filter(|e| e.dds_topic_name == "rt/a" && e.kind == EndpointKind::Writer)
                .count();
            assert_eq!(g.count_publishers("/a"), writers_on_a);
            let nodes: usize = g.participants.values().map(|p| p.nodes.len()).sum();
            assert_eq!(g.node_count(), nodes);
        }
    }
}
