//! Servers and clients of this crate talking to each other over DDS (run inside the test network
//! namespace). Each test has its own domain.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_services::prelude::*;
use horus_ros_services::SetupError;

const SECOND: Duration = Duration::from_secs(1);

fn node(domain: u32, name: &str) -> Node {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    context.create_node(name, "/").expect("node")
}

fn adder(node: &Node, name: &str) -> ServiceServer<AddTwoInts> {
    ServiceServerBuilder::<AddTwoInts>::new()
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
    let server = ServiceServerBuilder::<AddTwoInts>::new()
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
    let start = Instant::now();
    let err = c
        .call(AddTwoIntsRequest { a: 0, b: 1 }, 5 * SECOND)
        .expect_err("handler error");
    assert_eq!(
        err,
        ServiceError::ServiceFailed("a must not be zero".to_owned())
    );
    assert!(
        start.elapsed() < SECOND,
        "an error reply must not wait for the timeout"
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
    let start = Instant::now();
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(300)),
        Err(ServiceError::NoServer)
    );
    assert!(start.elapsed() < SECOND);
    assert_eq!(
        c.call_optional(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(300)),
        Ok(None)
    );
    // NoServer is permanent: not retried (one attempt's worth of time).
    let start = Instant::now();
    assert_eq!(
        c.call_resilient(AddTwoIntsRequest::default(), Duration::from_millis(200)),
        Err(ServiceError::NoServer)
    );
    assert!(start.elapsed() < Duration::from_millis(600));
}

#[test]
fn a_late_reply_is_dropped_and_the_next_call_gets_its_own() {
    let n = node(84, "slowpoke");
    let calls = Arc::new(AtomicUsize::new(0));
    let seen = Arc::clone(&calls);
    let _server = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&n)
        .name("/slow")
        .on_request(move |req| {
            if seen.fetch_add(1, Ordering::SeqCst) == 0 {
                std::thread::sleep(Duration::from_millis(400));
            }
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("server");
    let mut c = client(&n, "/slow");
    assert!(c.wait_for_service(10 * SECOND));
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(100)),
        Err(ServiceError::Timeout)
    );
    assert_eq!(
        c.pending_requests(),
        0,
        "a timed-out call leaves nothing behind"
    );
    // The first (late) reply, sum 2, arrives during this call and must not be taken for it.
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
    let _server = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&n)
        .name("/flaky")
        .on_request(move |req| {
            if seen.fetch_add(1, Ordering::SeqCst) == 0 {
                std::thread::sleep(Duration::from_millis(300));
            }
            Ok(AddTwoIntsResponse { sum: req.a * req.b })
        })
        .build()
        .expect("server");
    let mut c = client(&n, "/flaky");
    assert!(c.wait_for_service(10 * SECOND));
    let reply = c.call_resilient_with(
        AddTwoIntsRequest { a: 3, b: 4 },
        Duration::from_millis(150),
        RetryConfig::new(5, Duration::from_millis(20)),
    );
    assert_eq!(reply, Ok(AddTwoIntsResponse { sum: 12 }));
    assert!(
        calls.load(Ordering::SeqCst) >= 2,
        "the first attempt timed out, a retry answered"
    );
}

#[test]
fn a_server_dropped_mid_call_gives_the_client_an_error_within_its_timeout() {
    let n = node(86, "vanishing");
    let (handling_tx, handling_rx) = std::sync::mpsc::channel();
    let server = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&n)
        .name("/vanishing")
        .on_request(move |req| {
            let _ = handling_tx.send(());
            // A slow handler: the server is stopped while it runs.
            std::thread::sleep(Duration::from_millis(300));
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("server");
    let mut c = client(&n, "/vanishing");
    assert!(c.wait_for_service(10 * SECOND));
    let stopper = std::thread::spawn(move || {
        // Stopped mid-call: once the handler has the request.
        let _ = handling_rx.recv_timeout(10 * SECOND);
        server.stop();
        drop(server);
    });
    // The handler finishes its request before the server stops: a reply or a timeout, never a hang.
    let start = Instant::now();
    let _ = c.call(AddTwoIntsRequest { a: 1, b: 2 }, SECOND);
    assert!(start.elapsed() <= SECOND + Duration::from_millis(200));
    stopper.join().expect("stopper");
    // The server is gone: the next call fails within its timeout (ServerGone when the request
    // went out while its endpoints were still being withdrawn).
    let start = Instant::now();
    let err = c
        .call(AddTwoIntsRequest { a: 1, b: 2 }, SECOND)
        .expect_err("no server any more");
    assert!(
        matches!(
            err,
            ServiceError::NoServer | ServiceError::Timeout | ServiceError::ServerGone
        ),
        "{err:?}"
    );
    assert!(start.elapsed() <= SECOND + Duration::from_millis(200));
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
    let _slow = ServiceServerBuilder::<AddTwoInts>::new()
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
    let mut c = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/async_add")
        .build_async()
        .expect("client");
    // Sent before any server is matched: it goes out once one is.
    let mut first = c.call_async(AddTwoIntsRequest { a: 1, b: 2 }, 10 * SECOND);
    let start = Instant::now();
    let reply = loop {
        if let Some(r) = first.check().expect("check") {
            break r;
        }
        assert!(start.elapsed() < 10 * SECOND && !first.is_expired());
        std::thread::sleep(Duration::from_millis(5));
    };
    assert_eq!(reply.sum, 3);
    assert_eq!(
        c.call_async(AddTwoIntsRequest { a: 4, b: 5 }, 5 * SECOND)
            .wait(),
        Ok(AddTwoIntsResponse { sum: 9 })
    );
    let many: Vec<_> = (0..20)
        .map(|i| c.call_async(AddTwoIntsRequest { a: i, b: i }, 5 * SECOND))
        .collect();
    for (i, p) in many.into_iter().enumerate() {
        assert_eq!(block_on(p), Ok(AddTwoIntsResponse { sum: 2 * i as i64 }));
    }
    let mut missing = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/missing")
        .build_async()
        .expect("client");
    let pending = missing.call_async(AddTwoIntsRequest::default(), Duration::from_millis(200));
    assert_eq!(block_on(pending), Err(ServiceError::NoServer));
}

#[test]
fn a_server_needs_a_handler() {
    let n = node(89, "nohandler");
    assert!(matches!(
        ServiceServerBuilder::<AddTwoInts>::new().node(&n).build(),
        Err(SetupError::NoHandler)
    ));
    assert!(matches!(
        ServiceServerBuilder::<AddTwoInts>::new()
            .node(&n)
            .name("bad name")
            .on_request(|_| Ok(Default::default()))
            .build(),
        Err(SetupError::InvalidName { .. })
    ));
}

/// A minimal executor: polls the future on this thread, parking until woken.
fn block_on<F: std::future::Future>(future: F) -> F::Output {
    struct Unparker(std::thread::Thread);
    impl std::task::Wake for Unparker {
        fn wake(self: Arc<Self>) {
            self.0.unpark();
        }
    }
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
