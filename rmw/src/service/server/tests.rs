//! When a reply may go out, against a graph written by hand: which reader each convention waits
//! for, and the first-heartbeat settle for Cyclone DDS readers.

use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::*;
use crate::names::ServiceName;
use crate::Backend;

/// A graph written by hand.
#[derive(Default)]
struct Graph {
    vendors: Mutex<HashMap<[u8; 12], VendorId>>,
    /// (ours, theirs, since).
    matches: Mutex<Vec<(Gid, Gid, Instant)>>,
    discovered: Mutex<HashSet<Gid>>,
    client_ids: Mutex<HashMap<Gid, Arc<str>>>,
}

impl Peers for Graph {
    fn participant_vendor(&self, gid: Gid) -> Option<VendorId> {
        lock(&self.vendors).get(&gid.prefix()).copied()
    }

    fn is_matched(&self, local: Gid, remote: Gid) -> bool {
        lock(&self.matches)
            .iter()
            .any(|&(l, r, _)| l == local && r == remote)
    }

    fn participant_matched_since(&self, local: Gid, remote: Gid) -> Option<Instant> {
        lock(&self.matches)
            .iter()
            .filter(|&&(l, r, _)| l == local && r.prefix() == remote.prefix())
            .map(|&(_, _, since)| since)
            .min()
    }

    fn client_id(&self, gid: Gid) -> ClientIdLookup {
        match lock(&self.client_ids).get(&gid) {
            Some(id) => ClientIdLookup::Id(Arc::clone(id)),
            None if lock(&self.discovered).contains(&gid) => ClientIdLookup::Absent,
            None => ClientIdLookup::Undiscovered,
        }
    }

    fn matched_with_client_id(&self, local: Gid, remote: Gid, id: &str) -> bool {
        let ids = lock(&self.client_ids);
        lock(&self.matches).iter().any(|&(l, r, _)| {
            l == local && r.prefix() == remote.prefix() && ids.get(&r).is_some_and(|i| &**i == id)
        })
    }
}

impl Graph {
    fn participant(&self, prefix: u8, vendor: VendorId) {
        lock(&self.vendors).insert(gid(prefix, 0x0000_01c1).prefix(), vendor);
    }

    /// An endpoint discovered with `client_id` (`None`: no `clientid=`).
    fn endpoint(&self, gid: Gid, client_id: Option<&str>) {
        lock(&self.discovered).insert(gid);
        if let Some(id) = client_id {
            lock(&self.client_ids).insert(gid, id.into());
        }
    }

    fn matched(&self, local: Gid, remote: Gid, since: Instant) {
        lock(&self.matches).push((local, remote, since));
    }
}

/// A GID of participant `prefix` (vendor Cyclone DDS in its first two bytes) with `entity`.
fn gid(prefix: u8, entity: u32) -> Gid {
    let mut b = [0u8; 16];
    b[..2].copy_from_slice(&VendorId::CYCLONE_DDS.0);
    b[11] = prefix;
    b[12..].copy_from_slice(&entity.to_be_bytes());
    Gid::from_bytes(b)
}

/// Our reply writer, and the request writer and reply reader of client `n` of participant 2.
const OURS: u8 = 1;
fn reply_writer() -> Gid {
    gid(OURS, 0x0000_0303)
}
fn request_writer(n: u32) -> Gid {
    gid(2, 0x0000_0003 | (2 * n) << 8)
}
fn reply_reader(n: u32) -> Gid {
    gid(2, 0x0000_0004 | (2 * n + 1) << 8)
}

fn server_on(graph: &Arc<Graph>, backend: Backend) -> Server {
    let peers = Arc::clone(graph) as Arc<dyn Peers>;
    let service = ServiceName::new("/add_two_ints").expect("name");
    let own = crate::service::shapes::of(backend);
    Server::new(peers, service, reply_writer(), None, own)
}

/// An instant well past the first-heartbeat settle of a participant first heard from at `now`.
fn settled(now: Instant) -> Instant {
    now + 10 * CYCLONE_FIRST_HEARTBEAT_SETTLE
}

/// When the response to an rmw_cyclonedds request of `writer` may go out at `now`.
fn cyclone_reply(server: &Server, writer: Gid, now: Instant) -> Readiness {
    let header = CycloneHeader { guid: 7, seq: 1 };
    let sample = RawSample {
        body: header.prepend(&[0; 16]),
        big_endian: false,
        id: SampleId {
            writer,
            sequence_number: 1,
        },
        related: None,
        publication_handle: Some(9),
        source_timestamp: None,
        received_timestamp: 0,
    };
    let request = server.request_from(sample).expect("a request");
    let response = server
        .response(&request.route, Ok(vec![0; 8]))
        .expect("a response");
    server.readiness(response.recipient, now)
}

#[test]
fn an_rmw_cyclonedds_reply_waits_for_the_reader_with_its_client_id() {
    let graph = Arc::new(Graph::default());
    graph.participant(2, VendorId::CYCLONE_DDS);
    let server = server_on(&graph, Backend::Cyclone);
    let now = Instant::now();
    // Client 1 of the participant is answered already: its reader is matched.
    for n in [1, 2] {
        let id = format!("id.{n}");
        graph.endpoint(request_writer(n), Some(&id));
        graph.endpoint(reply_reader(n), Some(&id));
    }
    graph.matched(reply_writer(), reply_reader(1), now);
    assert_eq!(
        cyclone_reply(&server, request_writer(1), settled(now)),
        Readiness::Now
    );
    // Client 2's reader is not matched yet: its reply waits, although the participant's other
    // reader is matched (a Cyclone DDS writer never sends it what it wrote before the match).
    assert_eq!(
        cyclone_reply(&server, request_writer(2), now),
        Readiness::Later
    );
    graph.matched(reply_writer(), reply_reader(2), now);
    assert_eq!(
        cyclone_reply(&server, request_writer(2), settled(now)),
        Readiness::Now
    );
}

#[test]
fn an_rmw_cyclonedds_reply_waits_until_its_request_writer_is_discovered() {
    let graph = Arc::new(Graph::default());
    graph.participant(2, VendorId::CYCLONE_DDS);
    let server = server_on(&graph, Backend::Cyclone);
    let now = Instant::now();
    graph.endpoint(reply_reader(1), Some("id.1"));
    graph.matched(reply_writer(), reply_reader(1), now);
    // Whose reader is it? Not known until discovery lists the request writer.
    assert_eq!(
        cyclone_reply(&server, request_writer(2), now),
        Readiness::Later
    );
    graph.endpoint(request_writer(2), Some("id.1"));
    assert_eq!(
        cyclone_reply(&server, request_writer(2), settled(now)),
        Readiness::Now
    );
}

#[test]
fn a_request_writer_without_client_id_is_heard_by_its_participant() {
    let graph = Arc::new(Graph::default());
    graph.participant(2, VendorId::CYCLONE_DDS);
    let server = server_on(&graph, Backend::Cyclone);
    let now = Instant::now();
    graph.endpoint(request_writer(1), None);
    assert_eq!(
        cyclone_reply(&server, request_writer(1), now),
        Readiness::Later
    );
    graph.matched(reply_writer(), reply_reader(1), now);
    assert_eq!(
        cyclone_reply(&server, request_writer(1), settled(now)),
        Readiness::Now
    );
}

#[test]
fn a_client_of_our_own_participant_is_answered_at_once() {
    let graph = Arc::new(Graph::default());
    graph.participant(OURS, VendorId::CYCLONE_DDS);
    let server = server_on(&graph, Backend::Cyclone);
    let (writer, reader) = (gid(OURS, 0x0000_0103), gid(OURS, 0x0000_0204));
    graph.endpoint(writer, Some("id.1"));
    graph.endpoint(reader, Some("id.1"));
    let now = Instant::now();
    graph.matched(reply_writer(), reader, now);
    assert_eq!(cyclone_reply(&server, writer, now), Readiness::Now);
}

#[test]
fn a_fresh_cyclone_participant_gets_time_for_its_first_heartbeat_on_both_dds_backends() {
    for backend in [Backend::RustDds, Backend::Cyclone] {
        fresh_cyclone_participant_settles(backend);
    }
}

fn fresh_cyclone_participant_settles(backend: Backend) {
    let graph = Arc::new(Graph::default());
    graph.participant(2, VendorId::CYCLONE_DDS);
    let server = server_on(&graph, backend);
    let settle = CYCLONE_FIRST_HEARTBEAT_SETTLE;
    for n in [1, 2] {
        let id = format!("id.{n}");
        graph.endpoint(request_writer(n), Some(&id));
        graph.endpoint(reply_reader(n), Some(&id));
    }
    // Its reader was matched long ago, but it may have discovered our writer only now: the
    // settle counts from its first request too.
    let before = Instant::now();
    graph.matched(reply_writer(), reply_reader(1), before - 10 * settle);
    let ready = cyclone_reply(&server, request_writer(1), before);
    let after = Instant::now();
    let Readiness::At(at) = ready else {
        panic!("a fresh participant's first reply waits, not {ready:?}");
    };
    assert!(before + settle <= at && at <= after + settle, "{at:?}");
    assert_eq!(
        cyclone_reply(&server, request_writer(1), at),
        Readiness::Now
    );
    // A later client of the same participant: it has had its first heartbeat.
    let later = at + Duration::from_secs(1);
    graph.matched(reply_writer(), reply_reader(2), later);
    assert_eq!(
        cyclone_reply(&server, request_writer(2), later),
        Readiness::Now
    );
    // A participant matched just now waits from the match.
    let graph = Arc::new(Graph::default());
    graph.participant(2, VendorId::CYCLONE_DDS);
    let server = server_on(&graph, backend);
    graph.endpoint(request_writer(1), Some("id.1"));
    graph.endpoint(reply_reader(1), Some("id.1"));
    let matched = Instant::now() + settle;
    graph.matched(reply_writer(), reply_reader(1), matched);
    assert_eq!(
        cyclone_reply(&server, request_writer(1), matched),
        Readiness::At(matched + settle)
    );
}

#[test]
fn an_rmw_fastrtps_request_without_reader_waits_for_its_participant() {
    let graph = Arc::new(Graph::default());
    let fast_dds = VendorId::FAST_DDS;
    let server = server_on(&graph, Backend::RustDds);
    let writer = {
        let mut b = *request_writer(1).as_bytes();
        b[..2].copy_from_slice(&fast_dds.0);
        Gid::from_bytes(b)
    };
    let reader = {
        let mut b = *reply_reader(1).as_bytes();
        b[..2].copy_from_slice(&fast_dds.0);
        Gid::from_bytes(b)
    };
    lock(&graph.vendors).insert(writer.prefix(), fast_dds);
    let sample = RawSample {
        body: vec![0; 16],
        big_endian: false,
        id: SampleId {
            writer,
            sequence_number: 1,
        },
        related: None,
        publication_handle: None,
        source_timestamp: None,
        received_timestamp: 0,
    };
    let request = server.request_from(sample).expect("a request");
    let response = server
        .response(&request.route, Ok(vec![0; 8]))
        .expect("a response");
    let now = Instant::now();
    assert_eq!(server.readiness(response.recipient, now), Readiness::Later);
    graph.matched(reply_writer(), reader, now);
    assert_eq!(server.readiness(response.recipient, now), Readiness::Now);
}
