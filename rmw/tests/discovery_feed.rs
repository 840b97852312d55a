//! The discovery feed reports the context's own participant, nodes and endpoints (DDS discovery
//! reports only remote ones): a snapshot when it opens, then every change in order.

use std::time::Duration;

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::{EndpointKind, Qos};
use horus_ros_rmw::{Context, DiscoveryEvent, DiscoveryFeedError};

const DOMAIN: u32 = 36;

/// The next event that is not a match report (matches of our own `ros_discovery_info` reader
/// and writer come and go in between).
fn next_within(
    feed: &mut horus_ros_rmw::DiscoveryFeed,
    timeout: Duration,
) -> Option<DiscoveryEvent> {
    let deadline = std::time::Instant::now() + timeout;
    loop {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        match feed.next_timeout(left)? {
            DiscoveryEvent::Matched { .. } => continue,
            event => return Some(event),
        }
    }
}

fn next(feed: &mut horus_ros_rmw::DiscoveryFeed) -> DiscoveryEvent {
    next_within(feed, Duration::from_secs(5)).expect("an event within 5 s")
}

#[test]
fn own_entities_are_reported_as_snapshot_then_changes() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("me", "/ns").expect("node");
    let publisher = node
        .create_publisher::<Time>("t", &Qos::default())
        .expect("publisher");

    let mut feed = context.discovery_feed().expect("feed");
    assert!(matches!(
        context.discovery_feed(),
        Err(DiscoveryFeedError::AlreadyOpen)
    ));
    match next(&mut feed) {
        DiscoveryEvent::ParticipantDiscovered(p) => {
            assert_eq!(p.gid, context.gid());
            assert_eq!(p.vendor_id, context.vendor_id());
        }
        other => panic!("expected our participant first, got {other:?}"),
    }
    match next(&mut feed) {
        DiscoveryEvent::EndpointDiscovered(e) => {
            assert_eq!(e.gid, publisher.gid());
            assert_eq!(e.participant_gid, context.gid());
            assert_eq!(e.kind, EndpointKind::Writer);
            assert_eq!(e.dds_topic_name, "rt/ns/t");
            assert_eq!(e.dds_type_name, "builtin_interfaces::msg::dds_::Time_");
            assert_eq!(e.type_hash, Time::type_hash());
            // What peers receive: rmw_cyclonedds' `typehash=` where the backend announces
            // USER_DATA (Cyclone), nothing on rustdds.
            let user_data = if context.capabilities().announces_user_data {
                format!("typehash={};", Time::type_hash()).into_bytes()
            } else {
                Vec::new()
            };
            assert_eq!(e.user_data, user_data, "on {:?}", context.backend());
        }
        other => panic!("expected our writer, got {other:?}"),
    }
    match next(&mut feed) {
        DiscoveryEvent::ParticipantEntities(info) => assert_eq!(info, context.announced_entities()),
        other => panic!("expected our ros_discovery_info, got {other:?}"),
    }

    let gid = publisher.gid();
    drop(publisher);
    assert_eq!(
        next(&mut feed),
        DiscoveryEvent::EndpointLost {
            gid,
            kind: EndpointKind::Writer
        }
    );
    match next(&mut feed) {
        DiscoveryEvent::ParticipantEntities(info) => {
            assert!(info.node_entities_info_seq[0].writer_gid_seq.is_empty());
        }
        other => panic!("expected the republished message, got {other:?}"),
    }
    drop(node);
    match next(&mut feed) {
        DiscoveryEvent::ParticipantEntities(info) => {
            assert!(info.node_entities_info_seq.is_empty())
        }
        other => panic!("expected the node's removal, got {other:?}"),
    }
    // Nothing else about ourselves arrives (DDS discovery of our own entities is filtered).
    assert_eq!(next_within(&mut feed, Duration::from_millis(300)), None);

    drop(feed);
    if let Err(e) = context.discovery_feed() {
        panic!("a dropped feed can be opened again, but: {e}");
    }
}

#[test]
fn a_wake_before_a_wait_ends_that_wait_even_after_a_try_next() {
    // As a graph stops: it wakes the feed while its reader is between a `try_next` (which finds
    // nothing) and the unbounded wait that follows; that wait must still end.
    let context = Context::builder()
        .domain_id(DOMAIN + 1)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("feed");
    while feed.try_next().is_some() {}
    feed.waker().wake();
    while feed.try_next().is_some() {}
    let (ended, wait_ended) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        // Events may still come (matches of our own ros_discovery_info endpoints): each ends
        // a wait too; the wake must end the first wait that has nothing to report.
        while feed.next_timeout(None).is_some() {}
        let _ = ended.send(());
    });
    assert!(
        wait_ended.recv_timeout(Duration::from_secs(20)).is_ok(),
        "the wake was lost: the wait has not ended"
    );
}
