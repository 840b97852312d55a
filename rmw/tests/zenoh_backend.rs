//! The zenoh backend through the contract, two contexts of one process joined by a router
//! started in the test (what `horus-ros router` runs): the second context's feed reports the
//! first's participant, node and publisher with the GIDs rmw_zenoh would compute (its tokens),
//! a sample reaches a subscription waited on in a wait set with its writer's GID and sequence
//! number, and the publisher's and the context's end are reported.
//!
//! One test in this binary: the sessions read `ZENOH_CONFIG_OVERRIDE` from the process's
//! environment, set once before any context. Run inside `scripts/isolated`.

#[allow(dead_code)]
mod common;

use std::time::Instant;

use common::{spec, LIMIT};
use horus_ros_rmw::qos::{DurabilityPolicy, Qos};
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::{
    Backend, Context, DiscoveryEvent, DiscoveryFeed, Gid, SignalHandlerOptions, VendorId, WaitSet,
};
use zenoh::Wait;

const PORT: u16 = 17560;
const DOMAIN: u32 = 61;

/// The events a feed reported, kept so that a wait for one finds it among those already seen.
struct Events {
    feed: DiscoveryFeed,
    seen: Vec<DiscoveryEvent>,
}

impl Events {
    /// The first event (seen or still to come) satisfying `want`, within [`LIMIT`].
    fn find(
        &mut self,
        what: &str,
        mut want: impl FnMut(&DiscoveryEvent) -> bool,
    ) -> DiscoveryEvent {
        if let Some(e) = self.seen.iter().find(|e| want(e)) {
            return e.clone();
        }
        let deadline = Instant::now() + LIMIT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            assert!(
                !left.is_zero(),
                "no {what} within {LIMIT:?}: {:#?}",
                self.seen
            );
            if let Some(event) = self.feed.next_timeout(left) {
                self.seen.push(event.clone());
                if want(&event) {
                    return event;
                }
            }
        }
    }
}

fn context() -> Context {
    Context::builder()
        .backend(Backend::Zenoh)
        .domain_id(DOMAIN)
        .signal_handler(SignalHandlerOptions::None)
        .arguments(Default::default())
        .build()
        .expect("a zenoh context")
}

#[test]
fn two_contexts_through_a_router() {
    let get = |k: &str| {
        (k == config::CONFIG_OVERRIDE_ENV)
            .then(|| format!(r#"listen/endpoints=["tcp/127.0.0.1:{PORT}"]"#))
    };
    let router = zenoh::open(config::config(ConfigKind::Router, get).expect("router config"))
        .wait()
        .expect("router");
    std::env::set_var(
        config::CONFIG_OVERRIDE_ENV,
        format!(
            r#"connect/endpoints=["tcp/127.0.0.1:{PORT}"];listen/endpoints=["tcp/127.0.0.1:0"]"#
        ),
    );

    let listener = context();
    assert_eq!(listener.rmw_implementation(), "rmw_zenoh_cpp");
    let mut feed = Events {
        feed: listener.discovery_feed().expect("feed"),
        seen: Vec::new(),
    };
    let sub_node = listener.create_node("listener", "/").expect("node");
    let mut reader = sub_node
        .create_raw_reader(&spec("rt/zenoh_test"))
        .expect("reader");
    let set = WaitSet::new(&listener).expect("wait set");
    set.attach(&mut reader, 7).expect("attach");

    let talker = context();
    let node = talker.create_node("talker", "/ns").expect("node");
    let writer = node
        .create_raw_writer(&spec("rt/zenoh_test"))
        .expect("writer");

    // The talker's session is a participant; its writer an endpoint with the writer's GID (the
    // XXH3-128 of its MP token); its node lists it.
    let participant = match feed.find(
        "talker participant",
        |e| matches!(e, DiscoveryEvent::ParticipantDiscovered(p) if p.gid != listener.gid()),
    ) {
        DiscoveryEvent::ParticipantDiscovered(p) => p,
        _ => unreachable!(),
    };
    assert_eq!(participant.gid, talker.gid());
    assert_eq!(participant.vendor_id, VendorId::ZENOH);
    feed.find("the talker's writer", |e| {
        matches!(e, DiscoveryEvent::EndpointDiscovered(d)
            if d.gid == writer.gid() && d.participant_gid == talker.gid()
                && d.dds_topic_name == "rt/zenoh_test")
    });
    feed.find("the talker's node listing its writer", |e| {
        matches!(e, DiscoveryEvent::ParticipantEntities(info)
            if info.gid == talker.gid() && info.node_entities_info_seq.iter().any(|n|
                n.node_name == "talker" && n.node_namespace == "/ns"
                    && n.writer_gid_seq == vec![writer.gid()]))
    });
    feed.find("our reader matched with the writer", |e| {
        *e == DiscoveryEvent::Matched {
            local: reader.gid(),
            remote: writer.gid(),
        }
    });

    // A sample reaches the reader, waited for in the wait set.
    let body = vec![1, 0, 0, 0, 2, 0, 0, 0];
    let sent = writer.write(body.clone(), None, None).expect("write");
    assert_eq!(sent.sequence_number, 1, "rmw_zenoh numbers from 1");
    // The set was marked when the sample came, whether before or during this wait.
    let mut ready = Vec::new();
    assert!(set.wait(LIMIT, &mut ready), "the wait set was not woken");
    assert_eq!(ready, vec![7]);
    let sample = reader.take().expect("take").expect("the sample");
    assert_eq!(sample.body, body);
    assert_eq!(sample.id, sent);
    assert_eq!(sample.id.writer, writer.gid());

    // TRANSIENT_LOCAL (zenoh-ext's advanced publisher and subscriber, as rmw_zenoh's): a
    // subscription created after three samples were written gets the last `depth` (2) of them.
    let mut latched = spec("rt/zenoh_latched");
    latched.qos = Qos::default_profile().keep_last(2);
    latched.qos.durability = DurabilityPolicy::TransientLocal;
    let latched_writer = node.create_raw_writer(&latched).expect("latched writer");
    for n in 1u8..=3 {
        latched_writer
            .write(vec![n, 0, 0, 0], None, None)
            .expect("write");
    }
    let mut late = sub_node.create_raw_reader(&latched).expect("late reader");
    let mut got = Vec::new();
    let deadline = Instant::now() + LIMIT;
    while got.len() < 2 {
        match late.take().expect("take") {
            Some(sample) => got.push(sample.body[0]),
            None => {
                let left = deadline.saturating_duration_since(Instant::now());
                assert!(!left.is_zero(), "the history did not come: {got:?}");
                late.wait(left);
            }
        }
    }
    assert_eq!(got, vec![2, 3]);
    drop(late);
    drop(latched_writer);

    // The writer's end, then the context's.
    let writer_gid = writer.gid();
    drop(writer);
    feed.find(
        "the writer's loss",
        |e| matches!(e, DiscoveryEvent::EndpointLost { gid, .. } if *gid == writer_gid),
    );
    let talker_gid: Gid = talker.gid();
    drop(node);
    drop(talker);
    feed.find("the talker's loss", |e| {
        *e == DiscoveryEvent::ParticipantLost { gid: talker_gid }
    });
    drop(feed);
    drop(reader);
    drop(listener);
    router.close().wait().expect("close the router");
}
