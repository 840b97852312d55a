//! Nodes and endpoints on a real participant (run inside the test network namespace).

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::{qos::Qos, Context, NodeError};

/// Each test binary uses its own domains so that nothing else running at once is seen.
const DOMAIN: u32 = 31;

#[test]
fn node_names_are_validated_and_normalised_like_rcl() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    assert!(matches!(
        context.create_node("1abc", "/"),
        Err(NodeError::InvalidName { .. })
    ));
    assert!(matches!(
        context.create_node("my-node", "/"),
        Err(NodeError::InvalidName { .. })
    ));
    assert!(matches!(
        context.create_node("ok", "/bad//ns"),
        Err(NodeError::InvalidNamespace { .. })
    ));
    let n = context.create_node("ok", "").expect("empty namespace is /");
    assert_eq!(n.fully_qualified_name(), "/ok");
    let n = context
        .create_node("ok", "relative/ns")
        .expect("relative namespace made absolute");
    assert_eq!(n.fully_qualified_name(), "/relative/ns/ok");
    // Failed creations announced nothing: exactly the two nodes created are listed.
    assert_eq!(context.announced_entities().node_entities_info_seq.len(), 2);
}

#[test]
fn endpoints_are_listed_under_their_node_until_dropped() {
    let context = Context::builder()
        .domain_id(DOMAIN + 1)
        .build()
        .expect("context");
    let a = context.create_node("a", "/x").expect("node a");
    let b = context
        .create_node("a", "/x")
        .expect("duplicate names are allowed, as in ROS");
    let publisher = a
        .create_publisher::<Time>("t", &Qos::default())
        .expect("publisher");
    let subscription = b
        .create_subscription::<Time>("~/t", &Qos::sensor_data())
        .expect("subscription");
    assert_eq!(publisher.topic_name().as_str(), "/x/t");
    assert_eq!(subscription.topic_name().as_str(), "/x/a/t");

    let info = context.announced_entities();
    assert_eq!(info.gid, context.gid());
    assert_eq!(info.node_entities_info_seq.len(), 2);
    assert_eq!(
        info.node_entities_info_seq[0].writer_gid_seq,
        vec![publisher.gid()]
    );
    assert!(info.node_entities_info_seq[0].reader_gid_seq.is_empty());
    assert_eq!(
        info.node_entities_info_seq[1].reader_gid_seq,
        vec![subscription.gid()]
    );
    // On DDS, GIDs share the participant's GUID prefix (on Zenoh, a GID is the hash of the
    // entity's liveliness token, as rmw_zenoh's).
    if context.backend() != Some(horus_ros_rmw::Backend::Zenoh) {
        assert_eq!(publisher.gid().prefix(), context.gid().prefix());
    }

    drop(publisher);
    assert!(context.announced_entities().node_entities_info_seq[0]
        .writer_gid_seq
        .is_empty());
    drop(a);
    let info = context.announced_entities();
    assert_eq!(info.node_entities_info_seq.len(), 1);
    assert_eq!(
        info.node_entities_info_seq[0].reader_gid_seq,
        vec![subscription.gid()]
    );
    drop(subscription);
    drop(b);
    assert!(context
        .announced_entities()
        .node_entities_info_seq
        .is_empty());
}

#[test]
fn a_message_goes_from_publisher_to_subscription() {
    let context = Context::builder()
        .domain_id(DOMAIN + 2)
        .build()
        .expect("context");
    let node = context.create_node("loop", "/").expect("node");
    let qos = Qos::default().reliable().transient_local();
    let publisher = node
        .create_publisher::<Time>("/stamp", &qos)
        .expect("publisher");
    let mut subscription = node
        .create_subscription::<Time>("/stamp", &qos)
        .expect("subscription");
    let sent = Time {
        sec: 12,
        nanosec: 34,
    };
    publisher.publish(sent).expect("publish");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    let got = loop {
        if let Some(t) = subscription.try_take().expect("take") {
            break t;
        }
        let now = std::time::Instant::now();
        assert!(now < deadline, "no sample within 10 s");
        // Woken by the sample's arrival.
        subscription.wait(deadline - now);
    };
    assert_eq!(got, sent);
}

#[test]
fn invalid_topic_names_are_errors() {
    let context = Context::builder()
        .domain_id(DOMAIN + 3)
        .build()
        .expect("context");
    let node = context.create_node("n", "/").expect("node");
    assert!(node
        .create_publisher::<Time>("bad name", &Qos::default())
        .is_err());
    assert!(node
        .create_publisher::<Time>("{unknown}", &Qos::default())
        .is_err());
    assert!(node
        .create_subscription::<Time>("", &Qos::default())
        .is_err());
    assert!(context.announced_entities().node_entities_info_seq[0]
        .writer_gid_seq
        .is_empty());
}

#[test]
fn domain_ids_above_232_are_refused() {
    assert!(Context::builder().domain_id(233).build().is_err());
}
