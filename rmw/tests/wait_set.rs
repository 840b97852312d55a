//! `WaitSet` (`rmw_wait` over many readers) on the backend of `HORUS_ROS_BACKEND`: which readers
//! it reports, once per arrival, data that was there before a reader was attached, and its waker.

mod common;

use std::time::Instant;

use common::{await_matches, spec, LIMIT};
use horus_ros_rmw::{Context, Gid, RawReader, RawWriter, WaitSet};

const DOMAIN: u32 = 39;

/// Waits on `set` and takes from the readers it reports until `want` samples are taken (at
/// most [`LIMIT`]); returns them with the key of the reader each came from. A report may be
/// spurious (it says a reader *may* have data), so an empty take is no failure; a sample not
/// reported is never taken, so a lost wake-up fails here.
fn collect(set: &WaitSet, readers: &mut [RawReader], want: usize) -> Vec<(usize, Vec<u8>)> {
    let deadline = Instant::now() + LIMIT;
    let mut got = Vec::new();
    let mut ready = Vec::new();
    while got.len() < want {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "only {got:?} within {LIMIT:?}");
        set.wait(left, &mut ready);
        for &key in &ready {
            got.extend(drain(&mut readers[key]).into_iter().map(|b| (key, b)));
        }
    }
    got
}

fn drain(reader: &mut RawReader) -> Vec<Vec<u8>> {
    std::iter::from_fn(|| reader.take().expect("take").map(|s| s.body)).collect()
}

fn body(n: u8) -> Vec<u8> {
    vec![n, 0, 0, 0, 0, 0, 0, 0]
}

#[test]
fn a_wait_set_reports_each_arrival_on_its_readers_key() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("wait_set", "/").expect("node");
    let mut feed = context.discovery_feed().expect("feed");
    let topics = ["rq/ws_aRequest", "rq/ws_bRequest"];
    let writers: Vec<RawWriter> = topics
        .iter()
        .map(|t| node.create_raw_writer(&spec(t)).expect("writer"))
        .collect();
    let mut readers: Vec<RawReader> = topics
        .iter()
        .map(|t| node.create_raw_reader(&spec(t)).expect("reader"))
        .collect();
    let pairs: Vec<(Gid, Gid)> = writers
        .iter()
        .zip(&readers)
        .map(|(w, r)| (w.gid(), r.gid()))
        .collect();
    await_matches(&mut feed, &pairs);

    let set = WaitSet::new(&context).expect("wait set");
    for (key, reader) in readers.iter_mut().enumerate() {
        set.attach(reader, key).expect("attach");
    }

    // A burst on the second topic, all of it taken from the reader reported.
    for n in 0..3 {
        writers[1].write(body(n), None, None).expect("write");
    }
    let burst = collect(&set, &mut readers, 3);
    assert_eq!(burst, [(1, body(0)), (1, body(1)), (1, body(2))]);

    // The waker ends a wait with nothing to take.
    set.waker().wake();
    let mut ready = Vec::new();
    assert!(
        set.wait(LIMIT, &mut ready),
        "the waker did not end the wait"
    );

    // Each later arrival is reported again, on either reader.
    writers[0].write(body(7), None, None).expect("write");
    assert_eq!(collect(&set, &mut readers, 1), [(0, body(7))]);
    writers[1].write(body(8), None, None).expect("write");
    assert_eq!(collect(&set, &mut readers, 1), [(1, body(8))]);
}

#[test]
fn a_reader_attached_with_data_waiting_is_reported() {
    let context = Context::builder()
        .domain_id(DOMAIN + 1)
        .build()
        .expect("context");
    let node = context.create_node("wait_set_late", "/").expect("node");
    let mut feed = context.discovery_feed().expect("feed");
    let writer = node
        .create_raw_writer(&spec("rq/ws_lateRequest"))
        .expect("writer");
    let mut reader = node
        .create_raw_reader(&spec("rq/ws_lateRequest"))
        .expect("reader");
    await_matches(&mut feed, &[(writer.gid(), reader.gid())]);

    // The sample is acknowledged, so it is in the reader before the reader is attached.
    writer.write(body(5), None, None).expect("write");
    assert!(
        writer.wait_for_acknowledgments(LIMIT),
        "the sample was not acknowledged"
    );
    let set = WaitSet::new(&context).expect("wait set");
    set.attach(&mut reader, 0).expect("attach");
    let mut readers = [reader];
    assert_eq!(collect(&set, &mut readers, 1), [(0, body(5))]);
}
