//! Helpers building GIDs, endpoints and `ros_discovery_info` messages.

use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::{EndpointKind, HistoryPolicy, LivelinessPolicy, Qos, QosDuration};

use crate::{EndpointEntry, GraphCache};

/// A GID holding the bytes of `s` (at most 16), zero padded.
pub fn gid(s: &str) -> Gid {
    let mut data = [0u8; 16];
    for (d, b) in data.iter_mut().zip(s.bytes()) {
        *d = b;
    }
    Gid::from_bytes(data)
}

/// The QoS a remote endpoint shows: history UNKNOWN, infinite durations.
pub fn remote_qos() -> Qos {
    let mut q = Qos::services_default();
    q.history = HistoryPolicy::Unknown;
    q.depth = 0;
    q.lifespan = QosDuration::Infinite;
    q.deadline = QosDuration::Infinite;
    q.liveliness = LivelinessPolicy::Automatic;
    q.liveliness_lease_duration = QosDuration::Infinite;
    q
}

/// An endpoint with a remote QoS and no type hash.
pub fn entry(
    gid_s: &str,
    participant: &str,
    topic: &str,
    ty: &str,
    kind: EndpointKind,
) -> EndpointEntry {
    EndpointEntry {
        gid: gid(gid_s),
        participant_gid: gid(participant),
        dds_topic_name: topic.to_owned(),
        dds_type_name: ty.to_owned(),
        qos: remote_qos(),
        type_hash: TypeHash::ZERO,
        kind,
    }
}

/// A reader endpoint.
pub fn reader(gid_s: &str, participant: &str, topic: &str, ty: &str) -> EndpointEntry {
    entry(gid_s, participant, topic, ty, EndpointKind::Reader)
}

/// A writer endpoint.
pub fn writer(gid_s: &str, participant: &str, topic: &str, ty: &str) -> EndpointEntry {
    entry(gid_s, participant, topic, ty, EndpointKind::Writer)
}

/// A node listing the given reader and writer GIDs.
pub fn node(namespace: &str, name: &str, readers: &[&str], writers: &[&str]) -> NodeEntitiesInfo {
    NodeEntitiesInfo {
        node_namespace: namespace.to_owned(),
        node_name: name.to_owned(),
        reader_gid_seq: readers.iter().map(|s| gid(s)).collect(),
        writer_gid_seq: writers.iter().map(|s| gid(s)).collect(),
    }
}

/// A `ros_discovery_info` message.
pub fn msg(participant: &str, nodes: Vec<NodeEntitiesInfo>) -> ParticipantEntitiesInfo {
    ParticipantEntitiesInfo {
        gid: gid(participant),
        node_entities_info_seq: nodes,
    }
}

pub const STRING: &str = "std_msgs::msg::dds_::String_";
pub const ADD_REQ: &str = "example_interfaces::srv::dds_::AddTwoInts_Request_";
pub const ADD_RES: &str = "example_interfaces::srv::dds_::AddTwoInts_Response_";
pub const ADD_RQ: &str = "rq/add_two_intsRequest";
pub const ADD_RR: &str = "rr/add_two_intsReply";

/// A graph of two participants:
/// - `participant1` (enclave `/`): `/talker` publishing `/chatter` and `/_hidden/debug`;
///   `/server` serving `/add_two_ints`; plus `unlisted1`, a writer on `/chatter` no node lists.
/// - `participant2`: `/ns/listener` subscribing to `/chatter`; `/ns/client` calling
///   `/add_two_ints`.
/// - `bare1`: a writer on `/chatter` of a participant never seen.
pub fn sample_graph() -> GraphCache {
    let mut g = GraphCache::new();
    g.add_participant(gid("participant1"), Some("/".to_owned()));
    g.add_participant(gid("participant2"), None);
    for e in [
        writer("talker_pub", "participant1", "rt/chatter", STRING),
        writer("talker_hid", "participant1", "rt/_hidden/debug", STRING),
        reader("server_req", "participant1", ADD_RQ, ADD_REQ),
        writer("server_rep", "participant1", ADD_RR, ADD_RES),
        writer("unlisted1", "participant1", "rt/chatter", STRING),
        reader("listener_sub", "participant2", "rt/chatter", STRING),
        reader("client_rep", "participant2", ADD_RR, ADD_RES),
        writer("client_req", "participant2", ADD_RQ, ADD_REQ),
        writer("bare1", "bare_participant", "rt/chatter", STRING),
        writer(
            "discovery",
            "participant1",
            "ros_discovery_info",
            "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_",
        ),
    ] {
        g.add_entity(e);
    }
    g.update_participant_entities(msg(
        "participant1",
        vec![
            node("/", "talker", &[], &["talker_pub", "talker_hid"]),
            node("/", "server", &["server_req"], &["server_rep"]),
        ],
    ));
    g.update_participant_entities(msg(
        "participant2",
        vec![
            node("/ns", "listener", &["listener_sub"], &[]),
            node("/ns", "client", &["client_rep"], &["client_req"]),
        ],
    ));
    g
}
pub const INFO: &str = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";
