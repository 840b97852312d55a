//! The `tokio` feature: awaited calls, async handlers, cancellation, both runtime flavours (run
//! inside the test network namespace, on both backends). Each test has its own domain.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use horus_ros_rmw::qos::Qos;
use horus_ros_services::prelude::*;
use horus_ros_services::{AsyncServiceServer, SetupError};
use tokio::sync::{Barrier, Notify, Semaphore};
use tokio::task::JoinSet;

const SECOND: Duration = Duration::from_secs(1);

fn node(domain: u32, name: &str) -> Node {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    context.create_node(name, "/").expect("node")
}

fn async_client(node: &Node, name: &str) -> Arc<AsyncServiceClient<AddTwoInts>> {
    Arc::new(
        AsyncServiceClient::<AddTwoInts>::builder()
            .node(node)
            .name(name)
            .build()
            .expect("client"),
    )
}

/// An async adder that yields to the runtime before answering.
fn async_adder(node: &Node, name: &str) -> AsyncServiceServer<AddTwoInts> {
    ServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .on_request_async(|req| async move {
            tokio::task::yield_now().await;
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("async server")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_thousand_concurrent_awaited_calls_from_one_join_set_are_all_correct() {
    let n = node(200, "thousand");
    // A thousand requests at once overflow the default KEEP_LAST 10 history of the request
    // reader (and of the reply reader) whenever the server's thread falls behind — a loaded
    // machine is enough — and a request so dropped is never answered, as with rclcpp's
    // defaults. The endpoints are sized for the burst with room to spare (KEEP_LAST 2000): at
    // exactly the burst (1000), the rustdds backend's reliable writer lost a few unacknowledged
    // samples about one run in ten (992 of 1000 requests served); with 2000, none in 24. What
    // this test checks is that every call the DDS layer delivers is answered, correctly and to
    // its caller.
    let burst = Qos::services_default().with_depth(2000);
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/thousand")
        .qos(burst)
        .on_request_async(|req| async move {
            tokio::task::yield_now().await;
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()
        .expect("async server");
    let client = Arc::new(
        AsyncServiceClient::<AddTwoInts>::builder()
            .node(&n)
            .name("/thousand")
            .qos(burst)
            .build()
            .expect("client"),
    );
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let mut calls = JoinSet::new();
    for i in 0..1000_i64 {
        let client = Arc::clone(&client);
        calls.spawn(async move {
            let reply = client
                .call(AddTwoIntsRequest { a: i, b: 2 * i }, 60 * SECOND)
                .await;
            (i, reply)
        });
    }
    let mut answered = 0;
    while let Some(joined) = calls.join_next().await {
        let (i, reply) = joined.expect("task");
        assert_eq!(
            reply,
            Ok(AddTwoIntsResponse { sum: 3 * i }),
            "call {i}: served {} pending {}",
            server.served_count(),
            client.pending_requests()
        );
        answered += 1;
    }
    assert_eq!(answered, 1000);
    assert_eq!(client.pending_requests(), 0);
    assert_eq!(server.served_count(), 1000);
    assert!(server.peak_in_flight() <= server.max_in_flight());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pending_responses_are_awaited_on_tokio_and_a_sync_server_answers_awaited_calls() {
    let n = node(201, "pending");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/pending")
        .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
        .build()
        .expect("server");
    // The client in a participant of its own: rustdds 0.15.1 can leave a burst of requests
    // between a writer and a reader of one participant undelivered under load (seen in this
    // test: the server got 64 of the 100 and never the rest), which no call of ours can repair.
    let client = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&node(201, "pending_client"))
        .name("/pending")
        .build()
        .expect("client");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let mut set = JoinSet::new();
    for i in 0..100 {
        set.spawn(client.call_async(AddTwoIntsRequest { a: i, b: 1 }, 30 * SECOND));
    }
    let mut sums = Vec::new();
    while let Some(joined) = set.join_next().await {
        sums.push(joined.expect("task").expect("reply").sum);
    }
    sums.sort_unstable();
    assert_eq!(sums, (1..=100).collect::<Vec<i64>>());
    assert_eq!(client.pending_requests(), 0);
    // And the awaited call of the same client.
    assert_eq!(
        client
            .call(AddTwoIntsRequest { a: 5, b: 6 }, 5 * SECOND)
            .await,
        Ok(AddTwoIntsResponse { sum: 11 })
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn an_async_handler_has_64_calls_in_flight_at_once() {
    let n = node(202, "sixty_four");
    // No handler can finish until 64 of them are running together.
    let barrier = Arc::new(Barrier::new(64));
    let server = AsyncServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/sixty_four")
        .on_request(move |req| {
            let barrier = Arc::clone(&barrier);
            async move {
                barrier.wait().await;
                Ok(AddTwoIntsResponse { sum: req.a + req.b })
            }
        })
        .max_in_flight(64)
        .build()
        .expect("async server");
    let client = async_client(&n, "/sixty_four");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let mut calls = JoinSet::new();
    for i in 0..64_i64 {
        let client = Arc::clone(&client);
        calls.spawn(async move {
            (
                i,
                client
                    .call(AddTwoIntsRequest { a: i, b: 1 }, 60 * SECOND)
                    .await,
            )
        });
    }
    while let Some(joined) = calls.join_next().await {
        let (i, reply) = joined.expect("task");
        assert_eq!(reply, Ok(AddTwoIntsResponse { sum: i + 1 }));
    }
    assert_eq!(server.peak_in_flight(), 64);
    assert_eq!(server.served_count(), 64);
    assert_eq!(client.pending_requests(), 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn handlers_in_flight_are_bounded_and_the_excess_waits_in_the_reader() {
    let n = node(203, "bounded");
    // Handlers finish by groups of 4: with a bound of 4, 16 calls need 4 rounds, and more than 4
    // at once would be seen by the counter.
    let barrier = Arc::new(Barrier::new(4));
    let running = Arc::new(AtomicUsize::new(0));
    let most = Arc::new(AtomicUsize::new(0));
    let server = {
        let (running, most) = (Arc::clone(&running), Arc::clone(&most));
        AsyncServiceServer::<AddTwoInts>::builder()
            .node(&n)
            .name("/bounded")
            .on_request(move |req| {
                let (barrier, running, most) = (
                    Arc::clone(&barrier),
                    Arc::clone(&running),
                    Arc::clone(&most),
                );
                async move {
                    let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                    most.fetch_max(now, Ordering::SeqCst);
                    barrier.wait().await;
                    running.fetch_sub(1, Ordering::SeqCst);
                    Ok(AddTwoIntsResponse { sum: req.a + req.b })
                }
            })
            .max_in_flight(4)
            .build()
            .expect("async server")
    };
    let client = async_client(&n, "/bounded");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let mut calls = JoinSet::new();
    for i in 0..16_i64 {
        let client = Arc::clone(&client);
        calls.spawn(async move {
            client
                .call(AddTwoIntsRequest { a: i, b: 0 }, 60 * SECOND)
                .await
        });
    }
    let mut sums = Vec::new();
    while let Some(joined) = calls.join_next().await {
        sums.push(joined.expect("task").expect("reply").sum);
    }
    sums.sort_unstable();
    assert_eq!(sums, (0..16).collect::<Vec<i64>>());
    assert_eq!(most.load(Ordering::SeqCst), 4);
    assert_eq!(server.peak_in_flight(), 4);
    assert_eq!(server.max_in_flight(), 4);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_failing_or_panicking_async_handler_fails_that_call_only() {
    let n = node(204, "panicky");
    let server = AsyncServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/panicky")
        .on_request(|req| {
            // A panic while making the future counts as the handler's too.
            assert_ne!(req.a, 2, "refused before any await");
            async move {
                tokio::task::yield_now().await;
                match req.a {
                    0 => Err("a must not be zero".to_owned()),
                    1 => panic!("boom after an await"),
                    _ => Ok(AddTwoIntsResponse { sum: req.a + req.b }),
                }
            }
        })
        .build()
        .expect("async server");
    let client = async_client(&n, "/panicky");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let call = |a| client.call(AddTwoIntsRequest { a, b: 1 }, 10 * SECOND);
    assert_eq!(
        call(0).await,
        Err(ServiceError::ServiceFailed("a must not be zero".to_owned()))
    );
    match call(1).await {
        Err(ServiceError::ServiceFailed(m)) => {
            assert!(
                m.contains("panicked") && m.contains("boom after an await"),
                "{m}"
            )
        }
        other => panic!("expected ServiceFailed for a panic, got {other:?}"),
    }
    match call(2).await {
        Err(ServiceError::ServiceFailed(m)) => {
            assert!(m.contains("refused before any await"), "{m}")
        }
        other => panic!("expected ServiceFailed for a panic, got {other:?}"),
    }
    assert_eq!(call(3).await, Ok(AddTwoIntsResponse { sum: 4 }));
    // Counted before each reply is sent.
    assert_eq!((server.served_count(), server.failed_count()), (1, 3));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_dropped_call_is_withdrawn_and_leaves_nothing_behind() {
    let n = node(205, "cancel");
    let arrived = Arc::new(Notify::new());
    // Held handlers go on once given a permit each.
    let release = Arc::new(Semaphore::new(0));
    let server = {
        let (arrived, release) = (Arc::clone(&arrived), Arc::clone(&release));
        AsyncServiceServer::<AddTwoInts>::builder()
            .node(&n)
            .name("/cancel")
            .on_request(move |req| {
                let (arrived, release) = (Arc::clone(&arrived), Arc::clone(&release));
                async move {
                    if req.a < 0 {
                        arrived.notify_one();
                        release.acquire().await.expect("open").forget();
                    }
                    Ok(AddTwoIntsResponse { sum: req.a + req.b })
                }
            })
            .build()
            .expect("async server")
    };
    let client = async_client(&n, "/cancel");
    assert!(client.wait_for_service_async(10 * SECOND).await);

    // Dropped by select! once the server holds the request: the call was in flight.
    let call = client.call(AddTwoIntsRequest { a: -1, b: 0 }, 60 * SECOND);
    tokio::select! {
        reply = call => panic!("the handler cannot answer yet: {reply:?}"),
        () = arrived.notified() => {}
    }
    assert_eq!(
        client.pending_requests(),
        0,
        "the dropped call left its slot"
    );
    assert_eq!(server.in_flight(), 1);

    // Dropped by tokio::time::timeout: a PendingResponse this time.
    let pending_client = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/cancel")
        .build()
        .expect("client");
    assert!(pending_client.wait_for_service_async(10 * SECOND).await);
    let pending = pending_client.call_async(AddTwoIntsRequest { a: -2, b: 0 }, 60 * SECOND);
    tokio::select! {
        reply = pending => panic!("the handler cannot answer yet: {reply:?}"),
        () = arrived.notified() => {}
    }
    assert_eq!(pending_client.pending_requests(), 0);
    let timed_out = tokio::time::timeout(
        Duration::from_millis(50),
        client.call(AddTwoIntsRequest { a: -3, b: 0 }, 60 * SECOND),
    );
    assert!(timed_out.await.is_err(), "the handler holds it");
    assert_eq!(client.pending_requests(), 0);

    // The held handlers answer now; their replies find no call and are dropped.
    release.add_permits(3);
    // The client goes on as before.
    assert_eq!(
        client
            .call(AddTwoIntsRequest { a: 20, b: 22 }, 10 * SECOND)
            .await,
        Ok(AddTwoIntsResponse { sum: 42 })
    );
    assert_eq!(client.pending_requests(), 0);
    assert_eq!(pending_client.pending_requests(), 0);
}

#[tokio::test]
async fn a_current_thread_runtime_serves_and_calls_itself() {
    let n = node(206, "current");
    let server = async_adder(&n, "/current");
    let client = async_client(&n, "/current");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let calls: Vec<_> = (0..50)
        .map(|i| client.call(AddTwoIntsRequest { a: i, b: i }, 30 * SECOND))
        .collect();
    let replies = futures_util::future::join_all(calls).await;
    for (i, reply) in replies.into_iter().enumerate() {
        assert_eq!(reply, Ok(AddTwoIntsResponse { sum: 2 * i as i64 }));
    }
    assert_eq!(server.served_count(), 50);
    assert_eq!(client.pending_requests(), 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn waiting_for_a_service_is_woken_by_its_arrival_and_ends_at_the_timeout() {
    let n = node(207, "waiting");
    let client = async_client(&n, "/late_server");
    assert!(
        !client
            .wait_for_service_async(Duration::from_millis(200))
            .await
    );
    assert_eq!(
        client
            .call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(200))
            .await,
        Err(ServiceError::NoServer)
    );
    // A call and a wait started before the server exists are sent and end once it is there.
    let early_call = tokio::spawn({
        let client = Arc::clone(&client);
        async move {
            client
                .call(AddTwoIntsRequest { a: 40, b: 2 }, 30 * SECOND)
                .await
        }
    });
    let waiting = tokio::spawn({
        let client = Arc::clone(&client);
        async move { client.wait_for_service_async(30 * SECOND).await }
    });
    let _server = async_adder(&n, "/late_server");
    assert!(waiting.await.expect("task"));
    assert_eq!(
        early_call.await.expect("task"),
        Ok(AddTwoIntsResponse { sum: 42 })
    );
    assert_eq!(client.pending_requests(), 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_awaited_call_ends_with_server_gone_when_its_server_leaves() {
    let n = node(208, "gone");
    let arrived = Arc::new(Notify::new());
    let server = {
        let arrived = Arc::clone(&arrived);
        AsyncServiceServer::<AddTwoInts>::builder()
            .node(&n)
            .name("/gone")
            .on_request(move |_req| {
                let arrived = Arc::clone(&arrived);
                async move {
                    arrived.notify_one();
                    std::future::pending::<()>().await;
                    Err("never".to_owned())
                }
            })
            .build()
            .expect("async server")
    };
    let client = async_client(&n, "/gone");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    let call = tokio::spawn({
        let client = Arc::clone(&client);
        async move {
            client
                .call(AddTwoIntsRequest { a: 1, b: 1 }, 60 * SECOND)
                .await
        }
    });
    arrived.notified().await;
    // Dropping the server ends its handler task and withdraws its endpoints.
    drop(server);
    assert_eq!(
        call.await.expect("task"),
        Err(ServiceError::Transport(TransportError::ServerGone))
    );
    assert_eq!(client.pending_requests(), 0);
}

#[test]
fn an_async_server_needs_a_handler() {
    let n = node(210, "async_nohandler");
    let built = AsyncServiceServer::<AddTwoInts>::builder().node(&n).build();
    assert!(matches!(built, Err(SetupError::NoHandler)), "{built:?}");
}

#[test]
fn an_async_server_needs_a_runtime_or_a_handle_to_one() {
    let n = node(209, "handle");
    let outside = AsyncServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/handle")
        .on_request(|req| async move { Ok(AddTwoIntsResponse { sum: req.a + req.b }) })
        .build();
    assert!(
        matches!(outside, Err(SetupError::NoAsyncRuntime(_))),
        "{outside:?}"
    );

    // Given a runtime's handle, it serves there; a blocking client calls it from this thread.
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime");
    let server = AsyncServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/handle")
        .on_request(|req| async move { Ok(AddTwoIntsResponse { sum: req.a * req.b }) })
        .runtime(runtime.handle().clone())
        .build()
        .expect("async server on a handle");
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&n)
        .name("/handle")
        .build()
        .expect("client");
    assert!(client.wait_for_service(10 * SECOND));
    assert_eq!(
        client.call(AddTwoIntsRequest { a: 6, b: 7 }, 5 * SECOND),
        Ok(AddTwoIntsResponse { sum: 42 })
    );
    assert_eq!(server.served_count(), 1);
}

/// `<service>_Event` of `AddTwoInts` (rcl's service event message), as the test decodes it.
#[derive(Debug, serde::Deserialize)]
struct AddTwoIntsEvent {
    info: horus_ros_msgs::service_msgs::msg::ServiceEventInfo,
    request: Vec<AddTwoIntsRequest>,
    response: Vec<AddTwoIntsResponse>,
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_async_server_publishes_introspection_events_like_a_blocking_one() {
    use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
    use horus_ros_rmw::qos::Qos;
    use horus_ros_rmw::RawEndpointSpec;
    use horus_ros_services::{IntrospectionState, SERVICE_EVENT_TOPIC_POSTFIX};

    let n = node(214, "introspected");
    let server = AsyncServiceServer::<AddTwoInts>::builder()
        .node(&n)
        .name("/introspected")
        .introspection(IntrospectionState::Contents, Qos::services_default())
        .on_request(|req| async move { Ok(AddTwoIntsResponse { sum: req.a + req.b }) })
        .build()
        .expect("async server");
    assert_eq!(server.introspection_state(), IntrospectionState::Contents);
    let publisher = server.introspection_gid().expect("an event publisher");

    // The events' topic as `ros2 service echo` reads it.
    let mut reader = n
        .create_raw_reader(&RawEndpointSpec {
            dds_topic_name: format!("rt/introspected{SERVICE_EVENT_TOPIC_POSTFIX}"),
            dds_type_name: horus_ros_msgs::dds_type_name("example_interfaces/srv/AddTwoInts_Event"),
            type_hash: AddTwoInts::event_type_hash(),
            qos: Qos::services_default(),
            service_id: None,
        })
        .expect("event reader");
    let client = async_client(&n, "/introspected");
    assert!(client.wait_for_service_async(10 * SECOND).await);
    // Volatile events: the call is made once the event publisher has matched the reader.
    let graph = horus_ros_graph::Graph::of(n.context()).expect("graph");
    assert!(
        graph.wait_for_match(publisher, reader.gid(), 10 * SECOND),
        "the event publisher never matched the reader"
    );
    let reply = client
        .call(AddTwoIntsRequest { a: 20, b: 22 }, 10 * SECOND)
        .await;
    assert_eq!(reply, Ok(AddTwoIntsResponse { sum: 42 }));

    let mut events = Vec::new();
    let deadline = std::time::Instant::now() + 10 * SECOND;
    while events.len() < 2 {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        assert!(!left.is_zero(), "events by now: {events:?}");
        reader.wait(left);
        while let Some(sample) = reader.take().expect("take") {
            let event: AddTwoIntsEvent = if sample.big_endian {
                horus_ros_msgs::cdr::from_cdr_body::<_, byteorder::BigEndian>(&sample.body)
            } else {
                horus_ros_msgs::cdr::from_cdr_body::<_, byteorder::LittleEndian>(&sample.body)
            }
            .expect("an AddTwoInts_Event");
            events.push(event);
        }
    }
    let [received, sent] = &events[..] else {
        panic!("two events expected: {events:?}");
    };
    assert_eq!(received.info.event_type, ServiceEventInfo::REQUEST_RECEIVED);
    assert_eq!(received.request, vec![AddTwoIntsRequest { a: 20, b: 22 }]);
    assert!(received.response.is_empty());
    assert_eq!(sent.info.event_type, ServiceEventInfo::RESPONSE_SENT);
    assert_eq!(sent.response, vec![AddTwoIntsResponse { sum: 42 }]);
    assert!(sent.request.is_empty());
    assert_eq!(received.info.client_gid, sent.info.client_gid);
    assert_eq!(received.info.sequence_number, sent.info.sequence_number);
    assert_ne!(received.info.client_gid, [0; 16]);

    // OFF removes the publisher, as on a blocking server.
    server
        .configure_introspection(IntrospectionState::Off, &Qos::services_default())
        .expect("off");
    assert_eq!(server.introspection_gid(), None);
}
