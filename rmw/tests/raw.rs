//! Raw endpoints: bodies, sample identities, related_sample_identity and matching.

mod common;

use std::time::{Duration, Instant};

use common::{await_matches, spec};
use horus_ros_rmw::{Context, DdsError, DiscoveryEvent, SampleError, SampleId};

const DOMAIN: u32 = 38;

#[test]
fn raw_samples_carry_identity_and_related_identity() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("raw", "/").expect("node");
    let mut feed = context.discovery_feed().expect("feed");
    let writer = node
        .create_raw_writer(&spec("rq/rawRequest"))
        .expect("writer");
    let mut reader = node
        .create_raw_reader(&spec("rq/rawRequest"))
        .expect("reader");
    // The feed reports both sides of the match (writer→reader and reader→writer).
    await_matches(&mut feed, &[(writer.gid(), reader.gid())]);

    let related = SampleId {
        writer: reader.gid(),
        sequence_number: SampleId::UNKNOWN_SEQUENCE_NUMBER,
    };
    let body = vec![1, 0, 0, 0, 2, 0, 0, 0];
    let carries_identity = context.capabilities().carries_sample_identity;
    if !carries_identity {
        // Cyclone DDS cannot send related_sample_identity: refused, nothing sent.
        let refused = writer.write(body.clone(), Some(related), None);
        assert!(
            refused.is_err_and(|e| matches!(
                e.cause,
                SampleError::Dds(DdsError::RelatedSampleIdentityUnsupported)
            ) && e.to_string().contains("related_sample_identity")),
            "a related identity must be refused on {:?}",
            context.backend()
        );
    }
    let sent = writer
        .write(body.clone(), carries_identity.then_some(related), None)
        .expect("write");
    assert_eq!(sent.writer, writer.gid());
    let second = writer
        .write(vec![9, 9, 9, 9], None, Some(reader.gid()))
        .expect("write to one reader");
    assert_eq!(second.sequence_number, sent.sequence_number + 1);

    let deadline = Instant::now() + Duration::from_secs(10);
    let mut got = Vec::new();
    while got.len() < 2 {
        assert!(Instant::now() < deadline, "samples did not arrive: {got:?}");
        match reader.take().expect("take") {
            Some(s) => got.push(s),
            None => {
                reader.wait(Duration::from_millis(100));
            }
        }
    }
    assert_eq!(got[0].body, body);
    assert!(!got[0].big_endian);
    assert_eq!(got[1].body, vec![9, 9, 9, 9]);
    assert_eq!(got[1].related, None);
    if carries_identity {
        assert_eq!(got[0].id, sent);
        assert_eq!(got[0].related, Some(related));
        assert_eq!(got[1].id, second);
    } else {
        // The writer is known; sequence numbers and related identities are not reported.
        for sample in &got {
            assert_eq!(sample.id.writer, writer.gid());
            assert_eq!(sample.id.sequence_number, SampleId::UNKNOWN_SEQUENCE_NUMBER);
        }
        assert_eq!(got[0].related, None);
    }
}

#[test]
fn an_unlisted_reader_is_discovered_and_matched_but_listed_under_no_node() {
    let context = Context::builder()
        .domain_id(DOMAIN + 1)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("feed");
    let node = context.create_node("observer", "/").expect("node");
    let writer = node
        .create_raw_writer(&spec("rq/observedRequest"))
        .expect("writer");
    let mut reader = node
        .create_raw_reader_unlisted(&spec("rq/observedRequest"))
        .expect("unlisted reader");
    let mut discovered = false;
    let mut listings = Vec::new();
    let mut matched = std::collections::HashSet::new();
    let deadline = Instant::now() + common::LIMIT;
    while !(discovered && matched.len() == 2 && !listings.is_empty()) {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "not discovered and matched in time");
        match feed.next_timeout(left) {
            Some(DiscoveryEvent::EndpointDiscovered(e)) if e.gid == reader.gid() => {
                discovered = true;
            }
            Some(DiscoveryEvent::ParticipantEntities(m)) => listings.push(m),
            Some(DiscoveryEvent::Matched { local, remote }) => {
                matched.insert((local, remote));
            }
            _ => {}
        }
    }
    // Every ros_discovery_info message lists the writer at most, never the reader.
    let last = listings.last().expect("a listing");
    let ours = last
        .node_entities_info_seq
        .iter()
        .find(|n| n.node_name == "observer")
        .expect("the node is listed");
    assert_eq!(ours.writer_gid_seq, vec![writer.gid()]);
    for m in &listings {
        for n in &m.node_entities_info_seq {
            assert!(!n.reader_gid_seq.contains(&reader.gid()), "{m:?}");
        }
    }
    writer.write(vec![1, 0, 0, 0], None, None).expect("write");
    let deadline = Instant::now() + common::LIMIT;
    loop {
        if let Some(s) = reader.take().expect("take") {
            assert_eq!(s.body, vec![1, 0, 0, 0]);
            break;
        }
        assert!(Instant::now() < deadline, "the sample did not arrive");
        reader.wait(Duration::from_millis(100));
    }
}
