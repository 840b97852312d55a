//! `Topic::stream` (feature `tokio`): a topic's messages awaited as a bounded stream, inside the
//! test network namespace (the process's own node, in the environment's domain).

use futures_util::StreamExt;
use horus::msgs::std_msgs::msg::Int32;
use horus::prelude::*;
use horus::ros::Qos;
use horus::Lagged;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_topic_stream_gets_the_messages_in_order_within_its_bound() {
    const SENT: i32 = 10;
    const CAPACITY: usize = 4;
    // Transient local: the stream's subscription, created after the marker was sent, gets it
    // from the publisher's history once matched.
    let qos = Qos::default_profile()
        .keep_last(SENT as usize)
        .reliable()
        .transient_local();
    let sender = Topic::<Int32>::with_qos("async_numbers", qos).expect("topic");
    sender.try_send(Int32 { data: -1 }).expect("send");
    let receiver = Topic::<Int32>::with_qos("async_numbers", qos).expect("topic");
    let mut stream = receiver.stream(CAPACITY).expect("stream");
    assert_eq!(stream.topic_name(), "/async_numbers");
    assert_eq!(stream.capacity(), CAPACITY);
    assert_eq!(stream.next().await, Some(Ok(Int32 { data: -1 })));

    // Matched: a burst, in order, within the bound, each message delivered or counted.
    for data in 0..SENT {
        sender.try_send(Int32 { data }).expect("send");
    }
    let (mut delivered, mut missed, mut last) = (0_u64, 0_u64, -1);
    while last < SENT - 1 {
        match stream.next().await.expect("open") {
            Ok(Int32 { data }) => {
                assert!(data > last, "in order: {data} after {last}");
                last = data;
                delivered += 1;
            }
            Err(Lagged(n)) => missed += n,
        }
    }
    assert!(stream.peak() <= CAPACITY);
    assert_eq!(missed, stream.lagged());
    assert_eq!(delivered + missed, SENT as u64);
    assert_eq!(stream.received(), 1 + SENT as u64);
    // And one sent now arrives too.
    sender.try_send(Int32 { data: 100 }).expect("send");
    assert_eq!(stream.next().await, Some(Ok(Int32 { data: 100 })));
}
