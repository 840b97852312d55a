//! Raw CDR write/take between two participants, GUID/handle mapping, waiter wake-ups and
//! matched endpoints. Domains 141-143; run inside `scripts/isolated`.
mod common;

use std::time::{Duration, Instant};

use common::*;
use horus_ros_rmw_cyclone::{
    Durability, EndpointQos, GuardCondition, History, Participant, Reader, StatusMask, Waiter,
    Writer,
};

fn pair(domain: u32, topic: &str, qos: &EndpointQos) -> (Participant, Participant, Writer, Reader) {
    let a = participant(domain, "enclave=/a;");
    let b = participant(domain, "enclave=/b;");
    let w = a
        .writer(
            &a.blob_topic(topic, TIME_TYPE).expect("topic"),
            qos,
            TIME_USER_DATA.as_bytes(),
        )
        .expect("writer");
    let r = b
        .reader(
            &b.blob_topic(topic, TIME_TYPE).expect("topic"),
            qos,
            b"typehash=reader;",
        )
        .expect("reader");
    (a, b, w, r)
}

#[test]
fn raw_write_take_with_writer_guid_and_handle() {
    let qos = EndpointQos {
        durability: Durability::TransientLocal,
        history: History::KeepLast(10),
        ..Default::default()
    };
    let (_a, _b, w, r) = pair(141, "rt/rmwc/raw", &qos);
    wait_matched(&w, DISCOVERY);
    let wguid = w.entity().guid().expect("guid");
    let wih = w.entity().instance_handle().expect("instance handle");
    assert_ne!(wih, 0);
    for i in 0..3 {
        w.write(&time_cdr(i, 1000 + i as u32)).expect("write");
    }
    assert!(
        w.write(&[0, 1]).is_err(),
        "a sample without its encapsulation header is refused"
    );

    let waiter = Waiter::new().expect("waiter");
    waiter.attach_reader(&r, 7).expect("attach");
    let mut got = Vec::new();
    let end = Instant::now() + DISCOVERY;
    while got.len() < 3 {
        assert!(
            Instant::now() < end,
            "only {} of 3 samples arrived",
            got.len()
        );
        let woke = waiter.wait(Duration::from_millis(500)).expect("wait");
        assert!(woke.is_empty() || woke == [7]);
        while let Some(s) = r.take().expect("take") {
            got.push(s);
        }
    }
    for (i, s) in got.iter().enumerate() {
        assert_eq!(
            s.cdr,
            time_cdr(i as i32, 1000 + i as u32),
            "bytes incl. header round-trip"
        );
        assert_eq!(s.writer_guid, Some(wguid));
        assert_eq!(
            s.publication_handle, wih,
            "publication handle is the writer's instance handle"
        );
        assert!(s.source_timestamp_ns > 0);
    }
    assert!(r.take().expect("take").is_none());
    // GUIDs: endpoints share their participant's prefix.
    assert_eq!(wguid.participant(), _a.guid().expect("guid"));
    assert_eq!(
        r.entity().guid().expect("guid").participant(),
        _b.guid().expect("guid")
    );
    assert_eq!(wguid.vendor_hint(), horus_ros_rmw_cyclone::vendor::CYCLONE);
}

#[test]
fn waiter_wakes_on_data_and_on_guard() {
    let (_a, _b, w, r) = pair(142, "rt/rmwc/wake", &EndpointQos::default());
    wait_matched(&w, DISCOVERY);
    let guard = GuardCondition::new().expect("guard");
    let waiter = Waiter::new().expect("waiter");
    waiter.attach_reader(&r, 1).expect("attach reader");
    waiter.attach_guard(&guard, 2).expect("attach guard");

    // Nothing pending: times out, bounded.
    let t0 = Instant::now();
    assert!(waiter
        .wait(Duration::from_millis(200))
        .expect("wait")
        .is_empty());
    assert!(t0.elapsed() >= Duration::from_millis(150));

    // Guard set from another thread wakes us.
    let g2 = guard.clone();
    let t = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(100));
        g2.trigger().expect("trigger");
    });
    assert_eq!(waiter.wait(Duration::from_secs(5)).expect("wait"), vec![2]);
    t.join().expect("thread");
    assert!(guard.take().expect("take"), "the guard was triggered");
    assert!(!guard.take().expect("take"), "take resets it");

    // Data wakes us.
    let t0 = Instant::now();
    w.write(&time_cdr(5, 6)).expect("write");
    assert_eq!(waiter.wait(Duration::from_secs(5)).expect("wait"), vec![1]);
    assert!(t0.elapsed() < Duration::from_secs(5));
    assert_eq!(
        r.take().expect("take").map(|s| parse_time(&s.cdr)),
        Some((5, 6))
    );
    assert!(
        waiter
            .wait(Duration::from_millis(50))
            .expect("wait")
            .is_empty(),
        "level-triggered: empty again"
    );

    waiter.detach(2).expect("detach");
    guard.trigger().expect("trigger");
    assert!(
        waiter
            .wait(Duration::from_millis(100))
            .expect("wait")
            .is_empty(),
        "detached guard no longer wakes"
    );
}

#[test]
fn matched_endpoints_with_user_data() {
    let (a, b, w, r) = pair(143, "rt/rmwc/matched", &EndpointQos::default());
    wait_matched(&w, DISCOVERY);
    let subs = w.matched_subscriptions().expect("matched subs");
    assert_eq!(subs.len(), 1);
    assert_eq!(subs[0].guid, r.entity().guid().expect("guid"));
    assert_eq!(subs[0].participant_guid, b.guid().expect("guid"));
    assert_eq!(subs[0].user_data, b"typehash=reader;");
    let waiter = Waiter::new().expect("waiter");
    waiter
        .attach_status(&r.entity(), StatusMask::SUBSCRIPTION_MATCHED, 1)
        .expect("attach");
    let pubs = until(DISCOVERY, &waiter, || {
        let p = r.matched_publications().expect("matched pubs");
        (!p.is_empty()).then_some(p)
    })
    .expect("reader matched the writer");
    assert_eq!(pubs.len(), 1);
    assert_eq!(pubs[0].guid, w.entity().guid().expect("guid"));
    assert_eq!(pubs[0].participant_guid, a.guid().expect("guid"));
    assert_eq!(pubs[0].user_data, TIME_USER_DATA.as_bytes());

    // A best-effort writer cannot match a reliable reader: no match.
    let be = EndpointQos {
        reliability: horus_ros_rmw_cyclone::Reliability::BestEffort,
        ..Default::default()
    };
    let w2 = a
        .writer(
            &a.blob_topic("rt/rmwc/matched", TIME_TYPE).expect("topic"),
            &be,
            b"",
        )
        .expect("writer");
    // A best-effort reader of `b`, announced after `r`: once `w2` matched it, `b`'s
    // announcement of `r` (sent before, in order on the same reliable SEDP writer) has been
    // processed too, so a match with `r` would be there.
    let r2 = b
        .reader(
            &b.blob_topic("rt/rmwc/matched", TIME_TYPE).expect("topic"),
            &be,
            b"",
        )
        .expect("best-effort reader");
    wait_matched(&w2, DISCOVERY);
    let subs = w2.matched_subscriptions().expect("matched");
    assert_eq!(
        subs.iter().map(|s| s.guid).collect::<Vec<_>>(),
        vec![r2.entity().guid().expect("guid")],
        "the best-effort writer matched the best-effort reader only"
    );
    assert_eq!(r.matched_publications().expect("matched").len(), 1);
}

#[test]
fn domain_is_shared_per_id_and_config_must_agree() {
    use horus_ros_rmw_cyclone::Domain;
    let d1 = Domain::acquire(148, &config()).expect("domain");
    let d2 = Domain::acquire(148, &config()).expect("same config: shared");
    let err = Domain::acquire(148, "<CycloneDDS/>").expect_err("different config refused");
    assert!(err.to_string().contains("configured differently"), "{err}");
    drop(d1);
    let p = Participant::new(d2, b"").expect("participant on the remaining reference");
    assert_eq!(p.domain_id(), 148);
    drop(p);
    // All references gone: the domain may now be configured anew.
    let d3 = Domain::acquire(148, &format!("{},<CycloneDDS/>", config())).expect("reconfigured");
    drop(d3);
}

/// A sample with rmw_cyclonedds' request header: client `guid`, sequence number `seq`.
fn with_header(guid: u64, seq: i64) -> Vec<u8> {
    let mut cdr = vec![0, 1, 0, 0];
    cdr.extend_from_slice(&guid.to_le_bytes());
    cdr.extend_from_slice(&seq.to_le_bytes());
    cdr.extend_from_slice(&7i64.to_le_bytes());
    cdr
}

/// Takes from `r` until `n` samples came (bounded), then what is left at once.
fn take_all(r: &Reader, n: usize) -> Vec<Vec<u8>> {
    let waiter = Waiter::new().expect("waiter");
    waiter.attach_reader(r, 1).expect("attach");
    let mut got = Vec::new();
    let end = Instant::now() + DISCOVERY;
    while got.len() < n && Instant::now() < end {
        waiter.wait(Duration::from_millis(500)).expect("wait");
        while let Some(s) = r.take().expect("take") {
            got.push(s.cdr);
        }
    }
    got
}

#[test]
fn a_filtered_topic_stores_only_what_its_filter_keeps_from_remote_and_local_writers() {
    let qos = EndpointQos {
        history: History::KeepLast(100),
        ..Default::default()
    };
    let a = participant(144, "enclave=/a;");
    let b = participant(144, "enclave=/b;");
    let topic = "rr/rmwc/filteredReply";
    let ty = "test::Reply_";
    // Keeps the samples whose header names client 2 (the filter sees the first 20 bytes).
    let mine = |head: &[u8]| {
        head.len() == horus_ros_rmw_cyclone::HEAD_LEN
            && head.get(4..12) == Some(&2u64.to_le_bytes()[..])
    };
    let filtered = b
        .reader(
            &b.filtered_blob_topic(topic, ty, mine).expect("topic"),
            &qos,
            b"",
        )
        .expect("filtered reader");
    let all = b
        .reader(&b.blob_topic(topic, ty).expect("topic"), &qos, b"")
        .expect("reader");
    let remote = a
        .writer(&a.blob_topic(topic, ty).expect("topic"), &qos, b"")
        .expect("writer");
    let local = b
        .writer(&b.blob_topic(topic, ty).expect("topic"), &qos, b"")
        .expect("local writer");
    wait_matched(&remote, DISCOVERY);
    wait_matched(&local, DISCOVERY);
    for seq in 0..10 {
        let w = if seq % 2 == 0 { &remote } else { &local };
        w.write(&with_header(1 + seq as u64 % 3, seq))
            .expect("write");
    }
    // A sample too short to hold a header: the filter sees fewer bytes, and refuses it.
    remote.write(&[0, 1, 0, 0, 2]).expect("write");
    let everything = take_all(&all, 11);
    assert_eq!(
        everything.len(),
        11,
        "the unfiltered reader stores every sample"
    );
    let kept = take_all(&filtered, 3);
    let seqs: Vec<i64> = kept
        .iter()
        .map(|s| i64::from_le_bytes(s[12..20].try_into().expect("seq")))
        .collect();
    assert_eq!(
        seqs,
        vec![1, 4, 7],
        "only client 2's samples, from both writers"
    );
    drop(filtered);
    drop(b);
}
