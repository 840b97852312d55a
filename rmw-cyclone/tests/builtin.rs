//! Built-in topics: participant and endpoint USER_DATA, QoS, and loss (alive = false).
//! Domains 144-145; run inside `scripts/isolated`.
mod common;

use std::time::Duration;

use common::*;
use horus_ros_rmw_cyclone::{
    BuiltinReader, BuiltinSample, BuiltinTopic, Durability, EndpointInfo, EndpointQos, History,
    Liveliness, ParticipantInfo, Reliability,
};

fn collect(readers: &[&BuiltinReader], into: &mut Vec<BuiltinSample>) {
    for r in readers {
        into.extend(r.take().expect("take builtin"));
    }
}

#[test]
fn user_data_and_qos_through_builtin_topics() {
    let observer = participant(144, "enclave=/observer;");
    let parts = observer
        .builtin_reader(BuiltinTopic::Participant)
        .expect("reader");
    let pubs = observer
        .builtin_reader(BuiltinTopic::Publication)
        .expect("reader");
    let subs = observer
        .builtin_reader(BuiltinTopic::Subscription)
        .expect("reader");
    assert_eq!(pubs.topic(), BuiltinTopic::Publication);

    let a = participant(144, "enclave=/a;");
    let qos = EndpointQos {
        reliability: Reliability::Reliable,
        durability: Durability::TransientLocal,
        history: History::KeepLast(7),
        deadline: Some(Duration::from_secs(2)),
        lifespan: Some(Duration::from_millis(1500)),
        liveliness: Liveliness::Automatic,
        liveliness_lease: Some(Duration::from_secs(3)),
        ..Default::default()
    };
    let topic = a.blob_topic("rt/rmwc/builtin", TIME_TYPE).expect("topic");
    let w = a
        .writer(&topic, &qos, TIME_USER_DATA.as_bytes())
        .expect("writer");
    let be = EndpointQos {
        reliability: Reliability::BestEffort,
        history: History::KeepAll,
        ..Default::default()
    };
    let r = a
        .reader(&topic, &be, b"typehash=RIHS01_00;")
        .expect("reader");
    let (aguid, wguid, rguid) = (
        a.guid().expect("g"),
        w.entity().guid().expect("g"),
        r.entity().guid().expect("g"),
    );

    let mut seen = Vec::new();
    let waiter = builtin_waiter(&[&parts, &pubs, &subs]);
    let found = until(DISCOVERY, &waiter, || {
        collect(&[&parts, &pubs, &subs], &mut seen);
        let p = seen.iter().find_map(|s| match s {
            BuiltinSample::Participant(p) if p.guid == aguid => Some(p.clone()),
            _ => None,
        })?;
        let wi = seen.iter().find_map(|s| match s {
            BuiltinSample::Publication(e) if e.guid == wguid => Some(e.clone()),
            _ => None,
        })?;
        let ri = seen.iter().find_map(|s| match s {
            BuiltinSample::Subscription(e) if e.guid == rguid => Some(e.clone()),
            _ => None,
        })?;
        Some((p, wi, ri))
    });
    let (p, wi, ri): (ParticipantInfo, EndpointInfo, EndpointInfo) =
        found.expect("all three discovered");
    assert!(p.alive);
    assert_eq!(p.user_data, b"enclave=/a;");
    assert!(wi.alive);
    assert_eq!(wi.participant_guid, aguid);
    assert_eq!(wi.topic_name, "rt/rmwc/builtin");
    assert_eq!(wi.type_name, TIME_TYPE);
    assert_eq!(wi.user_data, TIME_USER_DATA.as_bytes());
    let wq = wi.qos.expect("writer qos");
    assert_eq!(wq.reliability, Reliability::Reliable);
    assert_eq!(wq.durability, Durability::TransientLocal);
    assert_eq!(wq.history, History::KeepLast(7));
    assert_eq!(wq.deadline, Some(Duration::from_secs(2)));
    assert_eq!(wq.lifespan, Some(Duration::from_millis(1500)));
    assert_eq!(wq.liveliness_lease, Some(Duration::from_secs(3)));
    assert_eq!(ri.user_data, b"typehash=RIHS01_00;");
    let rq = ri.qos.expect("reader qos");
    assert_eq!(rq.reliability, Reliability::BestEffort);
    assert_eq!(rq.history, History::KeepAll);
    assert_eq!(rq.deadline, None);
    // Our own participant is in DCPSParticipant too, with its USER_DATA.
    let me = observer.guid().expect("g");
    assert!(seen.iter().any(|s| matches!(s, BuiltinSample::Participant(p) if p.guid == me && p.user_data == b"enclave=/observer;")));
}

#[test]
fn loss_shows_as_not_alive() {
    let observer = participant(145, "enclave=/observer;");
    let parts = observer
        .builtin_reader(BuiltinTopic::Participant)
        .expect("reader");
    let pubs = observer
        .builtin_reader(BuiltinTopic::Publication)
        .expect("reader");
    let a = participant(145, "enclave=/a;");
    let w = a
        .writer(
            &a.blob_topic("rt/rmwc/loss", TIME_TYPE).expect("t"),
            &EndpointQos::default(),
            b"",
        )
        .expect("w");
    let (aguid, wguid) = (a.guid().expect("g"), w.entity().guid().expect("g"));
    let mut seen = Vec::new();
    let waiter = builtin_waiter(&[&parts, &pubs]);
    until(DISCOVERY, &waiter, || {
        collect(&[&pubs], &mut seen);
        seen.iter()
            .any(|s| matches!(s, BuiltinSample::Publication(e) if e.guid == wguid && e.alive))
            .then_some(())
    })
    .expect("writer discovered");

    drop(w);
    let gone = until(DISCOVERY, &waiter, || {
        pubs.take()
            .expect("take")
            .into_iter()
            .find_map(|s| match s {
                BuiltinSample::Publication(e) if e.guid == wguid => Some(e),
                _ => None,
            })
    })
    .expect("writer deletion reported");
    assert!(!gone.alive);
    assert!(gone.user_data.is_empty() && gone.qos.is_none());

    drop(a);
    let gone = until(DISCOVERY, &waiter, || {
        parts
            .take()
            .expect("take")
            .into_iter()
            .find_map(|s| match s {
                BuiltinSample::Participant(p) if p.guid == aguid && !p.alive => Some(p),
                _ => None,
            })
    });
    assert!(gone.is_some(), "participant deletion reported");
}
