//! Name queries, counts and topic endpoint info.

use std::collections::BTreeSet;

use super::fixtures::*;
use crate::{
    GraphCache, GraphError, NamesAndTypes, NodeInfo, TopicEndpointType, CREATED_BY_BARE_DDS_APP,
    NODE_NAMESPACE_UNKNOWN, NODE_NAME_UNKNOWN,
};

fn nt(items: &[(&str, &[&str])]) -> NamesAndTypes {
    items
        .iter()
        .map(|(n, ts)| {
            (
                (*n).to_owned(),
                ts.iter().map(|t| (*t).to_owned()).collect::<BTreeSet<_>>(),
            )
        })
        .collect()
}

fn node_info(namespace: &str, name: &str, enclave: Option<&str>) -> NodeInfo {
    NodeInfo {
        namespace: namespace.to_owned(),
        name: name.to_owned(),
        enclave: enclave.map(str::to_owned),
    }
}

#[test]
fn empty_cache_answers_empty() {
    let g = GraphCache::new();
    assert!(g.node_names().is_empty());
    assert_eq!(g.node_count(), 0);
    assert!(g.topic_names_and_types(true).is_empty());
    assert!(g.service_names_and_types(true).is_empty());
    assert_eq!(g.count_publishers("/chatter"), 0);
    assert_eq!(g.count_clients("/s"), 0);
    assert!(g.publishers_info_by_topic("/chatter", false).is_empty());
    assert_eq!(g.servers_info_by_service("/s", false), Ok(vec![]));
    assert_eq!(
        g.publisher_names_and_types_by_node("n", "/"),
        Err(GraphError::NodeNotFound {
            name: "n".to_owned(),
            namespace: "/".to_owned()
        })
    );
}

#[test]
fn node_names_with_enclaves() {
    let g = sample_graph();
    assert_eq!(
        g.node_names(),
        vec![
            node_info("/", "server", Some("/")),
            node_info("/", "talker", Some("/")),
            node_info("/ns", "client", None),
            node_info("/ns", "listener", None),
        ]
    );
    assert_eq!(g.node_count(), 4);
}

#[test]
fn topic_names_and_types_demangled_hidden_filtered() {
    let g = sample_graph();
    assert_eq!(
        g.topic_names_and_types(false),
        nt(&[("/chatter", &["std_msgs/msg/String"])])
    );
    assert_eq!(
        g.topic_names_and_types(true),
        nt(&[
            ("/_hidden/debug", &["std_msgs/msg/String"]),
            ("/chatter", &["std_msgs/msg/String"]),
        ])
    );
}

#[test]
fn topic_with_two_types_and_non_ros_type() {
    let mut g = GraphCache::new();
    g.add_entity(writer("w1", "p", "rt/t", STRING));
    g.add_entity(reader("r1", "p", "rt/t", "Plain"));
    g.add_entity(writer("w2", "p", "plain_dds_topic", STRING));
    assert_eq!(
        g.topic_names_and_types(false),
        nt(&[("/t", &["Plain", "std_msgs/msg/String"])])
    );
}

#[test]
fn service_names_and_types_from_rq_and_rr() {
    let mut g = sample_graph();
    // A reply-only and a request-only service both appear.
    g.add_entity(writer(
        "only_rr",
        "participant1",
        "rr/reply_onlyReply",
        ADD_RES,
    ));
    g.add_entity(reader(
        "only_rq",
        "participant1",
        "rq/request_onlyRequest",
        ADD_REQ,
    ));
    g.add_entity(reader(
        "hid_rq",
        "participant1",
        "rq/node/_privRequest",
        ADD_REQ,
    ));
    let add = &["example_interfaces/srv/AddTwoInts"][..];
    assert_eq!(
        g.service_names_and_types(false),
        nt(&[
            ("/add_two_ints", add),
            ("/reply_only", add),
            ("/request_only", add)
        ])
    );
    assert_eq!(g.service_names_and_types(true).len(), 4);
    assert!(g.service_names_and_types(true).contains_key("/node/_priv"));
}

#[test]
fn names_and_types_by_node() {
    let g = sample_graph();
    let chatter = nt(&[("/chatter", &["std_msgs/msg/String"])]);
    let mut talker_pubs = chatter.clone();
    talker_pubs.extend(nt(&[("/_hidden/debug", &["std_msgs/msg/String"])]));
    assert_eq!(
        g.publisher_names_and_types_by_node("talker", "/"),
        Ok(talker_pubs)
    );
    assert_eq!(
        g.subscription_names_and_types_by_node("talker", "/"),
        Ok(NamesAndTypes::new())
    );
    assert_eq!(
        g.subscription_names_and_types_by_node("listener", "/ns"),
        Ok(chatter)
    );
    let add = nt(&[("/add_two_ints", &["example_interfaces/srv/AddTwoInts"])]);
    assert_eq!(
        g.service_names_and_types_by_node("server", "/"),
        Ok(add.clone())
    );
    assert_eq!(
        g.client_names_and_types_by_node("server", "/"),
        Ok(NamesAndTypes::new())
    );
    assert_eq!(g.client_names_and_types_by_node("client", "/ns"), Ok(add));
    assert_eq!(
        g.service_names_and_types_by_node("client", "/ns"),
        Ok(NamesAndTypes::new())
    );
    // Service endpoints are not topics.
    assert_eq!(
        g.publisher_names_and_types_by_node("server", "/"),
        Ok(NamesAndTypes::new())
    );
    assert!(g
        .publisher_names_and_types_by_node("listener", "/")
        .is_err());
}

#[test]
fn counts() {
    let g = sample_graph();
    // talker, unlisted (unknown node) and bare DDS writers all count.
    assert_eq!(g.count_publishers("/chatter"), 3);
    assert_eq!(g.count_subscribers("/chatter"), 1);
    assert_eq!(g.count_services("/add_two_ints"), 1);
    assert_eq!(g.count_clients("/add_two_ints"), 1);
    assert_eq!(g.count_publishers("/add_two_ints"), 0);
}

#[test]
fn publishers_info_names_unknown_and_bare_endpoints() {
    let g = sample_graph();
    let infos = g.publishers_info_by_topic("/chatter", false);
    let got: Vec<(&str, &str, crate::Gid)> = infos
        .iter()
        .map(|i| {
            (
                i.node_name.as_str(),
                i.node_namespace.as_str(),
                i.endpoint_gid,
            )
        })
        .collect();
    // GID order: "bare1" < "talker_pub" < "unlisted1".
    assert_eq!(
        got,
        vec![
            (
                CREATED_BY_BARE_DDS_APP,
                CREATED_BY_BARE_DDS_APP,
                gid("bare1")
            ),
            ("talker", "/", gid("talker_pub")),
            (NODE_NAME_UNKNOWN, NODE_NAMESPACE_UNKNOWN, gid("unlisted1")),
        ]
    );
    for i in &infos {
        assert_eq!(i.topic_type, "std_msgs/msg/String");
        assert_eq!(i.endpoint_type, TopicEndpointType::Publisher);
        assert_eq!(i.qos_profile, remote_qos());
    }
    let subs = g.subscriptions_info_by_topic("/chatter", false);
    assert_eq!(subs.len(), 1);
    assert_eq!(subs[0].node_name, "listener");
    assert_eq!(subs[0].node_namespace, "/ns");
    assert_eq!(subs[0].endpoint_type, TopicEndpointType::Subscription);
    assert!(g.publishers_info_by_topic("/nothing", false).is_empty());
}

#[test]
fn topic_info_no_mangle_uses_raw_name() {
    let g = sample_graph();
    assert_eq!(g.publishers_info_by_topic("rt/chatter", true).len(), 3);
    assert!(g.publishers_info_by_topic("/chatter", true).is_empty());
    let raw = g.publishers_info_by_topic("ros_discovery_info", true);
    assert_eq!(raw.len(), 1);
    // The DDS type name as is (rmw's `_identity_demangle` with no_mangle).
    assert_eq!(
        raw[0].topic_type,
        "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"
    );
    assert_eq!(
        g.publishers_info_by_topic("rt/chatter", true)[0].topic_type,
        "std_msgs::msg::dds_::String_"
    );
    assert_eq!(raw[0].node_name, NODE_NAME_UNKNOWN);
}

#[test]
fn reader_gid_listed_as_writer_is_unknown_node() {
    // rmw_dds_common looks a reader up in reader_gid_seq only.
    let mut g = GraphCache::new();
    g.add_entity(reader("r", "p", "rt/t", STRING));
    g.update_participant_entities(msg("p", vec![node("/", "n", &[], &["r"])]));
    assert_eq!(
        g.subscriptions_info_by_topic("/t", false)[0].node_name,
        NODE_NAME_UNKNOWN
    );
}
