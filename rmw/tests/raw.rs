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
    let context = |name: &str| {
        let context = Context::builder()
            .domain_id(DOMAIN + 1)
            .build()
            .expect("context");
        let node = context.create_node(name, "/").expect("node");
        (context, node)
    };
    let (observer_context, observer) = context("observer");
    let mut feed = observer_context.discovery_feed().expect("feed");
    let mut reader = observer
        .create_raw_reader_unlisted(&spec("rq/observedRequest"))
        .expect("unlisted reader");
    let (writer_context, writer_node) = context("writer");
    let mut writer_feed = writer_context.discovery_feed().expect("feed");
    let writer = writer_node
        .create_raw_writer(&spec("rq/observedRequest"))
        .expect("writer");
    let mut discovered = false;
    let mut matched = false;
    let mut listings = Vec::new();
    let deadline = Instant::now() + common::LIMIT;
    while !(discovered && matched && !listings.is_empty()) {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "not discovered and matched in time");
        match feed.next_timeout(left) {
            Some(DiscoveryEvent::EndpointDiscovered(e)) if e.gid == reader.gid() => {
                discovered = true;
            }
            Some(DiscoveryEvent::ParticipantEntities(m)) if m.gid == observer_context.gid() => {
                listings.push(m)
            }
            Some(DiscoveryEvent::Matched { local, remote })
                if local == reader.gid() && remote == writer.gid() =>
            {
                matched = true;
            }
            _ => {}
        }
    }
    // Every ros_discovery_info message of the observer lists its node, never the reader.
    for m in &listings {
        let ours = m
            .node_entities_info_seq
            .iter()
            .find(|n| n.node_name == "observer")
            .expect("the node is listed");
        assert!(ours.reader_gid_seq.is_empty(), "{m:?}");
        assert!(ours.writer_gid_seq.is_empty(), "{m:?}");
    }
    // The writer sends only to the readers it has matched (VOLATILE): wait for its side too.
    let deadline = Instant::now() + common::LIMIT;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(
            !left.is_zero(),
            "the writer did not match the reader in time"
        );
        if let Some(DiscoveryEvent::Matched { local, remote }) = writer_feed.next_timeout(left) {
            if local == writer.gid() && remote == reader.gid() {
                break;
            }
        }
    }
    writer.write(vec![1, 0, 0, 0], None, None).expect("write");
    let deadline = Instant::now() + common::LIMIT;
    let sample = loop {
        if let Some(s) = reader.take().expect("take") {
            break s;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "the sample did not arrive");
        reader.wait(left);
    };
    assert_eq!(sample.body, vec![1, 0, 0, 0]);
}
