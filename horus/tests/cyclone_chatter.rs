//! HORUS talker and listener against an independent DDS implementation: a Cyclone DDS (Python)
//! peer on `/chatter` as demo_nodes uses it (`interop-tests/peers/cyclone_chatter.py`), both
//! directions, inside the test network namespace. Each test has its own domain.

mod common;

use common::{hear, run_listener, run_talker, LIMIT};
use interop_tests::Peer;

#[test]
fn a_horus_talker_is_heard_by_a_cyclone_dds_listener() {
    let domain = 191;
    let peer = Peer::start(
        "cyclone_chatter.py",
        &[domain.to_string(), "listen".into(), "3".into(), "25".into()],
    )
    .expect("peer");
    let talker = run_talker(domain);
    let out = peer.wait(LIMIT).expect("peer output");
    assert_eq!(talker.stop(), Ok(()));
    assert_eq!(out.code, Some(0), "{out:?}");
    let heard: Vec<_> = out
        .stdout
        .lines()
        .filter(|l| l.starts_with("I heard: [Hello World: "))
        .collect();
    assert_eq!(heard.len(), 3, "{out:?}");
}

#[test]
fn a_horus_listener_hears_a_cyclone_dds_talker() {
    let domain = 192;
    let (listener, heard) = run_listener(domain);
    let peer = Peer::start(
        "cyclone_chatter.py",
        &[domain.to_string(), "talk".into(), "0".into(), "20".into()],
    )
    .expect("peer");
    let got = hear(&heard, 3);
    drop(peer);
    let (outcome, metrics) = listener.stop();
    assert_eq!(outcome, Ok(()));
    assert!(
        got.iter().all(|m| m.starts_with("Hello World: ")),
        "{got:?}"
    );
    assert!(metrics.expect("metrics").messages_received >= 3);
}
