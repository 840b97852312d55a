//! Servers and clients of this crate talking to each other over DDS (run inside the test network
//! namespace). Each test has its own domain.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_services::prelude::*;
use horus_ros_services::{DdsServiceServer, ServiceServerTrait, SetupError};

const SECOND: Duration = Duration::from_secs(1);

fn node(domain: u32, name: &str) -> Node {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    context.create_node(name, "/").expect("node")
}

fn adder(node: &Node, name: &str) -> ServiceServer<AddTwoInts> {
    ServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
        .build()
        .expect("server")
}

fn client(node: &Node, name: &str) -> ServiceClient<AddTwoInts> {
    ServiceClient::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .build()
        .expect("client")
}

#[test]
fn a_call_gets_its_sum() {
    let n = node(81, "calls");
    let server = adder(&n, "/add_two_ints");
    let mut c = client(&n, "add_two_ints");
    assert!(c.wait_for_service(10 * SECOND));
    let reply = c
        .call(AddTwoIntsRequest { a: 2, b: 3 }, 5 * SECOND)
        .expect("call");
    assert_eq!(reply.sum, 5);
    assert_eq!(server.served_count(), 1);
    assert_eq!(c.pending_requests(), 0);
    assert_eq!(c.name().as_str(), "/add_two_ints");
}

#[test]
fn many_sequential_calls_are_fast() {
    let n = node(90, "speedy");
    let _server = adder(&n, "/speedy");
    let mut c = client(&n, "/speedy");
    assert!(c.wait_for_service(10 * SECOND));
    let start = Instant::now();
    for i in 0..200 {
        assert_eq!(
            c.call(AddTwoIntsRequest { a: i, b: 1 }, 5 * SECOND),
            Ok(AddTwoIntsResponse { sum: i + 1 })
        );
    }
    eprintln!("200 calls in {:?}", start.elapsed());
}

#[test]
fn handler_errors_and_panics_reach_the_client_quickly_and_the_server_keeps_serving() {
    let n = node(82, "failing");
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/picky")
        .on_request(|req| match req.a {
            0 => Err("a must not be zero".to_owned()),
            1 => panic!("boom"),
            _ => Ok(AddTwoIntsResponse { sum: req.a + req.b }),
        })
        .build()
        .expect("server");
    let mut c = client(&n, "/picky");
    assert!(c.wait_for_service(10 * SECOND));
    // The error reply ends the call: had the client waited for its timeout instead, the call
    // would have ended in Timeout.
    let err = c
        .call(AddTwoIntsRequest { a: 0, b: 1 }, 30 * SECOND)
        .expect_err("handler error");
    assert_eq!(
        err,
        ServiceError::ServiceFailed("a must not be zero".to_owned())
    );
    // A generous timeout: the default panic hook prints a symbolized backtrace first (tests
    // run with RUST_BACKTRACE=1), which takes seconds on a loaded machine.
    match c.call(AddTwoIntsRequest { a: 1, b: 1 }, 30 * SECOND) {
        Err(ServiceError::ServiceFailed(m)) => {
            assert!(m.contains("panicked") && m.contains("boom"), "{m}")
        }
        other => panic!("expected ServiceFailed for a panic, got {other:?}"),
    }
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 2, b: 2 }, 5 * SECOND),
        Ok(AddTwoIntsResponse { sum: 4 })
    );
    assert_eq!((server.served_count(), server.failed_count()), (1, 2));
    // Permanent failures are not retried.
    let err = c
        .call_resilient(AddTwoIntsRequest { a: 0, b: 0 }, SECOND)
        .expect_err("still failing");
    assert!(matches!(err, ServiceError::ServiceFailed(_)));
    assert_eq!(server.failed_count(), 3);
}

#[test]
fn without_a_server_calls_say_no_server_and_call_optional_says_none() {
    let n = node(83, "lonely");
    let mut c = client(&n, "/nobody_home");
    assert!(!c.server_available());
    // NoServer only once the call's timeout has passed without a server.
    let start = Instant::now();
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(300)),
        Err(ServiceError::NoServer)
    );
    assert!(start.elapsed() >= Duration::from_millis(300));
    assert_eq!(
        c.call_optional(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(300)),
        Ok(None)
    );
    assert_eq!(
        c.call_resilient(AddTwoIntsRequest::default(), Duration::from_millis(200)),
        Err(ServiceError::NoServer)
    );
    // NoServer is permanent: not retried. A retry would come only after a 60 s backoff, so an
    // answer well before that (one 200 ms attempt) means there was none.
    let (answer_tx, answer) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = answer_tx.send(c.call_resilient_with(
            AddTwoIntsRequest::default(),
            Duration::from_millis(200),
            RetryConfig::new(1, 60 * SECOND),
        ));
    });
    assert_eq!(
        answer.recv_timeout(30 * SECOND),
        Ok(Err(ServiceError::NoServer)),
        "NoServer was retried"
    );
}

#[test]
fn a_late_reply_is_dropped_and_the_next_call_gets_its_own() {
    let n = node(84, "slowpoke");
    let calls = Arc::new(AtomicUsize::new(0));
    let seen = Arc::clone(&calls);
    // The first request is answered only once the test releases it, after its call timed out.
    let (arrived_tx, arrived) = mpsc::channel();
    let (release_tx, released) = mpsc::channel::<()>();
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/slow")
        .on_request(move |req| {
            if seen.fetch_add(1, Ordering::SeqCst) == 0 {
                let _ = arrived_tx.send(());
                // Released by the test, or by its end (the sender dropped).
                let _ = released.recv();
            }
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("server");
    // Dropped before the server, which joins its thread: a failing assertion releases the handler.
    let release = release_tx;
    let mut c = client(&n, "/slow");
    assert!(c.wait_for_service(10 * SECOND));
    let start = Instant::now();
    let first = c.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(100));
    let took = start.elapsed();
    assert_eq!(first, Err(ServiceError::Timeout));
    assert!(
        took >= Duration::from_millis(100),
        "timed out early: {took:?}"
    );
    assert_eq!(
        arrived.recv_timeout(10 * SECOND),
        Ok(()),
        "the request reached the handler"
    );
    assert_eq!(
        c.pending_requests(),
        0,
        "a timed-out call leaves nothing behind"
    );
    release.send(()).expect("handler waiting");
    // The first (late) reply, sum 2, is sent before this call is answered and must not be taken
    // for it.
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 5, b: 5 }, 5 * SECOND),
        Ok(AddTwoIntsResponse { sum: 10 })
    );
    assert_eq!(c.pending_requests(), 0);
}

#[test]
fn call_resilient_retries_a_timeout() {
    let n = node(85, "retrying");
    let calls = Arc::new(AtomicUsize::new(0));
    let seen = Arc::clone(&calls);
    // The first request is answered only once the test releases it: when the retry is out.
    let (release_tx, released) = mpsc::channel::<()>();
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/flaky")
        .on_request(move |req| {
            if seen.fetch_add(1, Ordering::SeqCst) == 0 {
                // Released by the test, or by its end (the sender dropped).
                let _ = released.recv();
            }
            Ok(AddTwoIntsResponse { sum: req.a * req.b })
        })
        .build()
        .expect("server");
    // A raw server on the same service sees every request the client sends, and answers none.
    let mut observer = DdsServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/flaky")
        .build()
        .expect("observer");
    // Dropped before the server, which joins its thread: a failing assertion releases the handler.
    let release = release_tx;
    let mut c = client(&n, "/flaky");
    assert!(c.wait_for_service(10 * SECOND));
    let graph = Graph::of(n.context()).expect("graph");
    assert!(
        graph.wait_for_match(c.gids().0, observer.gids().0, 20 * SECOND),
        "the observer never matched the client"
    );
    let caller = std::thread::spawn(move || {
        c.call_resilient_with(
            AddTwoIntsRequest { a: 3, b: 4 },
            Duration::from_millis(500),
            RetryConfig::new(5, Duration::from_millis(20)),
        )
    });
    // The first attempt timed out when its retry goes out: then the handler is released.
    let mut buf = [0u8; 256];
    let mut seen_requests = 0;
    let deadline = Instant::now() + 20 * SECOND;
    let waker = std::task::Waker::from(Arc::new(Unparker(std::thread::current())));
    while seen_requests < 2 {
        observer.register_waker(&waker);
        if observer.try_recv_request(&mut buf).expect("take").is_some() {
            seen_requests += 1;
            continue;
        }
        let now = Instant::now();
        assert!(now < deadline, "saw {seen_requests} requests, no retry");
        std::thread::park_timeout(deadline - now);
    }
    release.send(()).expect("handler waiting");
    let reply = caller.join().expect("caller");
    assert_eq!(reply, Ok(AddTwoIntsResponse { sum: 12 }));
    assert!(
        calls.load(Ordering::SeqCst) >= 2,
        "the first attempt timed out, a retry answered"
    );
}

#[test]
fn a_server_dropped_mid_call_gives_the_client_an_error_within_its_timeout() {
    let n = node(86, "vanishing");
    let (handling_tx, handling_rx) = mpsc::channel();
    let (release_tx, released) = mpsc::channel::<()>();
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/vanishing")
        .on_request(move |req| {
            let _ = handling_tx.send(());
            // A slow handler: the server is stopped while it runs, and it finishes only once
            // the test releases it (or ends, dropping the sender).
            let _ = released.recv();
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("server");
    let mut c = client(&n, "/vanishing");
    assert!(c.wait_for_service(10 * SECOND));
    let (stopping_tx, stopping) = mpsc::channel();
    let stopper = std::thread::spawn(move || {
        // Stopped mid-call: once the handler has the request. Dropping it waits for the handler.
        let _ = handling_rx.recv_timeout(10 * SECOND);
        server.stop();
        let _ = stopping_tx.send(());
        drop(server);
    });
    // The server keeps its endpoints until its handler returns, after this call: a timeout,
    // at its deadline and not before.
    let start = Instant::now();
    let first = c.call(AddTwoIntsRequest { a: 1, b: 2 }, SECOND);
    let took = start.elapsed();
    let stopped_mid_call = stopping.recv_timeout(10 * SECOND);
    release_tx.send(()).expect("handler waiting");
    stopper.join().expect("stopper");
    assert_eq!(
        stopped_mid_call,
        Ok(()),
        "the request never reached the handler"
    );
    assert_eq!(first, Err(ServiceError::Timeout));
    assert!(took >= SECOND, "timed out early: {took:?}");
    // The server is gone: the next call fails (ServerGone when the request went out while its
    // endpoints were still being withdrawn) within its timeout, far from a hang.
    let start = Instant::now();
    let err = c
        .call(AddTwoIntsRequest { a: 1, b: 2 }, SECOND)
        .expect_err("no server any more");
    let took = start.elapsed();
    assert!(
        matches!(
            err,
            ServiceError::NoServer
                | ServiceError::Timeout
                | ServiceError::Transport(TransportError::ServerGone)
        ),
        "{err:?}"
    );
    assert!(took < 10 * SECOND, "the call hung: {took:?}");
}

#[test]
fn sixteen_clients_get_only_their_own_replies() {
    const CLIENTS: i64 = 16;
    const CALLS: i64 = 500;
    let n = node(87, "busy");
    let server = adder(&n, "/busy");
    let workers: Vec<_> = (0..CLIENTS)
        .map(|k| {
            let n = n.clone();
            std::thread::spawn(move || {
                let mut c = client(&n, "/busy");
                assert!(
                    c.wait_for_service(20 * SECOND),
                    "client {k} never saw the server"
                );
                for i in 0..CALLS {
                    let reply = c.call(
                        AddTwoIntsRequest {
                            a: k * 1_000_000,
                            b: i,
                        },
                        10 * SECOND,
                    );
                    assert_eq!(
                        reply,
                        Ok(AddTwoIntsResponse {
                            sum: k * 1_000_000 + i
                        }),
                        "client {k} call {i}"
                    );
                }
                c.pending_requests()
            })
        })
        .collect();
    for w in workers {
        assert_eq!(w.join().expect("worker"), 0);
    }
    assert_eq!(server.served_count(), (CLIENTS * CALLS) as u64);
}

/// The blocking clients of one context share one wait for replies (whichever caller waits
/// takes every client's replies): a caller whose reply is slow must not hold up the others, nor
/// strand them when it gives up.
#[test]
fn a_caller_with_a_slow_reply_neither_holds_up_nor_strands_the_other_clients_of_its_context() {
    let n = node(96, "sharing");
    // The slow service answers only once the test releases each request.
    let (arrived_tx, arrived) = std::sync::mpsc::channel::<i64>();
    let (release, released) = std::sync::mpsc::channel::<()>();
    let released = std::sync::Mutex::new(released);
    let _slow = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/slow")
        .on_request(move |req| {
            arrived_tx.send(req.a).expect("test alive");
            released.lock().expect("lock").recv().expect("released");
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("server");
    let _fast = adder(&n, "/fast");
    let mut slow = client(&n, "/slow");
    let mut fast = client(&n, "/fast");
    assert!(slow.wait_for_service(20 * SECOND) && fast.wait_for_service(20 * SECOND));

    // 1. While a caller waits 30 s for the slow reply, other clients' calls are answered.
    let waiting = std::thread::spawn(move || {
        let reply = slow.call(AddTwoIntsRequest { a: 1, b: 1 }, 30 * SECOND);
        (slow, reply)
    });
    assert_eq!(arrived.recv_timeout(20 * SECOND), Ok(1));
    for i in 0..50 {
        assert_eq!(
            fast.call(AddTwoIntsRequest { a: i, b: 2 }, 10 * SECOND),
            Ok(AddTwoIntsResponse { sum: i + 2 })
        );
    }
    release.send(()).expect("handler alive");
    let (mut slow, reply) = waiting.join().expect("caller");
    assert_eq!(reply, Ok(AddTwoIntsResponse { sum: 2 }));

    // 2. A caller that gives up leaves the others able to get their replies: this one times out
    // while another waits for a reply that comes only after.
    let mut second = client(&n, "/slow");
    assert!(second.wait_for_service(20 * SECOND));
    let giving_up = std::thread::spawn(move || {
        slow.call(
            AddTwoIntsRequest { a: 10, b: 0 },
            Duration::from_millis(300),
        )
    });
    assert_eq!(arrived.recv_timeout(20 * SECOND), Ok(10));
    let patient =
        std::thread::spawn(move || second.call(AddTwoIntsRequest { a: 20, b: 0 }, 30 * SECOND));
    assert_eq!(
        giving_up.join().expect("caller"),
        Err(ServiceError::Timeout)
    );
    // The request of 10 is answered (late, dropped), then the one of 20.
    release.send(()).expect("handler alive");
    assert_eq!(arrived.recv_timeout(20 * SECOND), Ok(20));
    release.send(()).expect("handler alive");
    assert_eq!(
        patient.join().expect("caller"),
        Ok(AddTwoIntsResponse { sum: 20 })
    );
}

#[test]
fn async_calls_can_be_checked_waited_and_awaited() {
    let n = node(88, "asyncer");
    let _server = adder(&n, "/async_add");
    let c = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/async_add")
        .build()
        .expect("client");
    // Sent before any server is matched: waiting sends it once one is.
    let first = c.call_async(AddTwoIntsRequest { a: 1, b: 2 }, 10 * SECOND);
    assert!(!first.is_expired());
    assert_eq!(first.wait(), Ok(AddTwoIntsResponse { sum: 3 }));
    // check() gives a reply that is in at once, and only once. The server answers in order and
    // the client's reply thread routes the replies in order: once a later call's reply is in, so
    // is this one's.
    let mut checked = c.call_async(AddTwoIntsRequest { a: 2, b: 5 }, 5 * SECOND);
    assert_eq!(
        c.call_async(AddTwoIntsRequest { a: 4, b: 5 }, 5 * SECOND)
            .wait(),
        Ok(AddTwoIntsResponse { sum: 9 })
    );
    assert_eq!(checked.check(), Ok(Some(AddTwoIntsResponse { sum: 7 })));
    assert_eq!(checked.check(), Ok(None));
    assert!(!checked.is_expired());
    let many: Vec<_> = (0..20)
        .map(|i| c.call_async(AddTwoIntsRequest { a: i, b: i }, 5 * SECOND))
        .collect();
    for (i, p) in many.into_iter().enumerate() {
        assert_eq!(block_on(p), Ok(AddTwoIntsResponse { sum: 2 * i as i64 }));
    }
    let missing = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/missing")
        .build()
        .expect("client");
    let pending = missing.call_async(AddTwoIntsRequest::default(), Duration::from_millis(200));
    assert_eq!(block_on(pending), Err(ServiceError::NoServer));
}

#[test]
fn a_server_needs_a_handler() {
    let n = node(89, "nohandler");
    assert!(matches!(
        ServiceServer::<AddTwoInts>::builder().node(&n).build(),
        Err(SetupError::NoHandler)
    ));
    assert!(matches!(
        ServiceServer::<AddTwoInts>::builder()
            .node(&n)
            .name("bad name")
            .on_request(|_| Ok(Default::default()))
            .build(),
        Err(SetupError::InvalidName { .. })
    ));
}

/// One [`EndpointOptions`] given to every kind of builder: each endpoint gets its node and name,
/// and `AsyncServiceClient::builder().build()` is an async client with the blocking client's
/// readiness words.
#[test]
fn one_set_of_endpoint_options_serves_every_builder() {
    let n = node(125, "shared_options");
    let options = EndpointOptions::default().node(&n).name("/shared_options");
    let server = ServiceServer::<AddTwoInts>::builder()
        .options(options.clone())
        .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
        .build()
        .expect("server");
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .options(options.clone())
        .build()
        .expect("client");
    let pending_client: AsyncServiceClient<AddTwoInts> =
        AsyncServiceClient::<AddTwoInts>::builder()
            .options(options.clone())
            .build()
            .expect("async client");
    let raw = DdsServiceServer::<AddTwoInts>::builder()
        .options(options)
        .name("/shared_options_raw")
        .build()
        .expect("raw server");
    assert_eq!(server.name().as_str(), "/shared_options");
    assert_eq!(client.name().as_str(), "/shared_options");
    assert_eq!(pending_client.name().as_str(), "/shared_options");
    assert_eq!(raw.name().as_str(), "/shared_options_raw");

    assert!(client.wait_for_service(10 * SECOND));
    assert!(pending_client.wait_for_service(10 * SECOND));
    assert!(pending_client.server_available());
    assert!(pending_client.is_server_ready());
    assert_eq!(
        client.call(AddTwoIntsRequest { a: 1, b: 2 }, 5 * SECOND),
        Ok(AddTwoIntsResponse { sum: 3 })
    );
    let pending = pending_client.call_async(AddTwoIntsRequest { a: 3, b: 4 }, 5 * SECOND);
    assert_eq!(pending.wait(), Ok(AddTwoIntsResponse { sum: 7 }));
}

/// Wakes a parked thread.
struct Unparker(std::thread::Thread);

impl std::task::Wake for Unparker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

/// A minimal executor: polls the future on this thread, parking until woken.
fn block_on<F: std::future::Future>(future: F) -> F::Output {
    let waker = std::task::Waker::from(Arc::new(Unparker(std::thread::current())));
    let mut cx = std::task::Context::from_waker(&waker);
    let mut future = std::pin::pin!(future);
    loop {
        if let std::task::Poll::Ready(out) = future.as_mut().poll(&mut cx) {
            return out;
        }
        std::thread::park();
    }
}

/// Every client speaks of its servers in the same words (the crate's "Readiness"): known to the
/// graph, then ready (matched both ways); `wait_for_service` waits for ready.
#[test]
fn every_client_says_known_and_ready_alike() {
    let n = node(98, "readiness");
    let blocking = client(&n, "/readiness");
    let pending = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/readiness")
        .build()
        .expect("async client");
    assert!(!blocking.server_available() && !blocking.is_server_ready());
    assert!(!pending.server_available() && !pending.is_server_ready());
    assert!(!blocking.wait_for_service(Duration::from_millis(50)));
    let _server = adder(&n, "/readiness");
    assert!(blocking.wait_for_service(10 * SECOND));
    assert!(blocking.server_available() && blocking.is_server_ready());
    let graph_changes = Graph::of(n.context()).expect("graph").subscribe();
    let deadline = Instant::now() + 10 * SECOND;
    while !pending.is_server_ready() {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(
            !left.is_zero(),
            "the async client never saw the server ready"
        );
        let _ = graph_changes.recv(Some(left));
    }
    assert!(pending.server_available());
}

/// A builder builds the client it came from.
#[test]
fn the_async_clients_builder_builds_an_async_client() {
    let n = node(99, "builders");
    let built: AsyncServiceClient<AddTwoInts> = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/built")
        .build()
        .expect("async client");
    let blocking: ServiceClient<AddTwoInts> = ServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/built")
        .build()
        .expect("blocking client");
    assert_eq!(built.name(), blocking.name());
}
