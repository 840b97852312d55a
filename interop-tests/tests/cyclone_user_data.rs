//! What an rmw_cyclonedds node reads from our DDS discovery data: the USER_DATA of our participant
//! and endpoints, as an independent Cyclone DDS peer (`peers/cyclone_discovery_info.py`) receives
//! it through the DCPSParticipant / DCPSPublication / DCPSSubscription built-in topics.
//!
//! - Cyclone backend: exactly what rmw_cyclonedds_cpp announces — participant `enclave=/;`
//!   (`rmw_context_impl_s::init`), topic endpoints `typehash=RIHS01_…;` (`create_readwrite_qos`),
//!   a server's request reader and reply writer `serviceid=<id>;typehash=…;` and a client's
//!   request writer and reply reader `clientid=<id>;typehash=…;` (`rmw_init_cs`), the id being the
//!   participant's GUID prefix and a per-participant counter from 1 (`get_unique_csid`) written
//!   as `csid_to_string` does.
//! - rustdds backend: nothing (a documented limitation: rustdds cannot send USER_DATA).
//!
//! Each test chooses its backend explicitly, so both run the same under any `HORUS_ROS_BACKEND`.

use std::time::Duration;

use horus_ros_msgs::builtin_interfaces::msg::{Duration as RosDuration, Time};
use horus_ros_rmw::{qos::Qos, Backend, Gid};
use horus_ros_services::prelude::*;
use interop_tests::Peer;
use serde_json::Value;

/// rmw_cyclonedds `csid_to_string`: lower-case hex bytes joined by `.`, the first right-aligned
/// in two characters (`std::setw(2)`, space fill), the others unpadded.
fn csid_to_string(id: &[u8; 16]) -> String {
    let mut s = format!("{:>2x}", id[0]);
    for b in &id[1..] {
        s.push_str(&format!(".{b:x}"));
    }
    s
}

/// rmw_cyclonedds `get_unique_csid`: the participant GID's 12-byte prefix, then the context's
/// `counter`-th client/service id, big-endian.
fn csid(participant: Gid, counter: u32) -> [u8; 16] {
    let mut id = [0u8; 16];
    id[..12].copy_from_slice(&participant.as_bytes()[..12]);
    id[12..].copy_from_slice(&counter.to_be_bytes());
    id
}

#[test]
fn csid_is_written_as_rmw_cyclonedds_writes_it() {
    let id = [
        0x01, 0x10, 0xa3, 0x0f, 0x00, 0xff, 0x7c, 0x10, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x01,
        0x2a,
    ];
    assert_eq!(
        csid_to_string(&id),
        " 1.10.a3.f.0.ff.7c.10.0.0.0.1.0.0.1.2a"
    );
    let mut wide = id;
    wide[0] = 0xab;
    assert!(csid_to_string(&wide).starts_with("ab.10."));
}

/// What the peer saw of our graph: a node with a publisher, a subscription, a server and a
/// client (created in that order).
struct Seen {
    doc: Value,
    context: Context,
    publisher: Gid,
    subscription: Gid,
    /// Request reader, reply writer.
    server: (Gid, Gid),
    /// Request writer, reply reader.
    client: (Gid, Gid),
}

impl Seen {
    fn new(domain: u32, backend: Backend) -> Self {
        let context = Context::builder()
            .domain_id(domain)
            .backend(backend)
            .build()
            .expect("context");
        assert_eq!(context.backend(), Some(backend));
        let node = context.create_node("ud_node", "/ud").expect("node");
        let publisher = node
            .create_publisher::<Time>("chatter", &Qos::default())
            .expect("publisher");
        let subscription = node
            .create_subscription::<RosDuration>("elapsed", &Qos::default())
            .expect("subscription");
        let server = ServiceServer::<AddTwoInts>::builder()
            .node(&node)
            .name("add")
            .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
            .build()
            .expect("server");
        let client = ServiceClient::<AddTwoInts>::builder()
            .node(&node)
            .name("/elsewhere/add")
            .build()
            .expect("client");

        // Readers: subscription, request reader, reply reader; writers: publisher, reply
        // writer, request writer.
        let peer = Peer::start(
            "cyclone_discovery_info.py",
            &[
                domain.to_string(),
                "/ud".into(),
                "ud_node".into(),
                "3".into(),
                "3".into(),
                "20".into(),
            ],
        )
        .expect("start the Cyclone DDS peer");
        let out = peer.wait(Duration::from_secs(30)).expect("peer output");
        assert_eq!(
            out.code,
            Some(0),
            "peer failed ({backend}): stdout={} stderr={}",
            out.stdout,
            out.stderr
        );
        let doc: Value = serde_json::from_str(out.stdout.trim()).expect("peer prints JSON");
        eprintln!("the Cyclone DDS peer saw ({backend}): {doc}");
        Self {
            doc,
            publisher: publisher.gid(),
            subscription: subscription.gid(),
            server: server.gids(),
            client: client.gids(),
            context,
        }
    }

    /// The USER_DATA the peer received for `guid` in `table` (`participants`, `publications`,
    /// `subscriptions`).
    fn user_data(&self, table: &str, guid: Gid) -> String {
        let guid = guid.to_string();
        self.doc[table]
            .as_array()
            .and_then(|a| a.iter().find(|e| e["guid"] == guid.as_str()))
            .and_then(|e| e["user_data"].as_str())
            .unwrap_or_else(|| panic!("{guid} not in the peer's {table}: {}", self.doc))
            .to_owned()
    }

    /// Every USER_DATA of ours: participant, publisher, subscription, server request reader and
    /// reply writer, client request writer and reply reader.
    fn all(&self) -> [String; 7] {
        [
            self.user_data("participants", self.context.gid()),
            self.user_data("publications", self.publisher),
            self.user_data("subscriptions", self.subscription),
            self.user_data("subscriptions", self.server.0),
            self.user_data("publications", self.server.1),
            self.user_data("publications", self.client.0),
            self.user_data("subscriptions", self.client.1),
        ]
    }
}

#[test]
fn cyclone_backend_announces_user_data_as_rmw_cyclonedds() {
    assert!(Backend::Cyclone
        .capabilities()
        .is_some_and(|c| c.announces_user_data));
    let seen = Seen::new(81, Backend::Cyclone);
    let participant = seen.context.gid();
    // The server's id was allocated first, the client's second.
    let service_id = csid_to_string(&csid(participant, 1));
    let client_id = csid_to_string(&csid(participant, 2));
    // Cyclone's GUID prefixes start with its vendor id 01.10: the padded first byte shows.
    assert!(service_id.starts_with(" 1.10."), "{service_id}");
    let request = AddTwoIntsRequest::type_hash();
    let response = AddTwoIntsResponse::type_hash();
    assert_eq!(
        seen.all(),
        [
            "enclave=/;".to_owned(),
            format!("typehash={};", Time::type_hash()),
            format!("typehash={};", RosDuration::type_hash()),
            format!("serviceid={service_id};typehash={request};"),
            format!("serviceid={service_id};typehash={response};"),
            format!("clientid={client_id};typehash={request};"),
            format!("clientid={client_id};typehash={response};"),
        ]
    );
}

#[test]
fn rustdds_backend_announces_no_user_data() {
    // A documented limitation: RustDDS cannot send USER_DATA, so rmw_cyclonedds nodes see no
    // enclave, no type hashes and no client/service ids from us.
    assert!(Backend::RustDds
        .capabilities()
        .is_some_and(|c| !c.announces_user_data));
    let seen = Seen::new(82, Backend::RustDds);
    assert_eq!(seen.all(), <[String; 7]>::default());
}
