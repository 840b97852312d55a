//! The raw, non-blocking service traits over DDS (run inside the test network namespace):
//! [`DdsServiceServer`] / [`DdsServiceClient`] with each other and with the ordinary
//! [`ServiceClient`] / [`ServiceServerBuilder`], in both wire conventions. Domains 91-95; every
//! wait is bounded.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::task::{Wake, Waker};
use std::thread::Thread;
use std::time::{Duration, Instant};

use horus_ros_msgs::cdr::{from_cdr, to_cdr};
use horus_ros_services::prelude::*;
use horus_ros_services::{
    DdsServiceClient, DdsServiceServer, ServiceClientTrait, ServiceServerTrait, TransportError,
};

const SECOND: Duration = Duration::from_secs(1);
const WAIT: Duration = Duration::from_secs(10);

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

/// Polls `f` every millisecond until it gives `Some`, at most `timeout`.
fn until<T>(timeout: Duration, mut f: impl FnMut() -> Option<T>) -> Option<T> {
    let deadline = Instant::now() + timeout;
    loop {
        if let Some(value) = f() {
            return Some(value);
        }
        if Instant::now() >= deadline {
            return None;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Polls discovery until it ends; its answer.
fn discover(client: &mut DdsServiceClient<AddTwoInts>, timeout_ms: u32) -> Option<bool> {
    client
        .start_server_discovery(timeout_ms)
        .expect("start discovery");
    until(
        Duration::from_millis(u64::from(timeout_ms)) + 5 * SECOND,
        || client.poll_server_discovery().expect("poll discovery"),
    )
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

/// Serves requests with `handle_request` until `done` says stop, at most `timeout`.
fn serve_until(
    server: &mut DdsServiceServer<AddTwoInts>,
    timeout: Duration,
    mut done: impl FnMut() -> bool,
) -> usize {
    let (mut req_buf, mut reply_buf) = ([0u8; 256], [0u8; 256]);
    let mut served = 0;
    until(timeout, || {
        if server
            .handle_request::<AddTwoInts>(&mut req_buf, &mut reply_buf, |r| AddTwoIntsResponse {
                sum: r.a + r.b,
            })
            .expect("handle_request")
        {
            served += 1;
        }
        done().then_some(())
    });
    served
}

/// Polls the raw client for its typed reply, at most `timeout`.
fn reply_of(
    client: &mut DdsServiceClient<AddTwoInts>,
    timeout: Duration,
) -> Option<Result<AddTwoIntsResponse, TransportError>> {
    let mut buf = [0u8; 256];
    until(timeout, || {
        client.try_recv_reply::<AddTwoInts>(&mut buf).transpose()
    })
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
    assert_eq!(discover(&mut client, 10_000), Some(true));
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
    serve_until(&mut server, WAIT, || {
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
    let handled = until(WAIT, || {
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

    // The deprecated blocking calls keep the seed's default: Timeout at once.
    #[allow(deprecated)]
    {
        assert_eq!(
            client.call_raw(&raw, &mut reply_buf),
            Err(TransportError::Timeout)
        );
        assert_eq!(
            client.call::<AddTwoInts>(
                &AddTwoIntsRequest { a: 1, b: 1 },
                &mut req_buf,
                &mut reply_buf
            ),
            Err(TransportError::Timeout)
        );
    }
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
    let caller = std::thread::spawn(move || {
        let results: Vec<_> = (0..5)
            .map(|i| client.call(AddTwoIntsRequest { a: i, b: 100 }, WAIT))
            .collect();
        results
    });
    let served = serve_until(&mut server, 3 * WAIT, || caller.is_finished());
    let results = caller.join().expect("caller thread");
    assert_eq!(served, 5);
    for (i, result) in (0..5).zip(results) {
        assert_eq!(result, Ok(AddTwoIntsResponse { sum: i + 100 }));
    }

    // An ordinary server answers the raw client, and its handler errors reach it.
    let _ordinary = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&a)
        .name("/mixed_two")
        .on_request(|r| match r.a {
            0 => Err("a must not be zero".to_owned()),
            _ => Ok(AddTwoIntsResponse { sum: r.a - r.b }),
        })
        .build()
        .expect("server");
    let mut client = raw_client(&b, "/mixed_two");
    assert_eq!(discover(&mut client, 10_000), Some(true));
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
    assert_eq!(discover(&mut client, 300), Some(false));
    assert!(started.elapsed() >= Duration::from_millis(300));

    // A request sent before any server exists is queued, and sent once one is ready.
    let mut buf = [0u8; 64];
    client
        .send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 20, b: 22 }, &mut buf)
        .expect("queued");
    assert_eq!(client.try_recv_reply_raw(&mut buf), Ok(None));
    let mut server = raw_server(&b, "/later");
    assert_eq!(discover(&mut client, 10_000), Some(true));
    assert_eq!(client.server_available(), Ok(true));
    assert!(client.is_server_ready());
    let mut reply = None;
    serve_until(&mut server, WAIT, || {
        reply = client.try_recv_reply::<AddTwoInts>(&mut buf).expect("recv");
        reply.is_some()
    });
    assert_eq!(reply, Some(AddTwoIntsResponse { sum: 42 }));

    // The server leaves: availability drops.
    drop(server);
    assert!(
        until(WAIT, || (client.server_available() == Ok(false))
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
    let caller = std::thread::spawn(move || {
        (0..3)
            .map(|i| client.call(AddTwoIntsRequest { a: i, b: 1 }, WAIT))
            .collect::<Vec<_>>()
    });
    serve_until(&mut server, 3 * WAIT, || caller.is_finished());
    let results = caller.join().expect("caller thread");
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
    assert_eq!(discover(&mut raw, 10_000), Some(true));
    let mut buf = [0u8; 64];
    raw.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 5, b: 6 }, &mut buf)
        .expect("send");
    let mut req_buf = [0u8; 64];
    let (sequence_number, data) = until(WAIT, || {
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
    let _ordinary = ServiceServerBuilder::<AddTwoInts>::new()
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
    assert_eq!(discover(&mut raw, 10_000), Some(true));
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
    assert_eq!(discover(&mut client, 10_000), Some(true));
    let (mut buf, mut req_buf) = ([0u8; 64], [0u8; 64]);
    let mut take = |server: &mut DdsServiceServer<AddTwoInts>| {
        until(WAIT, || {
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
        assert_eq!(discover(c, 10_000), Some(true));
        c.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: i, b: 1000 }, &mut buf)
            .expect("send");
    }
    let mut got: Vec<Option<AddTwoIntsResponse>> = vec![None; clients.len()];
    serve_until(&mut server, WAIT, || {
        for (c, slot) in clients.iter_mut().zip(got.iter_mut()) {
            if slot.is_none() {
                *slot = c.try_recv_reply::<AddTwoInts>(&mut buf).expect("recv");
            }
        }
        got.iter().all(Option::is_some)
    });
    for (i, reply) in (0i64..).zip(got) {
        assert_eq!(reply, Some(AddTwoIntsResponse { sum: i + 1000 }));
    }
}
