//! HORUS talker and listener against an independent DDS implementation: a Cyclone DDS (Python)
//! peer on `/chatter` as demo_nodes uses it (`interop-tests/peers/cyclone_chatter.py`), both
//! directions, inside the test network namespace. Each test has its own domain.

use std::sync::mpsc;
use std::time::Duration;

use horus::prelude::*;
use horus::ros::{Arguments, Context};
use interop_tests::Peer;

const LIMIT: Duration = Duration::from_secs(30);

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .arguments(Arguments::default())
        .build()
        .expect("context")
}

struct Talker {
    chatter: Topic<StringMsg>,
    count: u64,
}

impl Node for Talker {
    fn name(&self) -> &str {
        "talker"
    }
    fn tick(&mut self) {
        self.count += 1;
        self.chatter.send(StringMsg {
            data: format!("Hello World: {}", self.count),
        });
    }
}

#[test]
fn a_horus_talker_is_heard_by_a_cyclone_dds_listener() {
    let domain = 191;
    let peer = Peer::start(
        "cyclone_chatter.py",
        &[domain.to_string(), "listen".into(), "3".into(), "25".into()],
    )
    .expect("peer");
    let mut sched = Scheduler::new()
        .context(context(domain))
        .tick_rate(20_u64.hz())
        .print_report(false);
    sched
        .add(Talker {
            chatter: Topic::new("chatter").expect("topic"),
            count: 0,
        })
        .build()
        .expect("talker");
    let stop = sched.stop_handle();
    let runner = std::thread::spawn(move || sched.run().map_err(|e| e.to_string()));
    let out = peer.wait(LIMIT).expect("peer output");
    stop.stop();
    assert_eq!(runner.join().expect("scheduler"), Ok(()));
    assert_eq!(out.code, Some(0), "{out:?}");
    let heard: Vec<_> = out
        .stdout
        .lines()
        .filter(|l| l.starts_with("I heard: [Hello World: "))
        .collect();
    assert_eq!(heard.len(), 3, "{out:?}");
}

struct Listener {
    chatter: Topic<StringMsg>,
    heard: mpsc::Sender<String>,
}

impl Node for Listener {
    fn name(&self) -> &str {
        "listener"
    }
    fn init(&mut self) -> Result<()> {
        self.chatter.connect_subscriber()?;
        Ok(())
    }
    fn tick(&mut self) {
        while let Some(m) = self.chatter.try_recv() {
            let _ = self.heard.send(m.data);
        }
    }
}

#[test]
fn a_horus_listener_hears_a_cyclone_dds_talker() {
    let domain = 192;
    let (tx, heard) = mpsc::channel();
    let mut sched = Scheduler::new()
        .context(context(domain))
        .tick_rate(100_u64.hz())
        .print_report(false);
    sched
        .add(Listener {
            chatter: Topic::new("chatter").expect("topic"),
            heard: tx,
        })
        .build()
        .expect("listener");
    let stop = sched.stop_handle();
    let runner = std::thread::spawn(move || {
        let outcome = sched.run().map_err(|e| e.to_string());
        (outcome, sched.get_node_metrics("listener"))
    });
    let peer = Peer::start(
        "cyclone_chatter.py",
        &[domain.to_string(), "talk".into(), "0".into(), "20".into()],
    )
    .expect("peer");
    let mut got = Vec::new();
    while got.len() < 3 {
        match heard.recv_timeout(LIMIT) {
            Ok(m) => got.push(m),
            Err(_) => panic!("heard only {got:?}"),
        }
    }
    drop(peer);
    stop.stop();
    let (outcome, metrics) = runner.join().expect("scheduler");
    assert_eq!(outcome, Ok(()));
    assert!(
        got.iter().all(|m| m.starts_with("Hello World: ")),
        "{got:?}"
    );
    assert!(metrics.expect("metrics").messages_received >= 3);
}
