//! A cache rebuilt from its snapshot (through JSON, as the CLI's daemon sends it) holds the same
//! content, indexes and answers.

use horus_ros_msgs::TypeHash;

use super::fixtures::*;
use crate::{participant_gid_from_prefix, GraphCache, GraphSnapshot};

/// Every query the CLI makes, on every name of the graph, as one comparable text.
fn answers(g: &GraphCache) -> String {
    let mut out = format!("{:?}\n{:?}\n", g.node_names(), g.unsettled());
    for hidden in [false, true] {
        out += &format!(
            "{:?}\n{:?}\n",
            g.topic_names_and_types(hidden),
            g.service_names_and_types(hidden)
        );
    }
    for (topic, _) in g.topic_names_and_types(true) {
        out += &format!(
            "{topic} {} {} {:?} {:?}\n",
            g.count_publishers(&topic),
            g.count_subscribers(&topic),
            g.publishers_info_by_topic(&topic, false),
            g.subscriptions_info_by_topic(&topic, false),
        );
    }
    for (service, _) in g.service_names_and_types(true) {
        out += &format!(
            "{service} {} {} {:?} {:?}\n",
            g.count_services(&service),
            g.count_clients(&service),
            g.servers_info_by_service(&service, false),
            g.clients_info_by_service(&service, false),
        );
    }
    for n in g.node_names() {
        out += &format!(
            "{n:?} {:?} {:?} {:?} {:?}\n",
            g.publisher_names_and_types_by_node(&n.name, &n.namespace),
            g.subscription_names_and_types_by_node(&n.name, &n.namespace),
            g.service_names_and_types_by_node(&n.name, &n.namespace),
            g.client_names_and_types_by_node(&n.name, &n.namespace),
        );
    }
    out
}

/// The sample graph plus what a snapshot must keep apart: a participant that has not announced
/// its nodes, one that announced none, endpoint type hashes, set and unset service type hashes.
fn rich_graph() -> GraphCache {
    let mut g = sample_graph();
    g.add_participant(gid("silent"), Some("/secure".to_owned()));
    g.add_participant(gid("empty"), None);
    g.update_participant_entities(msg("empty", vec![]));
    let mut hashed = writer("hashed_pub", "participant2", "rt/stamped", STRING);
    hashed.type_hash = TypeHash::rihs01([7; 32]);
    g.add_entity(hashed);
    g.set_service_type_hash(
        "example_interfaces/srv/AddTwoInts",
        TypeHash::rihs01([9; 32]),
    );
    g.set_service_type_hash("pkg/srv/Unset", TypeHash::ZERO);
    g
}

#[test]
fn rebuilt_cache_answers_as_the_original() {
    let g = rich_graph();
    let snapshot = g.snapshot();
    let json = serde_json::to_string(&snapshot).expect("serialize");
    let back: GraphSnapshot = serde_json::from_str(&json).expect("deserialize");
    assert_eq!(back, snapshot);
    let rebuilt = GraphCache::from_snapshot(back);
    rebuilt.assert_indexes_consistent();
    assert_eq!(rebuilt.index, g.index);
    assert_eq!(rebuilt.snapshot(), snapshot);
    assert_eq!(answers(&rebuilt), answers(&g));
    // What the snapshot keeps: the participant that has not announced its nodes stays so.
    let silent = participant_gid_from_prefix(gid("silent").prefix());
    assert!(rebuilt.unsettled().unannounced.contains(&silent));
    assert!(!rebuilt.is_consistent());
}

#[test]
fn unset_type_hashes_are_null() {
    let g = rich_graph();
    let json = serde_json::to_value(g.snapshot()).expect("serialize");
    let endpoints = json["endpoints"].as_array().expect("endpoints");
    let hash_of = |gid_s: &str| {
        let want = serde_json::to_value(gid(gid_s)).expect("gid");
        endpoints
            .iter()
            .find(|e| e["gid"] == want)
            .map(|e| e["type_hash"].clone())
            .expect("endpoint")
    };
    assert_eq!(hash_of("talker_pub"), serde_json::Value::Null);
    assert_eq!(
        hash_of("hashed_pub"),
        serde_json::Value::from(TypeHash::rihs01([7; 32]).to_string())
    );
    assert_eq!(
        json["service_type_hashes"],
        serde_json::json!({
            "example_interfaces/srv/AddTwoInts": TypeHash::rihs01([9; 32]).to_string()
        })
    );
}

#[test]
fn empty_cache_round_trips() {
    let g = GraphCache::new();
    let rebuilt = GraphCache::from_snapshot(g.snapshot());
    assert_eq!(rebuilt.snapshot(), GraphSnapshot::default());
    assert!(rebuilt.is_consistent());
}
