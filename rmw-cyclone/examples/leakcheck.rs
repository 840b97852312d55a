//! Exercises every resource path of the binding (domain, participants, QoS objects, blob
//! topics, raw write/take serdata references, matched-endpoint data, built-in topic loans,
//! waitsets, read/status/guard conditions, data listeners and their signals) and tears everything down; run under valgrind by
//! `tests/leakcheck.rs`. Domain 147, loopback only: run inside `scripts/isolated`.
use std::time::{Duration, Instant};

use horus_ros_rmw_cyclone::config::{domain_config, DiscoveryRange};
use horus_ros_rmw_cyclone::{
    BuiltinSample, BuiltinTopic, Domain, EndpointQos, GuardCondition, History, Participant, Signal,
    StatusMask, Waiter,
};

const LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";
const ROUNDS: usize = 2;
const SAMPLES: usize = 20;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Twice, so that a domain torn down and created again is covered too.
    for round in 0..ROUNDS {
        run(round)?;
    }
    println!("leakcheck: ok");
    Ok(())
}

fn run(round: usize) -> Result<(), Box<dyn std::error::Error>> {
    let deadline = Instant::now() + Duration::from_secs(60);
    let xml = domain_config(
        DiscoveryRange::Subnet,
        &[],
        std::process::id(),
        Some(LOOPBACK),
    );
    let a = Participant::new(Domain::acquire(147, &xml)?, b"enclave=/a;")?;
    let b = Participant::new(Domain::acquire(147, &xml)?, b"enclave=/b;")?;
    let builtins = [
        b.builtin_reader(BuiltinTopic::Participant)?,
        b.builtin_reader(BuiltinTopic::Publication)?,
        b.builtin_reader(BuiltinTopic::Subscription)?,
    ];
    // Keep every sample: with the default depth (10) the reader would keep only the last 10.
    let qos = EndpointQos {
        history: History::KeepLast(SAMPLES as u32),
        ..EndpointQos::default()
    };
    let w = a.writer(
        &a.blob_topic("rt/leakcheck", "test::Blob_")?,
        &qos,
        b"typehash=RIHS01_w;",
    )?;
    let r = b.reader(
        &b.blob_topic("rt/leakcheck", "test::Blob_")?,
        &qos,
        b"typehash=RIHS01_r;",
    )?;
    // A filtered reader: every sample goes through the sertype's sample allocation,
    // deserialization and release (it keeps those longer than their encapsulation header).
    let filtered = b.reader(
        &b.filtered_blob_topic("rt/leakcheck", "test::Blob_", |head| head.len() > 4)?,
        &qos,
        b"typehash=RIHS01_f;",
    )?;

    let guard = GuardCondition::new()?;
    let waiter = Waiter::new()?;
    waiter.attach_reader(&r, 1)?;
    waiter.attach_guard(&guard, 2)?;
    waiter.attach_status(&w.entity(), StatusMask::PUBLICATION_MATCHED, 3)?;
    for br in &builtins {
        waiter.attach_builtin(br, 4)?;
    }
    while w.publication_matched()?.0 == 0 {
        if Instant::now() > deadline {
            return Err("no match".into());
        }
        waiter.wait(Duration::from_millis(200))?;
        for br in &builtins {
            br.take()?;
        }
    }
    waiter.detach(3)?;

    let body = vec![0xabu8; 1000];
    let mut got = 0;
    let mut kept = 0;
    waiter.attach_reader(&filtered, 5)?;
    // The data listener's path: raised on arrival, the notice detached again before the end.
    let signal = Signal::new();
    let notice = r.notify(&signal, 6);
    for i in 0..SAMPLES {
        let mut cdr = vec![0, 1, 0, 0];
        cdr.extend_from_slice(&(i as u32).to_le_bytes());
        cdr.extend_from_slice(&body);
        w.write(&cdr)?;
    }
    while got < SAMPLES || kept < SAMPLES {
        if Instant::now() > deadline {
            return Err(format!("only {got} samples, {kept} filtered").into());
        }
        waiter.wait(Duration::from_millis(200))?;
        while let Some(s) = r.take()? {
            assert_eq!(s.cdr.len(), 1008);
            assert!(s.writer_guid.is_some());
            got += 1;
        }
        while filtered.take()?.is_some() {
            kept += 1;
        }
        for br in &builtins {
            br.take()?;
        }
    }
    let mut ready = Vec::new();
    assert!(signal.wait(Some(Duration::ZERO), &mut ready));
    assert_eq!(ready, [6]);
    drop(notice);
    assert_eq!(w.matched_subscriptions()?.len(), 2);
    assert_eq!(r.matched_publications()?.len(), 1);
    guard.trigger()?;
    assert!(!waiter.wait(Duration::from_millis(100))?.is_empty());
    assert!(guard.take()?);

    // Deleting the writer produces a not-alive built-in sample (an invalid-data loan).
    let wguid = w.entity().guid()?;
    drop(w);
    let mut lost = false;
    while !lost {
        if Instant::now() > deadline {
            return Err("writer loss not seen".into());
        }
        std::thread::sleep(Duration::from_millis(20));
        lost = builtins[1]
            .take()?
            .iter()
            .any(|s| matches!(s, BuiltinSample::Publication(e) if e.guid == wguid && !e.alive));
    }
    println!("leakcheck: round {round}: {got} samples, writer loss seen");
    Ok(())
}
