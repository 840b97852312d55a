//! The `tokio` feature's streams: the graph's changes (`Graph::events`) and a subscription's
//! messages (`Subscription::into_stream`), bounded with drop-oldest and a lagged count (run inside
//! the test network namespace, on both backends). Each test has its own domain.

use std::time::Duration;

use futures_util::StreamExt;
use horus_ros_graph::{Graph, GraphEvent, Lagged};
use horus_ros_msgs::std_msgs::msg::Int32;
use horus_ros_rmw::qos::EndpointKind;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Context;

const SECOND: Duration = Duration::from_secs(1);

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_graph_event_wakes_the_task_awaiting_the_stream() {
    let context = context(210);
    let graph = Graph::of(&context).expect("graph");
    let mut events = graph.events();
    let watcher = tokio::spawn(async move {
        while let Some(event) = events.next().await {
            if let Ok(GraphEvent::EndpointAdded(endpoint)) = event {
                if endpoint.dds_topic == "rt/awaited_topic" {
                    return Some(endpoint.kind);
                }
            }
        }
        None
    });
    let node = context.create_node("stream_waker", "/").expect("node");
    let _publisher = node
        .create_publisher::<Int32>("awaited_topic", &Qos::default_profile())
        .expect("publisher");
    assert_eq!(watcher.await.expect("task"), Some(EndpointKind::Writer));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slow_graph_event_consumer_holds_at_most_the_capacity_and_learns_what_it_missed() {
    let context = context(211);
    let graph = Graph::of(&context).expect("graph");
    let mut events = graph.events_with_capacity(4);
    let node = context.create_node("stream_burst", "/").expect("node");
    let publishers: Vec<_> = (0..20)
        .map(|i| {
            node.create_publisher::<Int32>(&format!("burst_{i}"), &Qos::default_profile())
                .expect("publisher")
        })
        .collect();
    // The graph puts a change's events into the streams before the change can be seen.
    assert!(graph.wait_until(10 * SECOND, |c| {
        (0..20).all(|i| c.count_publishers(&format!("/burst_{i}")) == 1)
    }));
    assert_eq!(events.len(), 4, "full, and no fuller");
    assert_eq!(events.peak(), 4);
    assert_eq!(events.capacity(), 4);
    let lagged = events.lagged();
    assert!(
        lagged >= 16,
        "20 endpoints at least, 4 kept: {lagged} dropped"
    );
    assert_eq!(events.received(), lagged + 4);
    // The gap first, then the 4 newest.
    assert_eq!(events.next().await, Some(Err(Lagged(lagged))));
    for _ in 0..4 {
        assert!(matches!(events.next().await, Some(Ok(_))));
    }
    assert_eq!(events.try_next(), None);
    assert_eq!(events.lagged(), lagged, "nothing more dropped");
    drop(publishers);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slow_subscription_consumer_holds_at_most_the_capacity_and_counts_what_it_missed() {
    const SENT: i32 = 400;
    const CAPACITY: usize = 16;
    let context = context(212);
    let graph = Graph::of(&context).expect("graph");
    let node = context.create_node("stream_topic", "/").expect("node");
    let qos = Qos::default_profile().keep_last(SENT as usize).reliable();
    let publisher = node
        .create_publisher::<Int32>("numbers", &qos)
        .expect("publisher");
    let stream = node
        .create_subscription::<Int32>("numbers", &qos)
        .expect("subscription")
        .into_stream(CAPACITY)
        .expect("stream");
    // A second reader of the same samples tells when they have all arrived.
    let mut probe = node
        .create_subscription::<Int32>("numbers", &qos)
        .expect("probe");
    assert!(graph.wait_for_match(publisher.gid(), stream.gid(), 10 * SECOND));
    assert!(graph.wait_for_match(publisher.gid(), probe.gid(), 10 * SECOND));
    let mut stream = stream;

    for data in 0..SENT {
        publisher.publish(Int32 { data }).expect("publish");
    }
    // The consumer is slow: it reads nothing until every sample has arrived.
    let probed = tokio::task::spawn_blocking(move || {
        let deadline = std::time::Instant::now() + 30 * SECOND;
        let mut seen = 0;
        while seen < SENT {
            while let Ok(Some(_)) = probe.try_take() {
                seen += 1;
            }
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            if seen < SENT && (left.is_zero() || !probe.wait(left)) {
                break;
            }
        }
        seen
    })
    .await
    .expect("probe");
    assert_eq!(probed, SENT);

    let (mut delivered, mut missed, mut last) = (0_u64, 0_u64, -1);
    while last < SENT - 1 {
        assert!(stream.len() <= CAPACITY);
        match stream.next().await.expect("open") {
            Ok(Int32 { data }) => {
                assert!(data > last, "in order: {data} after {last}");
                last = data;
                delivered += 1;
            }
            Err(Lagged(n)) => missed += n,
        }
    }
    assert!(stream.peak() <= CAPACITY, "peak {}", stream.peak());
    assert!(missed > 0, "a consumer this slow must have lagged");
    assert_eq!(missed, stream.lagged());
    assert_eq!(
        delivered + missed,
        SENT as u64,
        "each sample delivered or counted"
    );
    assert_eq!(stream.received(), SENT as u64);
    assert!(stream.is_empty());
}
