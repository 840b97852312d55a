//! Our discovery feed against an eProsima Fast DDS 2.9 peer (`peers/fastdds/`) that joins the
//! graph as an rmw_fastrtps_cpp participant would, with a node owning an AddTwoInts service
//! server and client: we see its participant (vendor Fast DDS), its four service endpoints with
//! their DDS topic and type names, the type hashes from their USER_DATA and their QoS, its
//! `ros_discovery_info` message listing those GIDs under its node, and the endpoints leaving when
//! it exits.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use horus_ros_msgs::example_interfaces::srv::{AddTwoIntsRequest, AddTwoIntsResponse};
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::{DurabilityPolicy, EndpointKind, HistoryPolicy, ReliabilityPolicy};
use horus_ros_rmw::{Context, DiscoveredEndpoint, DiscoveryEvent, VendorId};
use interop_tests::fastdds::FastDdsPeer;

const DOMAIN: u32 = 61;
const SERVICE: &str = "/fast_ns/add_two_ints";
// REP-2011 hashes read off a Jazzy build (docs/ros2-jazzy-wire-facts.md); the peer sends these
// literals, independently of our own hashing.
const REQUEST_HASH: &str =
    "RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302";
const RESPONSE_HASH: &str =
    "RIHS01_de5c030d4af33cba2749310b249737b631594703f9300495f48bffb2b44dcc2f";
const REQUEST_TYPE: &str = "example_interfaces::srv::dds_::AddTwoInts_Request_";
const RESPONSE_TYPE: &str = "example_interfaces::srv::dds_::AddTwoInts_Response_";

/// Checks one of the peer's service endpoints as our feed reports it.
fn check_endpoint(
    e: &DiscoveredEndpoint,
    participant: &str,
    kind: EndpointKind,
    topic: &str,
    type_name: &str,
    hash: &str,
) {
    let what = format!("{kind:?} {}", e.gid);
    assert_eq!(e.kind, kind, "{what}");
    assert_eq!(e.participant_gid.to_string(), participant, "{what}");
    assert_eq!(e.dds_topic_name, topic, "{what}");
    assert_eq!(e.dds_type_name, type_name, "{what}");
    // rmw_dds_common encode_type_hash_for_user_data_qos: no NUL, unlike the participant's.
    assert_eq!(
        e.user_data,
        format!("typehash={hash};").into_bytes(),
        "{what}"
    );
    assert_eq!(e.type_hash.to_string(), hash, "{what}");
    // rmw_qos_profile_services_default as rmw_fastrtps maps it; SEDP does not carry history.
    assert_eq!(e.qos.reliability, ReliabilityPolicy::Reliable, "{what}");
    assert_eq!(e.qos.durability, DurabilityPolicy::Volatile, "{what}");
    assert_eq!(e.qos.history, HistoryPolicy::Unknown, "{what}");
}

/// How long the Fast DDS peer would stay: it is asked to leave before that.
const PEER_LINGER: Duration = Duration::from_secs(120);
/// Bound on the whole exchange, for a loaded machine (the test ends as soon as all is seen).
const LIMIT: Duration = Duration::from_secs(40);

#[test]
fn feed_reports_a_fastdds_ros_participant() {
    // Our hashing agrees with the Jazzy values the peer announces.
    assert_eq!(AddTwoIntsRequest::type_hash().to_string(), REQUEST_HASH);
    assert_eq!(AddTwoIntsResponse::type_hash().to_string(), RESPONSE_HASH);
    assert_eq!(AddTwoIntsRequest::dds_type_name(), REQUEST_TYPE);
    assert_eq!(AddTwoIntsResponse::dds_type_name(), RESPONSE_TYPE);

    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("feed");

    let started = Instant::now();
    let mut peer = FastDdsPeer::start(
        DOMAIN,
        "/fast_ns",
        "fast_node",
        SERVICE,
        // Stays until told to leave, once everything about it has been seen.
        PEER_LINGER,
    )
    .expect("build and start the Fast DDS peer");
    let created = peer
        .created(Duration::from_secs(10))
        .expect("the peer says what it created");
    eprintln!("Fast DDS peer created: {}", created.json);

    // What Fast DDS reports for its own endpoints.
    assert_eq!(created.vendor, "010f");
    assert!(created.participant.starts_with("01.0f."), "{created:?}");
    assert!(created.participant.ends_with(".00.00.01.c1"), "{created:?}");
    assert_eq!(created.request_topic, "rq/fast_ns/add_two_intsRequest");
    assert_eq!(created.reply_topic, "rr/fast_ns/add_two_intsReply");
    for endpoint in [
        "request_reader",
        "reply_writer",
        "request_writer",
        "reply_reader",
    ] {
        let qos = &created.json["qos"][endpoint];
        assert_eq!(qos["reliability"], "RELIABLE", "{endpoint}: {qos}");
        assert_eq!(qos["durability"], "VOLATILE", "{endpoint}: {qos}");
        assert_eq!(qos["history"], "KEEP_LAST", "{endpoint}: {qos}");
        assert_eq!(qos["depth"], 10, "{endpoint}: {qos}");
    }

    let participant = created.participant.clone();
    let endpoints = [
        (
            created.server_request_reader.clone(),
            EndpointKind::Reader,
            created.request_topic.as_str(),
            REQUEST_TYPE,
            REQUEST_HASH,
        ),
        (
            created.server_reply_writer.clone(),
            EndpointKind::Writer,
            created.reply_topic.as_str(),
            RESPONSE_TYPE,
            RESPONSE_HASH,
        ),
        (
            created.client_reply_reader.clone(),
            EndpointKind::Reader,
            created.reply_topic.as_str(),
            RESPONSE_TYPE,
            RESPONSE_HASH,
        ),
        (
            created.client_request_writer.clone(),
            EndpointKind::Writer,
            created.request_topic.as_str(),
            REQUEST_TYPE,
            REQUEST_HASH,
        ),
    ];
    // rmw_fastrtps lists readers and writers in creation order: server first, then client.
    let node_readers = vec![
        created.server_request_reader.clone(),
        created.client_reply_reader.clone(),
    ];
    let node_writers = vec![
        created.server_reply_writer.clone(),
        created.client_request_writer.clone(),
    ];

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
            "not everything seen within {:?}: participant={saw_participant} \
             endpoints={discovered:?} ros_discovery_info={saw_info} lost={lost:?} \
             participant_lost={participant_lost}\nevents:\n{}",
            LIMIT,
            log.join("\n")
        );
        // Everything about the peer is known: it leaves, as rmw does.
        if !asked_to_leave && saw_participant && discovered.len() == endpoints.len() && saw_info {
            peer.leave().expect("ask the peer to leave");
            asked_to_leave = true;
        }
        let Some(event) = feed.next_timeout(deadline.saturating_duration_since(Instant::now()))
        else {
            continue;
        };
        log.push(format!("{:?} {event:?}", started.elapsed()));
        match event {
            DiscoveryEvent::ParticipantDiscovered(p) if p.gid.to_string() == participant => {
                assert_eq!(p.vendor_id, VendorId::FAST_DDS);
                saw_participant = true;
            }
            DiscoveryEvent::EndpointDiscovered(e) => {
                let gid = e.gid.to_string();
                if let Some((_, kind, topic, type_name, hash)) =
                    endpoints.iter().find(|(g, ..)| *g == gid)
                {
                    check_endpoint(&e, &participant, *kind, topic, type_name, hash);
                    assert!(
                        lost.is_empty(),
                        "{gid} discovered after endpoints were lost"
                    );
                    discovered.insert(gid);
                } else {
                    // Its only other endpoints are the ros_discovery_info writer and reader.
                    assert!(
                        e.participant_gid.to_string() != participant
                            || e.dds_topic_name == "ros_discovery_info",
                        "unexpected endpoint of the peer: {e:?}"
                    );
                }
            }
            DiscoveryEvent::ParticipantEntities(info) if info.gid.to_string() == participant => {
                // Republished as the node and its endpoints appear: wait for the message that
                // lists all of them. (Also with no node when it leaves; that one is not awaited:
                // it reaches rustdds ~1 ms before the writer's disposal, and rustdds 0.15.1
                // drops samples not yet taken from a writer it forgets.)
                let Some(node) = info.node_entities_info_seq.first() else {
                    continue;
                };
                assert_eq!(info.node_entities_info_seq.len(), 1, "{info:?}");
                assert_eq!(
                    (node.node_namespace.as_str(), node.node_name.as_str()),
                    ("/fast_ns", "fast_node")
                );
                let readers: Vec<String> = node
                    .reader_gid_seq
                    .iter()
                    .map(ToString::to_string)
                    .collect();
                let writers: Vec<String> = node
                    .writer_gid_seq
                    .iter()
                    .map(ToString::to_string)
                    .collect();
                assert!(node_readers.starts_with(&readers), "{readers:?}");
                assert!(node_writers.starts_with(&writers), "{writers:?}");
                if readers == node_readers && writers == node_writers {
                    saw_info = true;
                }
            }
            // The peer leaves: removes its node, then deletes its endpoints and participant.
            DiscoveryEvent::EndpointLost { gid, kind } => {
                let gid = gid.to_string();
                if let Some((_, expected, ..)) = endpoints.iter().find(|(g, ..)| *g == gid) {
                    assert_eq!(kind, *expected, "{gid}");
                    lost.insert(gid);
                }
            }
            DiscoveryEvent::ParticipantLost { gid } if gid.to_string() == participant => {
                assert!(saw_participant, "participant lost before it was discovered");
                participant_lost = true;
            }
            _ => {}
        }
    }
    let code = peer
        .wait(Duration::from_secs(5))
        .expect("wait for the peer");
    assert_eq!(code, Some(0), "the Fast DDS peer exits cleanly");
    eprintln!(
        "everything seen {:?} after the peer started",
        started.elapsed()
    );
}
