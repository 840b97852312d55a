//! horus-ros services against an eProsima Fast DDS 2.9 peer (`peers/fastdds/`) that serves and
//! calls `example_interfaces/srv/AddTwoInts` the way rmw_fastrtps_cpp (Jazzy's default RMW) does:
//! request ids from the related_sample_identity, replies correlated through it.
//!
//! - Our client calls the Fast DDS server, choosing the rmw_fastrtps wire convention by itself
//!   from the server participant's vendor; the peer logs the request id it computed for each
//!   request, which must name our client's reply reader, as rmw_fastrtps would compute it.
//! - The Fast DDS client (which waits for our server as `rmw_service_server_is_available` does)
//!   calls our server and accepts our replies as `__rmw_take_response` does.
//!
//! Both need `related_sample_identity`, which only a backend that carries sample identities
//! (rustdds) can send and read. On the Cyclone backend (like rmw_cyclonedds itself) the tests
//! check the refusal instead: our client's call fails at once with a `Transport` error naming
//! rmw_fastrtps and the rustdds backend, and the Fast DDS client gets no answer from our server.

use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_rmw::VendorId;
use horus_ros_services::prelude::*;
use interop_tests::fastdds::{FastDdsPeer, Served};
use serde_json::Value;

const SECOND: Duration = Duration::from_secs(1);

/// How long a refusal may take once the server is on the graph ("at once": no call timeout).
const REFUSAL_LIMIT: Duration = Duration::from_secs(2);

fn node(domain: u32, name: &str) -> (Context, Node) {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node(name, "/").expect("node");
    (context, node)
}

#[test]
fn our_client_calls_a_fastdds_server() {
    const DOMAIN: u32 = 62;
    const SERVICE: &str = "/fast_ns/add_two_ints";
    const CALLS: i64 = 5;
    let (context, node) = node(DOMAIN, "horus_caller");
    let refusing = !context.backend().carries_sample_identity();
    let started = Instant::now();
    let mut peer = FastDdsPeer::start(
        DOMAIN,
        "/fast_ns",
        "fast_server",
        SERVICE,
        Duration::from_secs(if refusing { 8 } else { 15 }),
    )
    .expect("build and start the Fast DDS peer");
    let created = peer
        .created(10 * SECOND)
        .expect("the peer says what it created");
    // A Fast DDS participant, for which the client (not configured) must choose rmw_fastrtps'
    // convention; the peer's log below shows that it did. (No second participant of ours checks
    // the vendor on the wire: with one that has readers but no writers, Fast DDS 2.9.1 aborts
    // in OutputTrafficManager, eProsima/Fast-DDS#5704.)
    assert_eq!(created.vendor, "010f");
    let [hi, lo] = VendorId::FAST_DDS.0;
    assert_eq!(created.vendor, format!("{hi:02x}{lo:02x}"));
    assert_eq!(
        WireFlavour::for_vendor(Some(VendorId::FAST_DDS)),
        WireFlavour::FastRtps
    );
    assert!(created.participant.starts_with("01.0f."), "{created:?}");
    assert_eq!(created.request_topic, "rq/fast_ns/add_two_intsRequest");

    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name(SERVICE)
        .build()
        .expect("client");
    let (request_writer, reply_reader) = client.gids();
    if refusing {
        client_is_refused(&context, &mut client, &mut peer);
        return;
    }
    assert!(
        client.wait_for_service(10 * SECOND),
        "the Fast DDS server never became usable; peer output:\n{}",
        peer.output()
    );
    eprintln!(
        "server usable {:?} after the peer started",
        started.elapsed()
    );

    let calls: Vec<(i64, i64)> = (1..=CALLS).map(|i| (i, 100 * i + 7)).collect();
    for &(a, b) in &calls {
        let reply = client.call(AddTwoIntsRequest { a, b }, 5 * SECOND);
        assert_eq!(
            reply,
            Ok(AddTwoIntsResponse { sum: a + b }),
            "call a={a} b={b}; peer output:\n{}",
            peer.output()
        );
    }
    assert_eq!(client.pending_requests(), 0);

    // What the peer computed for each request (printed after it sent the reply).
    let mut served = Vec::new();
    let deadline = Instant::now() + 5 * SECOND;
    while served.len() < calls.len() && Instant::now() < deadline {
        if let Some(line) = peer.next_line(Duration::from_millis(100)) {
            if let Some(s) = Served::parse(&line) {
                served.push(s);
            }
        }
    }
    let output = peer.output();
    assert_eq!(served.len(), calls.len(), "peer output:\n{output}");
    for (k, (s, &(a, b))) in served.iter().zip(&calls).enumerate() {
        let what = format!("request {k}: {s:?}\npeer output:\n{output}");
        assert_eq!((s.a, s.b, s.sum), (a, b, a + b), "{what}");
        // The request came from our request writer, with related_sample_identity naming our
        // reply reader (only the rmw_fastrtps convention sends one; an rmw_cyclonedds-style
        // request would also have put a 16-byte header before a and b) ...
        assert_eq!(s.sample_writer, request_writer.to_string(), "{what}");
        assert_eq!(s.related_guid, reply_reader.to_string(), "{what}");
        // ... so rmw_fastrtps' request id is {our reply reader, the request's SN}: the k-th
        // sample of a fresh writer has SN k + 1.
        assert_eq!(s.request_id_guid, reply_reader.to_string(), "{what}");
        assert_eq!(s.request_id_sequence_number, k as i64 + 1, "{what}");
        // It found our reply reader matched before answering, as rmw_fastrtps requires.
        assert_eq!(s.client_present, "YES", "{what}");
        assert!(s.sent, "{what}");
    }
    eprintln!(
        "{CALLS} calls served {:?} after the peer started",
        started.elapsed()
    );
}

/// On a backend without sample identities: once the Fast DDS server is on the graph, a call
/// fails at once with a `Transport` error saying why and what to use instead, nothing is sent,
/// and `wait_for_service` reports the server unusable without waiting out its timeout.
fn client_is_refused(
    context: &Context,
    client: &mut ServiceClient<AddTwoInts>,
    peer: &mut FastDdsPeer,
) {
    let graph = Graph::shared(context).expect("graph");
    let shown = graph.wait_until(10 * SECOND, |cache| {
        cache
            .servers_info_by_service(client.name().as_str(), false)
            .is_ok_and(|servers| !servers.is_empty())
    });
    assert!(
        shown && client.server_available(),
        "the Fast DDS server never showed up on the graph; peer output:\n{}",
        peer.output()
    );
    let backend = context.backend();
    for k in 0..3 {
        let asked = Instant::now();
        let refused = client.call(AddTwoIntsRequest { a: k, b: 1 }, 5 * SECOND);
        let took = asked.elapsed();
        match &refused {
            Err(ServiceError::Transport(message)) => {
                assert!(
                    message.contains("rmw_fastrtps") && message.contains("rustdds"),
                    "the refusal on {backend} must name rmw_fastrtps and the rustdds backend: \
                     {message}"
                );
            }
            other => panic!(
                "call {k} on the {backend} backend: expected a Transport refusal, got {other:?}; \
                 peer output:\n{}",
                peer.output()
            ),
        }
        assert!(took < REFUSAL_LIMIT, "call {k} refused only after {took:?}");
    }
    assert_eq!(client.pending_requests(), 0);
    let asked = Instant::now();
    assert!(!client.wait_for_service(10 * SECOND));
    assert!(
        asked.elapsed() < REFUSAL_LIMIT,
        "wait_for_service took {:?}",
        asked.elapsed()
    );
    // Nothing reached the Fast DDS server: it never printed a served request.
    let quiet_until = Instant::now() + SECOND;
    while Instant::now() < quiet_until {
        if let Some(line) = peer.next_line(Duration::from_millis(100)) {
            assert!(
                Served::parse(&line).is_none(),
                "the Fast DDS server got a request from the {backend} backend: {line}"
            );
        }
    }
}

#[test]
fn a_fastdds_client_calls_our_server() {
    const DOMAIN: u32 = 63;
    const SERVICE: &str = "/horus_ns/add_two_ints";
    const CALLS: u32 = 5;
    let (context, node) = node(DOMAIN, "horus_server");
    let refusing = !context.backend().carries_sample_identity();
    let server = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&node)
        .name(SERVICE)
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");

    let started = Instant::now();
    let mut peer = FastDdsPeer::start_calling(
        DOMAIN,
        "/fast_ns",
        "fast_client",
        SERVICE,
        // Refused, the client waits for its first reply until this ends.
        Duration::from_secs(if refusing { 6 } else { 12 }),
        CALLS,
    )
    .expect("build and start the Fast DDS peer");
    let created = peer
        .created(10 * SECOND)
        .expect("the peer says what it created");
    assert_eq!(created.json["mode"], "call");
    assert_eq!(created.request_topic, "rq/horus_ns/add_two_intsRequest");
    assert_eq!(created.reply_topic, "rr/horus_ns/add_two_intsReply");
    assert!(created.server_request_reader.is_empty() && created.server_reply_writer.is_empty());

    let (code, lines) = peer.finish(15 * SECOND).expect("wait for the peer");
    let output = peer.output();
    eprintln!("the peer finished {:?} after it started", started.elapsed());

    let parsed: Vec<Value> = lines
        .iter()
        .map(|l| serde_json::from_str(l).unwrap_or(Value::Null))
        .collect();
    let replies: Vec<&Value> = parsed.iter().filter(|v| v.get("sum").is_some()).collect();
    let summary = parsed
        .iter()
        .find_map(|v| v.get("summary"))
        .unwrap_or_else(|| panic!("no summary; output:\n{output}"));
    if refusing {
        // Our server was there for it (matched as rmw_fastrtps checks), but its request, which
        // needs an answer through related_sample_identity, was dropped: no reply ever came, and
        // the handler never ran.
        assert_eq!(
            code,
            Some(1),
            "the Fast DDS client must get no reply; output:\n{output}"
        );
        assert!(replies.is_empty(), "output:\n{output}");
        assert_eq!(summary["calls"], CALLS, "{output}");
        assert_eq!(summary["available"], true, "{output}");
        assert_eq!(summary["answered"], 0, "{output}");
        assert_eq!(summary["correct"], 0, "{output}");
        assert_eq!(server.served_count(), 0);
        assert_eq!(server.failed_count(), 0);
        return;
    }
    assert_eq!(
        code,
        Some(0),
        "the Fast DDS client failed; output:\n{output}"
    );
    assert_eq!(replies.len(), CALLS as usize, "output:\n{output}");
    for (k, reply) in replies.iter().enumerate() {
        let i = k as i64 + 1;
        assert_eq!(reply["a"], i, "output:\n{output}");
        assert_eq!(reply["b"], 10 * i, "output:\n{output}");
        assert_eq!(reply["sum"], 11 * i, "output:\n{output}");
        // __rmw_send_request: the sequence number Fast DDS gave the request sample (its fresh
        // request writer's k-th), which our reply's related_sample_identity carried back.
        assert_eq!(reply["sequence_number"], i, "output:\n{output}");
    }
    assert_eq!(summary["calls"], CALLS, "{output}");
    assert_eq!(summary["correct"], CALLS, "{output}");
    assert_eq!(summary["available"], true, "{output}");

    assert_eq!(server.served_count(), u64::from(CALLS));
    assert_eq!(server.failed_count(), 0);
}
