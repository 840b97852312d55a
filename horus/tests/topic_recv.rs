//! `Topic::recv` / `recv_timeout` wait without holding the topic: a `send` on the same `Topic`
//! from another thread goes through meanwhile, and malformed samples are skipped, not mistaken
//! for an empty queue. Inside the test network namespace (the process's own node, in the
//! environment's domain); every wait is bounded by `WAIT`.

use std::sync::{mpsc, Arc};
use std::time::Duration;

use horus::msgs::std_msgs::msg::Int32;
use horus::prelude::*;
use horus::ros::{Context, Qos};
use horus_ros_rmw::RawEndpointSpec;

const WAIT: Duration = Duration::from_secs(30);
const ROUNDS: i32 = 50;

/// Transient local: what is sent before the endpoints are matched still arrives.
fn qos() -> Qos {
    Qos::default_profile()
        .keep_last(ROUNDS as usize)
        .reliable()
        .transient_local()
}

#[test]
fn a_send_on_a_topic_goes_through_while_another_thread_waits_in_recv() {
    let topic = Arc::new(Topic::<Int32>::with_qos("recv_while_sending", qos()).expect("topic"));
    topic.connect_subscriber().expect("subscriber");

    // The receiver goes back to `recv` at once after each message, so it is usually blocked
    // there when the next `send` comes (which waited for it before the fix: a deadlock).
    let (got_tx, got) = mpsc::channel();
    let receiver = {
        let topic = Arc::clone(&topic);
        std::thread::spawn(move || {
            for _ in 0..ROUNDS {
                if got_tx.send(topic.recv()).is_err() {
                    return;
                }
            }
        })
    };
    let (send_tx, send_rx) = mpsc::channel::<i32>();
    let sender = {
        let topic = Arc::clone(&topic);
        std::thread::spawn(move || {
            for data in send_rx {
                topic.try_send(Int32 { data }).expect("send");
            }
        })
    };
    for data in 0..ROUNDS {
        send_tx.send(data).expect("sender running");
        let received = got
            .recv_timeout(WAIT)
            .unwrap_or_else(|_| panic!("message {data} not received within {WAIT:?}"));
        assert_eq!(received, Some(Int32 { data }));
    }
    drop(send_tx);
    sender.join().expect("sender");
    receiver.join().expect("receiver");
    assert_eq!(topic.skipped_samples(), 0);
}

#[test]
fn recv_skips_malformed_samples_and_gets_the_good_ones_queued_behind() {
    let topic = Arc::new(Topic::<StringMsg>::with_qos("recv_malformed", qos()).expect("topic"));
    topic.connect_subscriber().expect("subscriber");
    // A raw writer of the same topic and type (a participant of its own) sends a string whose
    // length runs past the sample's end, then a good one, back to back.
    let context = Context::from_env().expect("context");
    let node = context.create_node("malformed_writer", "/").expect("node");
    let writer = node
        .create_raw_writer(&RawEndpointSpec {
            dds_topic_name: "rt/recv_malformed".to_owned(),
            dds_type_name: <StringMsg as Message>::dds_type_name(),
            type_hash: <StringMsg as Message>::type_hash(),
            qos: qos(),
            service_id: None,
        })
        .expect("raw writer");

    let (got_tx, got) = mpsc::channel();
    let receiver = {
        let topic = Arc::clone(&topic);
        std::thread::spawn(move || {
            for _ in 0..ROUNDS {
                if got_tx.send(topic.recv_timeout(WAIT)).is_err() {
                    return;
                }
            }
        })
    };
    for data in 0..ROUNDS {
        writer
            .write(vec![100, 0, 0, 0], None, None)
            .expect("malformed sample");
        let good = horus::msgs::cdr::to_cdr_body(&message(data)).expect("encode");
        writer.write(good, None, None).expect("good sample");
        let received = got
            .recv_timeout(WAIT)
            .unwrap_or_else(|_| panic!("round {data}: no answer within {WAIT:?}"));
        assert_eq!(received, Some(message(data)), "round {data}");
    }
    receiver.join().expect("receiver");
    assert_eq!(topic.skipped_samples(), ROUNDS as u64);
}

fn message(n: i32) -> StringMsg {
    StringMsg {
        data: format!("good {n}"),
    }
}
