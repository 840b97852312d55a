//! Set-up shared by rmw's integration tests: raw endpoint specs and waiting for matches.

use std::collections::HashSet;
use std::time::{Duration, Instant};

use horus_ros_msgs::{Message, TypeHash};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{DiscoveryEvent, DiscoveryFeed, Gid, RawEndpointSpec};

/// How long a test waits for discovery.
pub const LIMIT: Duration = Duration::from_secs(10);

/// A raw endpoint of `topic` (a mangled DDS topic name) with the services' default QoS.
pub fn spec(topic: &str) -> RawEndpointSpec {
    RawEndpointSpec {
        dds_topic_name: topic.to_owned(),
        dds_type_name: horus_ros_msgs::builtin_interfaces::msg::Time::dds_type_name(),
        type_hash: TypeHash::ZERO,
        qos: Qos::services_default(),
        service_id: None,
    }
}

/// Waits (on the feed's events) until each writer is matched with its reader, both ways.
pub fn await_matches(feed: &mut DiscoveryFeed, pairs: &[(Gid, Gid)]) {
    let mut missing: HashSet<(Gid, Gid)> =
        pairs.iter().flat_map(|&(w, r)| [(w, r), (r, w)]).collect();
    let deadline = Instant::now() + LIMIT;
    while !missing.is_empty() {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "not matched within {LIMIT:?}: {missing:?}");
        if let Some(DiscoveryEvent::Matched { local, remote }) = feed.next_timeout(left) {
            missing.remove(&(local, remote));
        }
    }
}
