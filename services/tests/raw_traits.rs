//! The raw, non-blocking service traits over DDS (run inside the test network namespace):
//! [`DdsServiceServer`] / [`DdsServiceClient`] with each other and with the ordinary
//! [`ServiceClient`] / [`ServiceServerBuilder`], in both wire conventions. Domains 91-95; every
//! wait is bounded, and event-driven: a thread waits parked, woken by the endpoints' wakers or by
//! graph changes, never by a polling interval.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Weak};
use std::task::{Wake, Waker};
use std::thread::Thread;
use std::time::{Duration, Instant};

use horus_ros_graph::{Graph, GraphView, GraphWatcher};
use horus_ros_msgs::cdr::{from_cdr, to_cdr};
use horus_ros_services::prelude::*;
use horus_ros_services::{
    DdsServiceClient, DdsServiceServer, ServiceClientTrait, ServiceServerTrait, TransportError,
};

const SECOND: Duration = Duration::from_secs(1);
const WAIT: Duration = Duration::from_secs(10);
/// How long the rustdds backend gives an rmw_cyclonedds server's reply writer to match a client's
/// reader after the graph shows the match (`CYCLONE_MATCH_SETTLE` in the client core, 100 ms,
/// with a margin): no event marks its end.
const SETTLE: Duration = Duration::from_millis(250);

/// A node in its own context (its own DDS participant) on `domain`.
fn node(domain: u32, name: &str) -> Node {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    context.create_node(name, "/").expect("node")
}

fn raw_server(node: &Node, name: &str) -> DdsServiceServer<AddTwoInts> {
    DdsServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .build()
        .expect("raw server")
}

fn raw_client(node: &Node, name: &str) -> DdsServiceClient<AddTwoInts> {
    DdsServiceClient::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .build()
        .expect("raw client")
}

/// Unparks the thread that made it: as a waker, and as a watcher of a graph.
struct Unparker(Thread);

impl Unparker {
    fn new() -> Arc<Self> {
        Arc::new(Self(std::thread::current()))
    }
}

impl Wake for Unparker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

impl GraphWatcher for Unparker {
    fn graph_changed(&self, _graph: &GraphView<'_>) {
        self.0.unpark();
    }
}

/// Looks with `look` until it gives `Some`, at most `timeout`, parked in between: `look` is given
/// a waker that unparks this thread, registers it with every endpoint whose event it waits for
/// (`register_waker`) and then looks, so an event after the look ends the park that follows.
fn until<T>(timeout: Duration, look: impl FnMut(&Waker) -> Option<T>) -> Option<T> {
    wait_for(None, timeout, None, look)
}

/// [`until`], also woken by every change of `node`'s graph (what availability and readiness
/// follow), by the instant [`SETTLE`] after the last one, and at `also_at`, if given.
fn until_graph<T>(
    node: &Node,
    timeout: Duration,
    also_at: Option<Instant>,
    look: impl FnMut(&Waker) -> Option<T>,
) -> Option<T> {
    let graph = Graph::of(node.context()).expect("graph");
    wait_for(Some(&graph), timeout, also_at, look)
}

fn wait_for<T>(
    graph: Option<&Graph>,
    timeout: Duration,
    also_at: Option<Instant>,
    mut look: impl FnMut(&Waker) -> Option<T>,
) -> Option<T> {
    let deadline = Instant::now() + timeout;
    let unparker = Unparker::new();
    if let Some(graph) = graph {
        let watcher: Weak<dyn GraphWatcher> = Arc::downgrade(&unparker) as _;
        graph.watch(watcher);
    }
    let waker = Waker::from(Arc::clone(&unparker));
    loop {
        if let Some(value) = look(&waker) {
            return Some(value);
        }
        let now = Instant::now();
        if now >= deadline {
            return None;
        }
        let settled = graph.map(|g| g.last_change() + SETTLE);
        let wake_at = [settled, also_at]
            .into_iter()
            .flatten()
            .filter(|&at| at > now)
            .fold(deadline, Instant::min);
        // Spurious wake-ups (an earlier waker firing late) only make it look again.
        std::thread::park_timeout(wake_at - now);
    }
}

/// Waits for discovery to end (woken by graph changes, and at the query's end); its answer.
fn discover(
    node: &Node,
    client: &mut DdsServiceClient<AddTwoInts>,
    timeout_ms: u32,
) -> Option<bool> {
    let query = Duration::from_millis(u64::from(timeout_ms));
    let ends = Instant::now() + query;
    client
        .start_server_discovery(timeout_ms)
        .expect("start discovery");
    until_graph(node, query + 5 * SECOND, Some(ends), |_| {
        client.poll_server_discovery().expect("poll discovery")
    })
}

/// A waker that raises a flag and unparks the thread that made it.
struct Flag {
    raised: AtomicBool,
    thread: Thread,
}

impl Flag {
    fn new() -> Arc<Self> {
        Arc::new(Self {
            raised: AtomicBool::new(false),
            thread: std::thread::current(),
        })
    }

    fn waker(self: &Arc<Self>) -> Waker {
        Waker::from(Arc::clone(self))
    }

    /// Parks until the flag is raised, at most `timeout`; whether it was.
    fn wait(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        while !self.raised.load(Ordering::SeqCst) {
            let now = Instant::now();
            if now >= deadline {
                return false;
            }
            std::thread::park_timeout(deadline - now);
        }
        true
    }
}

impl Wake for Flag {
    fn wake(self: Arc<Self>) {
        self.raised.store(true, Ordering::SeqCst);
        self.thread.unpark();
    }
}

/// Serves requests with `handle_request` until `done` says stop, at most `timeout`: woken by the
/// server's waker, and by whatever `done` registers the waker it is given with.
fn serve_until(
    server: &mut DdsServiceServer<AddTwoInts>,
    timeout: Duration,
    mut done: impl FnMut(&Waker) -> bool,
) -> usize {
    let (mut req_buf, mut reply_buf) = ([0u8; 256], [0u8; 256]);
    let mut served = 0;
    until(timeout, |waker| {
        server.register_waker(waker);
        if server
            .handle_request::<AddTwoInts>(&mut req_buf, &mut reply_buf, |r| AddTwoIntsResponse {
                sum: r.a + r.b,
            })
            .expect("handle_request")
        {
            served += 1;
        }
        done(waker).then_some(())
    });
    served
}

/// Waits for the raw client's typed reply (woken by its waker), at most `timeout`.
fn reply_of(
    client: &mut DdsServiceClient<AddTwoInts>,
    timeout: Duration,
) -> Option<Result<AddTwoIntsResponse, TransportError>> {
    let mut buf = [0u8; 256];
    until(timeout, |waker| {
        client.register_waker(waker);
        client.try_recv_reply::<AddTwoInts>(&mut buf).transpose()
    })
}

/// Runs `calls` on a thread of its own; the results come back on the channel, and the thread
/// that spawned it is unparked then (a `serve_until` waiting for them looks again).
fn on_a_thread<T: Send + 'static>(
    calls: impl FnOnce() -> T + Send + 'static,
) -> (std::thread::JoinHandle<()>, mpsc::Receiver<T>) {
    let (tx, rx) = mpsc::channel();
    let waiting = std::thread::current();
    let handle = std::thread::spawn(move || {
        let _ = tx.send(calls());
        waiting.unpark();
    });
    (handle, rx)
}

#[test]
fn a_raw_server_and_a_raw_client_talk_typed_and_raw() {
    let (a, b) = (node(91, "raw_server"), node(91, "raw_client"));
    let mut server = raw_server(&a, "/raw_add");
    let mut client = raw_client(&b, "raw_add");
    assert_eq!(client.name().as_str(), "/raw_add");
    assert!(!server.has_request());
    let (mut req_buf, mut reply_buf) = ([0u8; 256], [0u8; 256]);
    assert_eq!(
        server.try_recv_request(&mut req_buf).expect("nothing yet"),
        None
    );
    assert_eq!(discover(&b, &mut client, 10_000), Some(true));
    assert!(client.is_server_ready());
    assert_eq!(client.server_available(), Ok(true));

    // Typed request; the server's waker fires and has_request does not consume.
    let server_flag = Flag::new();
    ServiceServerTrait::register_waker(&server, &server_flag.waker());
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 2, b: 3 }, &mut req_buf)
        .expect("send");
    assert!(server_flag.wait(WAIT), "the server's waker never fired");
    assert!(server.has_request());
    assert!(server.has_request(), "has_request consumed the request");

    // Too small a buffer: an error, and the request stays.
    let mut tiny = [0u8; 8];
    assert_eq!(
        server.try_recv_request(&mut tiny),
        Err(TransportError::BufferTooSmall {
            needed: 20,
            capacity: 8
        })
    );
    assert!(server.has_request());
    let request = server
        .try_recv_request(&mut req_buf)
        .expect("take")
        .expect("a request");
    let sequence_number = request.sequence_number;
    assert_eq!(&request.data[..4], &[0, 1, 0, 0], "CDR_LE encapsulation");
    let decoded: AddTwoIntsRequest = from_cdr(request.data).expect("decode");
    assert_eq!(decoded, AddTwoIntsRequest { a: 2, b: 3 });
    assert!(!server.has_request());
    assert_eq!(server.outstanding_requests(), 1);

    // Unknown sequence numbers are refused; the real one is answered exactly once.
    let reply = to_cdr(&AddTwoIntsResponse { sum: 5 }).expect("encode");
    assert_eq!(
        server.send_reply(sequence_number + 1000, &reply),
        Err(TransportError::UnknownRequest(sequence_number + 1000))
    );
    let client_flag = Flag::new();
    ServiceClientTrait::register_waker(&client, &client_flag.waker());
    server.send_reply(sequence_number, &reply).expect("reply");
    assert_eq!(
        server.send_reply(sequence_number, &reply),
        Err(TransportError::UnknownRequest(sequence_number))
    );
    assert_eq!(server.outstanding_requests(), 0);
    assert!(client_flag.wait(WAIT), "the client's waker never fired");

    // Too small a reply buffer keeps the reply; then the typed path decodes it.
    assert_eq!(
        client.try_recv_reply_raw(&mut tiny),
        Err(TransportError::BufferTooSmall {
            needed: 12,
            capacity: 8
        })
    );
    assert_eq!(
        client.try_recv_reply::<AddTwoInts>(&mut reply_buf),
        Ok(Some(AddTwoIntsResponse { sum: 5 }))
    );
    assert_eq!(client.try_recv_reply_raw(&mut reply_buf), Ok(None));

    // Raw bytes in, raw bytes out; the server side through handle_request.
    let raw = to_cdr(&AddTwoIntsRequest { a: 40, b: 2 }).expect("encode");
    client.send_request_raw(&raw).expect("send raw");
    let mut len = None;
    serve_until(&mut server, WAIT, |waker| {
        client.register_waker(waker);
        len = client.try_recv_reply_raw(&mut reply_buf).expect("recv raw");
        len.is_some()
    });
    let len = len.expect("a raw reply");
    assert_eq!(&reply_buf[..4], &[0, 1, 0, 0]);
    assert_eq!(
        from_cdr::<AddTwoIntsResponse>(&reply_buf[..len]).expect("decode"),
        AddTwoIntsResponse { sum: 42 }
    );

    // handle_request_boxed, and Ok(false) when nothing waits.
    assert_eq!(
        server.handle_request::<AddTwoInts>(&mut req_buf, &mut reply_buf, |_| unreachable!()),
        Ok(false)
    );
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 7, b: 8 }, &mut req_buf)
        .expect("send");
    let handled = until(WAIT, |waker| {
        server.register_waker(waker);
        server
            .handle_request_boxed::<AddTwoInts>(&mut req_buf, &mut reply_buf, |r| {
                Box::new(AddTwoIntsResponse { sum: r.a * r.b })
            })
            .expect("handle boxed")
            .then_some(())
    });
    assert!(handled.is_some());
    assert_eq!(
        reply_of(&mut client, WAIT),
        Some(Ok(AddTwoIntsResponse { sum: 56 }))
    );

    // A request that does not fit the caller's buffer is refused before sending.
    assert!(matches!(
        client.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 1, b: 1 }, &mut [0u8; 4]),
        Err(TransportError::BufferTooSmall { needed: 20, .. })
    ));
    // So is a payload that is not CDR.
    assert!(matches!(
        client.send_request_raw(&[0, 1]),
        Err(TransportError::Serialization(_))
    ));

    // The deprecated blocking calls: not the seed's default (Timeout at once, without trying),
    // but a call, woken by its reply, while another thread serves.
    let serving = std::thread::spawn(move || {
        let (mut req_buf, mut reply_buf) = ([0u8; 256], [0u8; 256]);
        let mut handled = 0;
        let served = until(WAIT, |waker| {
            server.register_waker(waker);
            while server
                .handle_request::<AddTwoInts>(&mut req_buf, &mut reply_buf, |r| {
                    AddTwoIntsResponse { sum: r.a + r.b }
                })
                .expect("handle")
            {
                handled += 1;
            }
            (handled == 2).then_some(())
        });
        assert!(served.is_some(), "served {handled} of the 2 blocking calls");
        // Kept until the calls have their replies: a server dropped right after its last
        // reply may leave before the reply is delivered (ServerGone, as with rclcpp).
        server
    });
    #[allow(deprecated)]
    {
        let len = client.call_raw(&raw, &mut reply_buf).expect("call_raw");
        assert_eq!(
            from_cdr::<AddTwoIntsResponse>(&reply_buf[..len]).expect("decode"),
            AddTwoIntsResponse { sum: 42 }
        );
        assert_eq!(
            client.call::<AddTwoInts>(
                &AddTwoIntsRequest { a: 1, b: 1 },
                &mut req_buf,
                &mut reply_buf
            ),
            Ok(AddTwoIntsResponse { sum: 2 })
        );
    }
    let server = serving.join().expect("the serving thread");
    drop(server);

    // With no server, a blocking call ends at the client's send timeout with NoServer.
    let mut lonely = DdsServiceClient::<AddTwoInts>::builder()
        .node(&b)
        .name("/raw_add_nobody")
        .send_timeout(Duration::from_millis(300))
        .build()
        .expect("raw client");
    let started = Instant::now();
    #[allow(deprecated)]
    let outcome = lonely.call_raw(&raw, &mut reply_buf);
    assert_eq!(outcome, Err(TransportError::NoServer));
    assert!(
        started.elapsed() >= Duration::from_millis(300),
        "not before the send timeout"
    );
}

#[test]
fn raw_endpoints_talk_with_the_ordinary_client_and_server() {
    let (a, b) = (node(92, "ordinary"), node(92, "raw"));

    // A raw server answers an ordinary ServiceClient.
    let mut server = raw_server(&b, "/mixed_one");
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&a)
        .name("/mixed_one")
        .build()
        .expect("client");
    let (caller, calls) = on_a_thread(move || {
        (0..5)
            .map(|i| client.call(AddTwoIntsRequest { a: i, b: 100 }, WAIT))
            .collect::<Vec<_>>()
    });
    let mut results = None;
    let served = serve_until(&mut server, 3 * WAIT, |_| {
        results = calls.try_recv().ok();
        results.is_some()
    });
    caller.join().expect("caller thread");
    let results = results.expect("the calls never ended");
    assert_eq!(served, 5);
    for (i, result) in (0..5).zip(results) {
        assert_eq!(result, Ok(AddTwoIntsResponse { sum: i + 100 }));
    }

    // An ordinary server answers the raw client, and its handler errors reach it.
    let _ordinary = ServiceServer::<AddTwoInts>::builder()
        .node(&a)
        .name("/mixed_two")
        .on_request(|r| match r.a {
            0 => Err("a must not be zero".to_owned()),
            _ => Ok(AddTwoIntsResponse { sum: r.a - r.b }),
        })
        .build()
        .expect("server");
    let mut client = raw_client(&b, "/mixed_two");
    assert_eq!(discover(&b, &mut client, 10_000), Some(true));
    let mut buf = [0u8; 64];
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 10, b: 3 }, &mut buf)
        .expect("send");
    assert_eq!(
        reply_of(&mut client, WAIT),
        Some(Ok(AddTwoIntsResponse { sum: 7 }))
    );
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 0, b: 3 }, &mut buf)
        .expect("send");
    assert_eq!(
        reply_of(&mut client, WAIT),
        Some(Err(TransportError::ServiceFailed(
            "a must not be zero".to_owned()
        )))
    );
}

#[test]
fn discovery_and_availability_follow_the_graph() {
    let (a, b) = (node(93, "disc_client"), node(93, "disc_server"));
    let mut client = raw_client(&a, "/later");
    assert_eq!(client.server_available(), Ok(false));
    assert!(!client.is_server_ready());
    let started = Instant::now();
    assert_eq!(discover(&a, &mut client, 300), Some(false));
    assert!(started.elapsed() >= Duration::from_millis(300));

    // A request sent before any server exists is queued, and sent once one is ready.
    let mut buf = [0u8; 64];
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 20, b: 22 }, &mut buf)
        .expect("queued");
    assert_eq!(client.try_recv_reply_raw(&mut buf), Ok(None));
    let mut server = raw_server(&b, "/later");
    assert_eq!(discover(&a, &mut client, 10_000), Some(true));
    assert_eq!(client.server_available(), Ok(true));
    assert!(client.is_server_ready());
    let mut reply = None;
    serve_until(&mut server, WAIT, |waker| {
        client.register_waker(waker);
        reply = client.try_recv_reply::<AddTwoInts>(&mut buf).expect("recv");
        reply.is_some()
    });
    assert_eq!(reply, Some(AddTwoIntsResponse { sum: 42 }));

    // The server leaves: availability drops (a graph change).
    drop(server);
    assert!(
        until_graph(&a, WAIT, None, |_| (client.server_available() == Ok(false))
            .then_some(()))
        .is_some(),
        "the dropped server stayed available"
    );
    assert!(!client.is_server_ready());

    // A queued request gives up after the send timeout, waking the waker.
    let mut impatient = DdsServiceClient::<AddTwoInts>::builder()
        .node(&a)
        .name("/nobody")
        .send_timeout(Duration::from_millis(200))
        .build()
        .expect("client");
    let flag = Flag::new();
    impatient.register_waker(&flag.waker());
    impatient
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 1, b: 1 }, &mut buf)
        .expect("queued");
    assert!(flag.wait(WAIT), "the send timeout did not wake the waker");
    assert_eq!(
        impatient.try_recv_reply_raw(&mut buf),
        Err(TransportError::NoServer)
    );
    assert_eq!(impatient.try_recv_reply_raw(&mut buf), Ok(None));
}

#[test]
fn the_rmw_cyclonedds_convention_works_both_ways() {
    let (a, b) = (node(94, "cyc_ordinary"), node(94, "cyc_raw"));

    // Raw server (Cyclone) ← ordinary client (Cyclone).
    let mut server = DdsServiceServer::<AddTwoInts>::builder()
        .node(&b)
        .name("/cyc_one")
        .wire_flavour(WireFlavour::CycloneDds)
        .build()
        .expect("raw server");
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&a)
        .name("/cyc_one")
        .wire_flavour(WireFlavour::CycloneDds)
        .build()
        .expect("client");
    let (caller, calls) = on_a_thread(move || {
        (0..3)
            .map(|i| client.call(AddTwoIntsRequest { a: i, b: 1 }, WAIT))
            .collect::<Vec<_>>()
    });
    let mut results = None;
    serve_until(&mut server, 3 * WAIT, |_| {
        results = calls.try_recv().ok();
        results.is_some()
    });
    caller.join().expect("caller thread");
    let results = results.expect("the calls never ended");
    for (i, result) in (0..3).zip(results) {
        assert_eq!(result, Ok(AddTwoIntsResponse { sum: i + 1 }));
    }

    // Raw client (Cyclone) → raw server (Cyclone): the request data has no rmw_cyclonedds header.
    let mut raw = DdsServiceClient::<AddTwoInts>::builder()
        .node(&a)
        .name("/cyc_one")
        .wire_flavour(WireFlavour::CycloneDds)
        .build()
        .expect("raw client");
    assert_eq!(discover(&a, &mut raw, 10_000), Some(true));
    let mut buf = [0u8; 64];
    raw.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 5, b: 6 }, &mut buf)
        .expect("send");
    let mut req_buf = [0u8; 64];
    let (sequence_number, data) = until(WAIT, |waker| {
        server.register_waker(waker);
        server
            .try_recv_request(&mut req_buf)
            .expect("take")
            .map(|r| (r.sequence_number, r.data.to_vec()))
    })
    .expect("a request");
    assert_eq!(data.len(), 20, "header stripped: {data:?}");
    let request: AddTwoIntsRequest = from_cdr(&data).expect("decode");
    let reply = to_cdr(&AddTwoIntsResponse {
        sum: request.a + request.b,
    })
    .expect("encode");
    server.send_reply(sequence_number, &reply).expect("reply");
    assert_eq!(
        reply_of(&mut raw, WAIT),
        Some(Ok(AddTwoIntsResponse { sum: 11 }))
    );

    // Ordinary server (Cyclone) → raw client (Cyclone).
    let _ordinary = ServiceServer::<AddTwoInts>::builder()
        .node(&b)
        .name("/cyc_two")
        .wire_flavour(WireFlavour::CycloneDds)
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a * r.b }))
        .build()
        .expect("server");
    let mut raw = DdsServiceClient::<AddTwoInts>::builder()
        .node(&a)
        .name("/cyc_two")
        .wire_flavour(WireFlavour::CycloneDds)
        .build()
        .expect("raw client");
    assert_eq!(discover(&a, &mut raw, 10_000), Some(true));
    raw.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 6, b: 7 }, &mut buf)
        .expect("send");
    assert_eq!(
        reply_of(&mut raw, WAIT),
        Some(Ok(AddTwoIntsResponse { sum: 42 }))
    );
}

#[test]
fn only_the_latest_request_is_answered_and_clients_get_their_own_replies() {
    let (a, b) = (node(95, "latest_server"), node(95, "latest_clients"));
    let mut server = raw_server(&a, "/latest");
    let mut client = raw_client(&b, "/latest");
    assert_eq!(discover(&b, &mut client, 10_000), Some(true));
    let (mut buf, mut req_buf) = ([0u8; 64], [0u8; 64]);
    let mut take = |server: &mut DdsServiceServer<AddTwoInts>| {
        until(WAIT, |waker| {
            server.register_waker(waker);
            server
                .try_recv_request(&mut req_buf)
                .expect("take")
                .map(|r| {
                    let req: AddTwoIntsRequest = from_cdr(r.data).expect("decode");
                    (r.sequence_number, req)
                })
        })
        .expect("a request")
    };
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 1, b: 0 }, &mut buf)
        .expect("send 1");
    let (first, _) = take(&mut server);
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 2, b: 0 }, &mut buf)
        .expect("send 2");
    let (second, req) = take(&mut server);
    assert_eq!(req.a, 2);
    assert_ne!(first, second);

    // The reply to the superseded request is dropped: both replies go out in order on one
    // reliable writer, so had the first been kept it would come before the second.
    let reply = |sum| to_cdr(&AddTwoIntsResponse { sum }).expect("encode");
    server.send_reply(first, &reply(1)).expect("reply 1");
    server.send_reply(second, &reply(2)).expect("reply 2");
    assert_eq!(
        reply_of(&mut client, WAIT),
        Some(Ok(AddTwoIntsResponse { sum: 2 }))
    );
    assert_eq!(client.try_recv_reply_raw(&mut buf), Ok(None));

    // Several raw clients at once, each gets only its own reply.
    let mut clients: Vec<_> = (0..4).map(|_| raw_client(&b, "/latest")).collect();
    for (i, c) in (0i64..).zip(clients.iter_mut()) {
        assert_eq!(discover(&b, c, 10_000), Some(true));
        c.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: i, b: 1000 }, &mut buf)
            .expect("send");
    }
    let mut got: Vec<Option<AddTwoIntsResponse>> = vec![None; clients.len()];
    serve_until(&mut server, WAIT, |waker| {
        for (c, slot) in clients.iter_mut().zip(got.iter_mut()) {
            if slot.is_none() {
                c.register_waker(waker);
                *slot = c.try_recv_reply::<AddTwoInts>(&mut buf).expect("recv");
            }
        }
        got.iter().all(Option::is_some)
    });
    for (i, reply) in (0i64..).zip(got) {
        assert_eq!(reply, Some(AddTwoIntsResponse { sum: i + 1000 }));
    }
}
