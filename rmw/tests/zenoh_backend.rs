//! The zenoh backend through the contract, two contexts of one process joined by a router
//! started in the test (what `horus-ros router` runs): the second context's feed reports the
//! first's participant, node and publisher with the GIDs rmw_zenoh would compute (its tokens),
//! a sample reaches a subscription waited on in a wait set with its writer's GID and sequence
//! number, and the publisher's and the context's end are reported. A service server (a
//! queryable with its SS token) in one context and a client (SC token, queries) in the other
//! exchange a request, a reply and an error reply with the identities rmw_zenoh gives them.
//!
//! One test in this binary: the sessions read `ZENOH_CONFIG_OVERRIDE` from the process's
//! environment, set once before any context. Run inside `scripts/isolated`.

#[allow(dead_code)]
mod common;

use std::time::Instant;

use common::{spec, LIMIT};
use horus_ros_rmw::qos::{DurabilityPolicy, Qos};
use horus_ros_rmw::service::HORUS_CLIENT_MARKER;
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::{
    Backend, Context, DiscoveryEvent, DiscoveryFeed, Gid, RawEndpointSpec, RawReader, RawSample,
    SampleId, ServiceEndpointRole, SignalHandlerOptions, VendorId, WaitSet,
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

/// The request and reply specs of an `example_interfaces/srv/AddTwoInts` server or client of
/// `/add_two_ints` in `context`.
fn service_specs(
    context: &Context,
    role: ServiceEndpointRole,
) -> (RawEndpointSpec, RawEndpointSpec) {
    use horus_ros_msgs::example_interfaces::srv::{
        AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse,
    };
    use horus_ros_msgs::{Message, Service};
    let id = Some(context.new_service_endpoint_id(role, AddTwoInts::type_hash()));
    let part = |topic: &str, dds_type_name: String, type_hash| RawEndpointSpec {
        dds_topic_name: topic.to_owned(),
        dds_type_name,
        type_hash,
        qos: Qos::services_default(),
        service_id: id,
    };
    (
        part(
            "rq/add_two_intsRequest",
            AddTwoIntsRequest::dds_type_name(),
            AddTwoIntsRequest::type_hash(),
        ),
        part(
            "rr/add_two_intsReply",
            AddTwoIntsResponse::dds_type_name(),
            AddTwoIntsResponse::type_hash(),
        ),
    )
}

/// The next sample of `reader`, within [`LIMIT`].
fn next_sample(reader: &mut RawReader, what: &str) -> RawSample {
    let deadline = Instant::now() + LIMIT;
    loop {
        if let Some(sample) = reader.take().expect("take") {
            return sample;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "no {what} within {LIMIT:?}");
        reader.wait(left);
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

    // A server in the talker's context, a client in the listener's: the client's request writer
    // is matched with the server's request reader (the GID of its SS token) and its reply reader
    // with the server's reply writer, as with any DDS server.
    let (request, reply) = service_specs(&talker, ServiceEndpointRole::Server);
    let mut requests = node.create_raw_reader(&request).expect("request reader");
    let replies = node.create_raw_writer(&reply).expect("reply writer");
    let (request, reply) = service_specs(&listener, ServiceEndpointRole::Client);
    let calls = sub_node
        .create_raw_writer(&request)
        .expect("request writer");
    let mut answers = sub_node.create_raw_reader(&reply).expect("reply reader");
    feed.find("the server's request reader", |e| {
        matches!(e, DiscoveryEvent::EndpointDiscovered(d)
            if d.gid == requests.gid() && d.dds_topic_name == "rq/add_two_intsRequest")
    });
    feed.find("our request writer matched with the server", |e| {
        *e == DiscoveryEvent::Matched {
            local: calls.gid(),
            remote: requests.gid(),
        }
    });
    feed.find("our reply reader matched with the server", |e| {
        *e == DiscoveryEvent::Matched {
            local: answers.gid(),
            remote: replies.gid(),
        }
    });
    // {a: 2, b: 3}: the request carries the client's GID and its sequence number from 1.
    let mut body = 2i64.to_le_bytes().to_vec();
    body.extend_from_slice(&3i64.to_le_bytes());
    let sent = calls.write(body.clone(), None, None).expect("request");
    assert_eq!(
        sent.sequence_number, 1,
        "rmw_zenoh numbers a client's requests from 1"
    );
    let taken = next_sample(&mut requests, "request");
    assert_eq!(taken.body, body);
    assert_eq!(taken.id, sent);
    assert_eq!(
        taken.related,
        Some(SampleId {
            writer: calls.gid(),
            sequence_number: HORUS_CLIENT_MARKER
        })
    );
    // The reply goes back through the query; one for a query that is gone is dropped.
    let gone = SampleId {
        writer: calls.gid(),
        sequence_number: 99,
    };
    replies
        .write(vec![9; 8], Some(gone), None)
        .expect("reply to nothing");
    replies
        .write(5i64.to_le_bytes().to_vec(), Some(sent), None)
        .expect("reply");
    let answer = next_sample(&mut answers, "reply");
    assert_eq!(answer.body, 5i64.to_le_bytes().to_vec());
    assert_eq!(
        answer.related,
        Some(sent),
        "the reply echoes the request's identity"
    );
    // An error reply (negated sequence number) is Zenoh's error reply.
    let second = calls.write(body, None, None).expect("request");
    assert_eq!(second.sequence_number, 2);
    let taken = next_sample(&mut requests, "second request");
    assert_eq!(taken.id, second);
    let failed = SampleId {
        sequence_number: -2,
        ..second
    };
    replies
        .write(vec![1, 0, 0, 0, 0, 0, 0, 0], Some(failed), None)
        .expect("error reply");
    let answer = next_sample(&mut answers, "error reply");
    assert_eq!(answer.related, Some(failed));
    assert!(
        answers.take().expect("take").is_none(),
        "one reply per request"
    );
    // A client in the server's own context reaches it too (its queryable answers local gets).
    let (request, reply) = service_specs(&talker, ServiceEndpointRole::Client);
    let local_calls = node
        .create_raw_writer(&request)
        .expect("local request writer");
    let mut local_answers = node.create_raw_reader(&reply).expect("local reply reader");
    let local = local_calls
        .write(vec![0; 16], None, None)
        .expect("local request");
    assert_eq!(
        local.sequence_number, 1,
        "each client numbers its own requests"
    );
    let taken = next_sample(&mut requests, "local request");
    assert_eq!(taken.id, local);
    replies
        .write(0i64.to_le_bytes().to_vec(), Some(local), None)
        .expect("local reply");
    assert_eq!(
        next_sample(&mut local_answers, "local reply").related,
        Some(local)
    );
    assert!(
        answers.take().expect("take").is_none(),
        "not the other client's"
    );
    drop(local_calls);
    drop(local_answers);

    // The server's end takes it off the client's graph.
    let server_gid = requests.gid();
    drop(requests);
    drop(replies);
    feed.find(
        "the server's loss",
        |e| matches!(e, DiscoveryEvent::EndpointLost { gid, .. } if *gid == server_gid),
    );
    drop(calls);
    drop(answers);

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
