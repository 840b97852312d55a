//! Our discovery feed against a real ROS 2 Jazzy node (rclpy 7.1.6 on the run's RMW:
//! rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5, or rmw_cyclonedds_cpp 2.2.2 / Cyclone DDS 0.10) with
//! a `std_srvs/srv/SetBool` server and client: we see its participant (the vendor of its RMW's
//! DDS), its four service endpoints with their DDS topic and type names, the type hashes of their
//! USER_DATA (the wheels' own) and their QoS, its `ros_discovery_info` message listing those GIDs
//! under its node, and the endpoints and participant leaving when it leaves. The GIDs are the
//! ones rclpy's own graph API gives for its endpoints.
//!
//! DDS only (not in the Zenoh run): what it checks is DDS discovery itself — SPDP participants
//! with a DDS vendor id, SEDP endpoints on `rq/`/`rr/` topics with USER_DATA, and
//! `ros_discovery_info` — none of which rmw_zenoh has. On Zenoh the feed is synthesized from
//! liveliness tokens (`rmw-zenoh/src/feed.rs`, with its unit tests), and what it yields is
//! compared with rclpy's graph API on rmw_zenoh_cpp by `jazzy_graph.rs`.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use horus_ros_msgs::std_srvs::srv::{SetBoolRequest, SetBoolResponse};
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::{DurabilityPolicy, EndpointKind, HistoryPolicy, ReliabilityPolicy};
use horus_ros_rmw::{Backend, Context, DiscoveredEndpoint, DiscoveryEvent, Gid, VendorId};
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::{gid_in, service_topics, wheels, RclpyPeer};
use serde_json::{json, Value};

const DOMAIN: u32 = 113;
const SERVICE: &str = "/rclpy_ns/set";
const REQUEST_TYPE: &str = "std_srvs::srv::dds_::SetBool_Request_";
const RESPONSE_TYPE: &str = "std_srvs::srv::dds_::SetBool_Response_";
/// Bound on the whole exchange, for a loaded machine (the test ends as soon as all is seen).
const LIMIT: Duration = Duration::from_secs(60);

/// The GID of the one endpoint of node `rclpy_node` that the peer's view lists on `topic`.
fn own_gid(view: &Value, topic: &str, side: &str) -> Option<Gid> {
    view["endpoints"][topic][side]
        .as_array()?
        .iter()
        .filter_map(Value::as_str)
        .find(|t| t.starts_with("Node name: rclpy_node\n"))
        .and_then(gid_in)
}

/// Checks one of the peer's service endpoints as our feed reports it.
fn check_endpoint(
    e: &DiscoveredEndpoint,
    backend: Backend,
    participant: Gid,
    kind: EndpointKind,
    topic: &str,
) {
    let what = format!("{kind:?} {}", e.gid);
    let (type_name, ros_type) = if topic.starts_with("rq/") {
        (REQUEST_TYPE, SetBoolRequest::TYPE_NAME)
    } else {
        (RESPONSE_TYPE, SetBoolResponse::TYPE_NAME)
    };
    let hash = wheels::wheel_hash(ros_type).expect("the wheels' hash");
    assert_eq!(e.kind, kind, "{what}");
    assert_eq!(e.participant_gid, participant, "{what}");
    assert_eq!(e.dds_topic_name, topic, "{what}");
    assert_eq!(e.dds_type_name, type_name, "{what}");
    // rmw_dds_common encode_type_hash_for_user_data_qos: no NUL, unlike the participant's.
    // rmw_cyclonedds puts its client's or server's id first (`create_readwrite_qos`), the same
    // on both endpoints of one client or server.
    let user_data = String::from_utf8_lossy(&e.user_data).into_owned();
    let type_hash = format!("typehash={hash};");
    match Rmw::of_peers() {
        Rmw::CycloneDds => {
            // A server reads requests and writes replies.
            let server = (kind == EndpointKind::Reader) == topic.starts_with("rq/");
            let key = if server { "serviceid=" } else { "clientid=" };
            let id = user_data
                .strip_suffix(&type_hash)
                .and_then(|id| id.strip_prefix(key))
                .and_then(|id| id.strip_suffix(';'));
            assert!(id.is_some_and(|id| !id.is_empty()), "{what}: {user_data}");
        }
        _ => assert_eq!(user_data, type_hash, "{what}"),
    }
    assert_eq!(e.type_hash.to_string(), hash, "{what}");
    // rmw_qos_profile_services_default as the peer's RMW maps it.
    assert_eq!(e.qos.reliability, ReliabilityPolicy::Reliable, "{what}");
    assert_eq!(e.qos.durability, DurabilityPolicy::Volatile, "{what}");
    // Its history as our backend observes it, as the RMW it stands in for would: Cyclone DDS
    // announces HISTORY (KEEP_LAST 10), Fast DDS does not; Cyclone DDS reports what it holds, the
    // announced policy or the DDS default it fills in (KEEP_LAST 1), as rmw_cyclonedds does;
    // rustdds 0.15 keeps no history of a discovered endpoint (`sedp_messages.rs` `qos()`), and
    // rmw_fastrtps reports none (UNKNOWN).
    let history = match (backend, Rmw::of_peers()) {
        (Backend::Cyclone, Rmw::CycloneDds) => (HistoryPolicy::KeepLast, 10),
        (Backend::Cyclone, _) => (HistoryPolicy::KeepLast, 1),
        _ => (HistoryPolicy::Unknown, 0),
    };
    assert_eq!((e.qos.history, e.qos.depth), history, "{what}");
}

#[test]
fn feed_reports_an_rclpy_node() {
    // Our types hash as the wheels' (the peer's endpoints announce theirs).
    assert_eq!(
        Ok(SetBoolRequest::type_hash().to_string()),
        wheels::wheel_hash(SetBoolRequest::TYPE_NAME)
    );
    assert_eq!(SetBoolRequest::dds_type_name(), REQUEST_TYPE);
    assert_eq!(SetBoolResponse::dds_type_name(), RESPONSE_TYPE);

    assert!(
        Rmw::of_peers().is_dds(),
        "DDS discovery only: the peers' RMW is {} (see the module documentation)",
        Rmw::of_peers().name()
    );
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let backend = context.backend().expect("a built-in backend");
    let mut feed = context.discovery_feed().expect("feed");
    let started = Instant::now();
    let mut peer = RclpyPeer::start(&json!({
        "domain": DOMAIN, "namespace": "/rclpy_ns", "name": "rclpy_node",
        "servers": [{"service": SERVICE, "type": "std_srvs/srv/SetBool"}],
        "clients": [{"service": SERVICE, "type": "std_srvs/srv/SetBool"}],
        "graph": true,
    }))
    .expect("start the rclpy peer");
    // Its endpoints' GIDs, as rclpy's graph API gives them.
    let (request, reply) = service_topics(SERVICE);
    let endpoints: Vec<(Gid, EndpointKind, String)> = peer
        .wait_for(
            LIMIT,
            "rclpy's view of its own service endpoints",
            |lines| {
                let view = lines.iter().rev().find_map(|l| l.get("graph"))?;
                Some(vec![
                    (
                        own_gid(view, &request, "subscriptions")?,
                        EndpointKind::Reader,
                        request.clone(),
                    ),
                    (
                        own_gid(view, &reply, "publishers")?,
                        EndpointKind::Writer,
                        reply.clone(),
                    ),
                    (
                        own_gid(view, &reply, "subscriptions")?,
                        EndpointKind::Reader,
                        reply.clone(),
                    ),
                    (
                        own_gid(view, &request, "publishers")?,
                        EndpointKind::Writer,
                        request.clone(),
                    ),
                ])
            },
        )
        .unwrap_or_else(|e| panic!("{e}"));
    // The participant's GID: its endpoints' GUID prefix, entity id 0x000001c1.
    let mut participant = endpoints[0].0;
    participant.data[12..].copy_from_slice(&[0, 0, 1, 0xc1]);
    let node_readers = [endpoints[0].0, endpoints[2].0];
    let node_writers = [endpoints[1].0, endpoints[3].0];

    let mut saw_participant = false;
    let mut discovered = BTreeSet::new();
    let mut saw_info = false;
    let mut lost = BTreeSet::new();
    let mut participant_lost = false;
    // Every event the feed gave, for the failure message.
    let mut log = Vec::new();
    let deadline = Instant::now() + LIMIT;
    let mut asked_to_leave = false;
    while !(saw_participant
        && discovered.len() == endpoints.len()
        && saw_info
        && lost.len() == endpoints.len()
        && participant_lost)
    {
        assert!(
            Instant::now() < deadline,
            "not everything seen within {LIMIT:?}: participant={saw_participant} \
             endpoints={discovered:?} ros_discovery_info={saw_info} lost={lost:?} \
             participant_lost={participant_lost}\nevents:\n{}\n{}",
            log.join("\n"),
            peer.output()
        );
        // Everything about the peer is known: it leaves, as rclpy does.
        if !asked_to_leave && saw_participant && discovered.len() == endpoints.len() && saw_info {
            peer.leave();
            asked_to_leave = true;
        }
        let Some(event) = feed.next_timeout(deadline.saturating_duration_since(Instant::now()))
        else {
            continue;
        };
        log.push(format!("{:?} {event:?}", started.elapsed()));
        match event {
            DiscoveryEvent::ParticipantDiscovered(p) if p.gid == participant => {
                let vendor = Rmw::of_peers().dds_vendor_id().map(VendorId);
                assert_eq!(Some(p.vendor_id), vendor, "{p:?}");
                saw_participant = true;
            }
            DiscoveryEvent::EndpointDiscovered(e) => {
                if let Some((_, kind, topic)) = endpoints.iter().find(|(g, ..)| *g == e.gid) {
                    check_endpoint(&e, backend, participant, *kind, topic);
                    assert!(
                        lost.is_empty(),
                        "{} discovered after endpoints were lost",
                        e.gid
                    );
                    discovered.insert(e.gid);
                }
            }
            DiscoveryEvent::ParticipantEntities(info) if info.gid == participant => {
                // Republished as the node and its endpoints appear, and with no node when it
                // leaves (not awaited: rustdds may drop a sample not yet taken from a writer it
                // forgets): wait for the one that lists all four under the node.
                let Some(node) = info.node_entities_info_seq.first() else {
                    continue;
                };
                assert_eq!(info.node_entities_info_seq.len(), 1, "{info:?}");
                assert_eq!(
                    (node.node_namespace.as_str(), node.node_name.as_str()),
                    ("/rclpy_ns", "rclpy_node")
                );
                if node_readers.iter().all(|g| node.reader_gid_seq.contains(g))
                    && node_writers.iter().all(|g| node.writer_gid_seq.contains(g))
                {
                    saw_info = true;
                }
            }
            // The peer leaves: removes its node, then deletes its endpoints and participant.
            DiscoveryEvent::EndpointLost { gid, kind } => {
                if let Some((_, expected, _)) = endpoints.iter().find(|(g, ..)| *g == gid) {
                    assert_eq!(kind, *expected, "{gid}");
                    lost.insert(gid);
                }
            }
            DiscoveryEvent::ParticipantLost { gid } if gid == participant => {
                assert!(saw_participant, "participant lost before it was discovered");
                participant_lost = true;
            }
            _ => {}
        }
    }
    assert_eq!(
        peer.finish(Duration::from_secs(10)),
        Ok(Some(0)),
        "{}",
        peer.output()
    );
    eprintln!(
        "everything seen {:?} after the peer started",
        started.elapsed()
    );
}
