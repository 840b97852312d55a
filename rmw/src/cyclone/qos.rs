//! QoS between our profiles and the binding layer's `EndpointQos`, through the rustdds policies
//! our profiles already map to (one mapping for both backends: see `qos/dds.rs`).

use std::time::Duration;

use horus_ros_rmw_cyclone::{self as cyc, EndpointQos};
use rustdds::policy;

use crate::qos::{EndpointKind, Qos};

/// The Cyclone QoS for a writer or reader created with these rustdds policies (which
/// `Qos::to_dds` always fills: history, reliability, durability, liveliness).
pub(crate) fn endpoint_qos(p: &rustdds::QosPolicies) -> EndpointQos {
    let mut q = EndpointQos::default();
    match p.reliability() {
        Some(policy::Reliability::BestEffort) => q.reliability = cyc::Reliability::BestEffort,
        Some(policy::Reliability::Reliable { max_blocking_time }) => {
            q.reliability = cyc::Reliability::Reliable;
            q.max_blocking_time = duration(max_blocking_time).unwrap_or(Duration::MAX);
        }
        None => {}
    }
    q.durability = match p.durability() {
        Some(policy::Durability::TransientLocal) => cyc::Durability::TransientLocal,
        _ => cyc::Durability::Volatile,
    };
    q.history = match p.history() {
        Some(policy::History::KeepAll) => cyc::History::KeepAll,
        Some(policy::History::KeepLast { depth }) => {
            cyc::History::KeepLast(u32::try_from(depth.max(1)).unwrap_or(u32::MAX))
        }
        None => cyc::History::KeepLast(1),
    };
    q.deadline = p.deadline().and_then(|d| duration(d.0));
    q.lifespan = p.lifespan().and_then(|l| duration(l.duration));
    match p.liveliness() {
        Some(policy::Liveliness::ManualByTopic { lease_duration }) => {
            q.liveliness = cyc::Liveliness::ManualByTopic;
            q.liveliness_lease = duration(lease_duration);
        }
        Some(
            policy::Liveliness::Automatic { lease_duration }
            | policy::Liveliness::ManualByParticipant { lease_duration },
        ) => {
            q.liveliness = cyc::Liveliness::Automatic;
            q.liveliness_lease = duration(lease_duration);
        }
        None => {}
    }
    q
}

/// A finite DDS duration; `None` for infinite.
fn duration(d: rustdds::Duration) -> Option<Duration> {
    if d == rustdds::Duration::INFINITE {
        return None;
    }
    Some(Duration::from_nanos(
        u64::try_from(d.to_nanoseconds()).unwrap_or(0),
    ))
}

fn dds_duration(d: Option<Duration>) -> rustdds::Duration {
    match d {
        None => rustdds::Duration::INFINITE,
        Some(d) => rustdds::Duration::from_nanos(i64::try_from(d.as_nanos()).unwrap_or(i64::MAX)),
    }
}

/// The ROS view of a discovered endpoint's QoS, as for the rustdds backend: history is not
/// carried by discovery, so it is UNKNOWN (see `Qos::from_dds`).
pub(crate) fn discovered(q: &EndpointQos, kind: EndpointKind) -> Qos {
    let reliability = match q.reliability {
        cyc::Reliability::BestEffort => policy::Reliability::BestEffort,
        cyc::Reliability::Reliable => policy::Reliability::Reliable {
            max_blocking_time: dds_duration(Some(q.max_blocking_time)),
        },
    };
    let durability = match q.durability {
        cyc::Durability::Volatile => policy::Durability::Volatile,
        cyc::Durability::TransientLocal => policy::Durability::TransientLocal,
    };
    let lease_duration = dds_duration(q.liveliness_lease);
    let liveliness = match q.liveliness {
        cyc::Liveliness::Automatic => policy::Liveliness::Automatic { lease_duration },
        cyc::Liveliness::ManualByTopic => policy::Liveliness::ManualByTopic { lease_duration },
    };
    let policies = rustdds::QosPolicyBuilder::new()
        .reliability(reliability)
        .durability(durability)
        .liveliness(liveliness)
        .deadline(policy::Deadline(dds_duration(q.deadline)))
        .lifespan(policy::Lifespan {
            duration: dds_duration(q.lifespan),
        })
        .build();
    Qos::from_dds(&policies, kind)
}

/// `ros_discovery_info`'s QoS: RELIABLE, TRANSIENT_LOCAL, KEEP_LAST `depth` (0: KEEP_ALL).
pub(crate) fn discovery_info(depth: u32) -> EndpointQos {
    EndpointQos {
        reliability: cyc::Reliability::Reliable,
        max_blocking_time: Duration::MAX,
        durability: cyc::Durability::TransientLocal,
        history: if depth == 0 {
            cyc::History::KeepAll
        } else {
            cyc::History::KeepLast(depth)
        },
        ..EndpointQos::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::qos::{DurabilityPolicy, HistoryPolicy, ReliabilityPolicy};

    #[test]
    fn profiles_map_and_come_back() {
        let profile = Qos::default_profile()
            .best_effort()
            .transient_local()
            .keep_last(7)
            .with_deadline(Duration::from_millis(250));
        let dds = profile.to_dds(EndpointKind::Writer).expect("valid profile");
        let q = endpoint_qos(&dds);
        assert_eq!(q.reliability, cyc::Reliability::BestEffort);
        assert_eq!(q.durability, cyc::Durability::TransientLocal);
        assert_eq!(q.history, cyc::History::KeepLast(7));
        assert_eq!(q.deadline, Some(Duration::from_millis(250)));
        assert_eq!(q.lifespan, None);
        let back = discovered(&q, EndpointKind::Writer);
        assert_eq!(back.reliability, ReliabilityPolicy::BestEffort);
        assert_eq!(back.durability, DurabilityPolicy::TransientLocal);
        assert_eq!(back.history, HistoryPolicy::Unknown);
        assert_eq!(back.deadline.total_nanos(), 250_000_000);
        assert!(back.lifespan.is_infinite());
        let all = endpoint_qos(
            &Qos::default_profile()
                .keep_all()
                .to_dds(EndpointKind::Reader)
                .expect("valid profile"),
        );
        assert_eq!(all.history, cyc::History::KeepAll);
        assert_eq!(all.reliability, cyc::Reliability::Reliable);
    }
}
