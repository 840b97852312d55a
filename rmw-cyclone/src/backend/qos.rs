//! [`DdsQos`] as the binding layer's `EndpointQos`, and back (what Cyclone's built-in topics
//! report of a remote endpoint).

use std::time::Duration;

use crate::{self as cyc, EndpointQos};

use horus_ros_rmw_contract::qos::{
    DdsDurability, DdsHistory, DdsLiveliness, DdsQos, DdsReliability, Qos,
};

/// The Cyclone QoS for a writer or reader with `qos`. Cyclone has no TRANSIENT, PERSISTENT or
/// MANUAL_BY_PARTICIPANT here (ROS maps to none of them): they become TRANSIENT_LOCAL and
/// AUTOMATIC.
pub(crate) fn endpoint_qos(qos: &DdsQos) -> EndpointQos {
    let mut q = EndpointQos::default();
    match qos.reliability {
        DdsReliability::BestEffort => q.reliability = cyc::Reliability::BestEffort,
        DdsReliability::Reliable { max_blocking_time } => {
            q.reliability = cyc::Reliability::Reliable;
            q.max_blocking_time = max_blocking_time;
        }
    }
    q.durability = match qos.durability {
        DdsDurability::Volatile => cyc::Durability::Volatile,
        DdsDurability::TransientLocal | DdsDurability::Transient | DdsDurability::Persistent => {
            cyc::Durability::TransientLocal
        }
    };
    q.history = match qos.history {
        Some(DdsHistory::KeepAll) => cyc::History::KeepAll,
        Some(DdsHistory::KeepLast(depth)) => cyc::History::KeepLast(depth.max(1)),
        None => cyc::History::KeepLast(1),
    };
    q.deadline = qos.deadline;
    q.lifespan = qos.lifespan;
    q.liveliness = match qos.liveliness {
        DdsLiveliness::ManualByTopic => cyc::Liveliness::ManualByTopic,
        DdsLiveliness::Automatic | DdsLiveliness::ManualByParticipant => cyc::Liveliness::Automatic,
    };
    q.liveliness_lease = qos.liveliness_lease;
    q
}

/// What Cyclone reports of an endpoint. Its history is what Cyclone DDS's built-in topics give
/// (the HISTORY a Cyclone DDS peer announces in its discovery data, else the DDS default that
/// Cyclone fills in, KEEP_LAST 1), as rmw_cyclonedds reports it (jazzy `rmw_node.cpp`
/// `dds_qos_to_rmw_qos` on the built-in topics' samples).
fn dds_qos(q: &EndpointQos) -> DdsQos {
    DdsQos {
        reliability: match q.reliability {
            cyc::Reliability::BestEffort => DdsReliability::BestEffort,
            cyc::Reliability::Reliable => DdsReliability::Reliable {
                max_blocking_time: q.max_blocking_time,
            },
        },
        durability: match q.durability {
            cyc::Durability::Volatile => DdsDurability::Volatile,
            cyc::Durability::TransientLocal => DdsDurability::TransientLocal,
        },
        history: Some(match q.history {
            cyc::History::KeepAll => DdsHistory::KeepAll,
            cyc::History::KeepLast(depth) => DdsHistory::KeepLast(depth),
        }),
        deadline: q.deadline,
        lifespan: q.lifespan,
        liveliness: match q.liveliness {
            cyc::Liveliness::Automatic => DdsLiveliness::Automatic,
            cyc::Liveliness::ManualByTopic => DdsLiveliness::ManualByTopic,
        },
        liveliness_lease: q.liveliness_lease,
    }
}

/// The ROS view of a discovered endpoint's QoS, as rmw_cyclonedds gives it (history included).
pub(crate) fn discovered(q: &EndpointQos) -> Qos {
    Qos::from_dds(&dds_qos(q))
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
    use horus_ros_rmw_contract::qos::{
        DurabilityPolicy, EndpointKind, HistoryPolicy, ReliabilityPolicy,
    };

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
        assert_eq!(dds_qos(&q), dds);
        let back = discovered(&q);
        assert_eq!(back.reliability, ReliabilityPolicy::BestEffort);
        assert_eq!(back.durability, DurabilityPolicy::TransientLocal);
        assert_eq!(back.history, HistoryPolicy::KeepLast);
        assert_eq!(back.depth, 7);
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
        assert_eq!(
            all.max_blocking_time,
            horus_ros_rmw_contract::qos::RELIABLE_MAX_BLOCKING_TIME
        );
    }
}
