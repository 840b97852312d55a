//! Our services against peers that misbehave or die, on the backend of `HORUS_ROS_BACKEND`:
//! - an independent Cyclone DDS peer (Python binding, `peers/cyclone_hostile_peer.py`) playing a
//!   crashed rmw_cyclonedds client (requests that no reply can reach) or writing garbage on the
//!   request topic: a good client's p99 does not move by more than 2×;
//! - a horus-ros server in a process of its own (`horus_add_two_ints_server`) SIGKILLed half a
//!   second into a 2 s handler: its client learns it (`ServiceError::Transport(TransportError::ServerGone)`) when the dead
//!   participant's lease expires, and the dead participant leaves the graph then. The killed
//!   server runs on the Cyclone backend, whose participants announce Cyclone DDS's default lease
//!   (10 s), as rmw_cyclonedds' do; rustdds 0.15 announces a fixed 50 s lease that horus-ros
//!   cannot change (see the design notes).

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_services::prelude::*;
use interop_tests::{cyclone_config, Peer};
use serde_json::Value;

const SECOND: Duration = Duration::from_secs(1);
/// Below this, a p99 is scheduling noise on a loaded 2-core machine (see
/// services/tests/reliability.rs): "not moved by more than 2×" is checked against at least this.
const P99_FLOOR: Duration = Duration::from_millis(100);
/// Cyclone DDS's default participant lease (`Discovery/LeaseDuration`, 10 s), which
/// rmw_cyclonedds keeps and our Cyclone backend announces.
const CYCLONE_LEASE: Duration = Duration::from_secs(10);
/// Lease expiry is checked periodically by the DDS layer, and our graph follows its events.
const LEASE_SLACK: Duration = Duration::from_secs(3);

fn node(domain: u32, name: &str) -> Node {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
        .create_node(name, "/")
        .expect("node")
}

fn adder(node: &Node, name: &str) -> ServiceServer<AddTwoInts> {
    ServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .on_request(|req| {
            Ok(AddTwoIntsResponse {
                sum: req.a.wrapping_add(req.b),
            })
        })
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

/// `calls` sequential calls; their latencies (every call must succeed with its sum).
fn latencies(c: &mut ServiceClient<AddTwoInts>, calls: i64) -> Vec<Duration> {
    (0..calls)
        .map(|i| {
            let t = Instant::now();
            assert_eq!(
                c.call(AddTwoIntsRequest { a: i, b: 3 }, 5 * SECOND),
                Ok(AddTwoIntsResponse { sum: i + 3 }),
                "good call {i}"
            );
            t.elapsed()
        })
        .collect()
}

fn p99(mut samples: Vec<Duration>) -> Duration {
    samples.sort_unstable();
    samples[((samples.len() * 99).div_ceil(100)).clamp(1, samples.len()) - 1]
}

/// A good client's p99 alone, while the Cyclone peer misbehaves in `mode`, and after it left.
fn good_client_with_cyclone_peer(domain: u32, mode: &str) -> (Duration, Duration, Duration, Value) {
    let service = format!("/hostile_{mode}");
    let _server = adder(&node(domain, "target_server"), &service);
    let mut good = client(&node(domain, "good_client"), &service);
    assert!(good.wait_for_service(20 * SECOND), "no server");
    let _warm_up = latencies(&mut good, 50);
    let alone = p99(latencies(&mut good, 200));

    let mut peer = Peer::start(
        "cyclone_hostile_peer.py",
        &[domain.to_string(), service.clone(), mode.into(), "4".into()],
    )
    .expect("start the Cyclone DDS peer");
    let lines = peer.stdout_lines().expect("peer output");
    // The peer writes for 4 s once matched (it takes a moment to start): calls go on until it
    // has printed its summary, and only those made while it was writing count.
    let done = Arc::new(AtomicBool::new(false));
    let summary = {
        let done = Arc::clone(&done);
        thread::spawn(move || {
            let line = lines.recv_timeout(40 * SECOND).ok();
            done.store(true, Ordering::SeqCst);
            line
        })
    };
    let mut during = Vec::new();
    while !done.load(Ordering::SeqCst) {
        during.extend(latencies(&mut good, 10));
    }
    let summary: Value = summary
        .join()
        .expect("reader")
        .and_then(|l| serde_json::from_str(&l).ok())
        .expect("the peer's summary");
    let out = peer.wait(10 * SECOND).expect("peer exit");
    assert_eq!(out.code, Some(0), "peer failed: {summary} {}", out.stderr);
    let after = p99(latencies(&mut good, 200));
    let during = p99(during);
    eprintln!("{mode} peer ({summary}): good client p99 alone {alone:?}, during {during:?}, after {after:?}");
    (alone, during, after, summary)
}

#[test]
fn a_crashed_rmw_cyclonedds_client_does_not_stall_our_server() {
    let (alone, during, after, summary) = good_client_with_cyclone_peer(130, "stall");
    assert!(
        summary["written"].as_u64().unwrap_or(0) >= 20,
        "the peer sent too little: {summary}"
    );
    let bound = 2 * alone.max(P99_FLOOR);
    assert!(
        during <= bound,
        "p99 with the stalling peer {during:?} > 2 x max(p99 alone {alone:?}, {P99_FLOOR:?})"
    );
    assert!(
        after <= bound,
        "p99 after the peer left {after:?} > {bound:?}"
    );
}

#[test]
fn garbage_from_a_cyclone_peer_costs_nothing_lasting() {
    let (alone, during, after, summary) = good_client_with_cyclone_peer(131, "garbage");
    assert!(
        summary["written"].as_u64().unwrap_or(0) >= 100,
        "the peer sent too little: {summary}"
    );
    let bound = 2 * alone.max(P99_FLOOR);
    assert!(
        during <= bound,
        "p99 with the garbage peer {during:?} > 2 x max(p99 alone {alone:?}, {P99_FLOOR:?})"
    );
    assert!(
        after <= bound,
        "p99 after the peer left {after:?} > {bound:?}"
    );
}

#[test]
fn a_killed_server_is_reported_to_its_client_and_leaves_the_graph_within_its_lease() {
    const DOMAIN: u32 = 132;
    let mut server = Command::new(env!("CARGO_BIN_EXE_horus_add_two_ints_server"))
        .args([&DOMAIN.to_string(), "/doomed", "2000"])
        .env("HORUS_ROS_BACKEND", "cyclone")
        .env("CYCLONEDDS_URI", cyclone_config())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start the server process");
    let stdout = server.stdout.take().expect("server stdout");
    let (tx, rx) = std::sync::mpsc::channel();
    thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let caller_node = node(DOMAIN, "bereaved_client");
    let graph = Graph::of(caller_node.context()).expect("graph");
    let mut c = client(&caller_node, "/doomed");
    assert!(c.wait_for_service(30 * SECOND), "no server");
    let caller = thread::spawn(move || {
        let result = c.call(AddTwoIntsRequest { a: 1, b: 2 }, 60 * SECOND);
        (result, Instant::now())
    });
    let handling = loop {
        match rx.recv_timeout(30 * SECOND) {
            Ok(line) if line.starts_with("handling") => break Instant::now(),
            Ok(_) => continue,
            Err(e) => panic!("the server never started handling the call: {e}"),
        }
    };
    // Half a second into its 2 s handler.
    thread::sleep(Duration::from_millis(500).saturating_sub(handling.elapsed()));
    server.kill().expect("SIGKILL the server");
    let killed = Instant::now();
    server.wait().expect("reap the server");

    let (result, ended) = caller.join().expect("caller");
    let noticed = ended.duration_since(killed);
    eprintln!("the killed server's client got {result:?} {noticed:?} after the kill");
    assert_eq!(
        result,
        Err(ServiceError::Transport(TransportError::ServerGone)),
        "after {noticed:?}"
    );
    assert!(
        noticed <= CYCLONE_LEASE + LEASE_SLACK,
        "the client learnt it after {noticed:?}"
    );
    // The dead participant (its node) has left our graph by then too.
    let left = graph.wait_until(
        (CYCLONE_LEASE + LEASE_SLACK).saturating_sub(killed.elapsed()),
        |cache| !cache.node_names().iter().any(|n| n.name == "doomed_server"),
    );
    eprintln!(
        "the dead server's node left the graph {:?} after the kill",
        killed.elapsed()
    );
    assert!(
        left,
        "the dead server's node is still in the graph after {:?}",
        killed.elapsed()
    );
}
