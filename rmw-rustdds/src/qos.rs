//! [`DdsQos`] as rustdds [`QosPolicies`], and back (what SEDP carried of a remote endpoint).

use std::time::Duration;

use rustdds::policy::{Deadline, Durability, History, Lifespan, Liveliness, Reliability};
use rustdds::{QosPolicies, QosPolicyBuilder};

use horus_ros_rmw_contract::qos::{
    DdsDurability, DdsHistory, DdsLiveliness, DdsQos, DdsReliability, EndpointKind,
};

/// A duration as rustdds counts it (`None`: infinite).
fn to_rustdds_duration(d: Option<Duration>) -> rustdds::Duration {
    match d {
        None => rustdds::Duration::INFINITE,
        Some(d) => rustdds::Duration::from_nanos(i64::try_from(d.as_nanos()).unwrap_or(i64::MAX)),
    }
}

/// A rustdds duration; `None` for infinite and for negative ones (rmw `rmw_time_from_nsec`).
fn from_rustdds_duration(d: rustdds::Duration) -> Option<Duration> {
    if d == rustdds::Duration::INFINITE {
        return None;
    }
    // RTPS durations count 2^-32 s; rustdds's to_nanoseconds rounds down, so a value made by
    // from_nanos(n) can come back as n - 1. Take the n that maps back to exactly `d`.
    let nanos = d.to_nanoseconds();
    let nanos = match nanos.checked_add(1) {
        Some(up) if rustdds::Duration::from_nanos(up) == d => up,
        _ => nanos,
    };
    u64::try_from(nanos).ok().map(Duration::from_nanos)
}

/// The rustdds policies for `qos` (deadline and lifespan only when finite: DDS's default is
/// infinite).
pub(crate) fn to_rustdds(qos: &DdsQos) -> QosPolicies {
    let reliability = match qos.reliability {
        DdsReliability::BestEffort => Reliability::BestEffort,
        DdsReliability::Reliable { max_blocking_time } => Reliability::Reliable {
            max_blocking_time: to_rustdds_duration(Some(max_blocking_time)),
        },
    };
    let durability = match qos.durability {
        DdsDurability::Volatile => Durability::Volatile,
        DdsDurability::TransientLocal => Durability::TransientLocal,
        DdsDurability::Transient => Durability::Transient,
        DdsDurability::Persistent => Durability::Persistent,
    };
    let lease_duration = to_rustdds_duration(qos.liveliness_lease);
    let liveliness = match qos.liveliness {
        DdsLiveliness::Automatic => Liveliness::Automatic { lease_duration },
        DdsLiveliness::ManualByParticipant => Liveliness::ManualByParticipant { lease_duration },
        DdsLiveliness::ManualByTopic => Liveliness::ManualByTopic { lease_duration },
    };
    let mut builder = QosPolicyBuilder::new()
        .reliability(reliability)
        .durability(durability)
        .liveliness(liveliness);
    match qos.history {
        Some(DdsHistory::KeepLast(depth)) => {
            builder = builder.history(History::KeepLast {
                depth: i32::try_from(depth).unwrap_or(i32::MAX),
            });
        }
        Some(DdsHistory::KeepAll) => builder = builder.history(History::KeepAll),
        None => {}
    }
    if let Some(d) = qos.deadline {
        builder = builder.deadline(Deadline(to_rustdds_duration(Some(d))));
    }
    if let Some(d) = qos.lifespan {
        builder = builder.lifespan(Lifespan {
            duration: to_rustdds_duration(Some(d)),
        });
    }
    builder.build()
}

/// What rustdds `policies` of an endpoint of `kind` say; a policy absent from them takes its
/// DDS default ([`DdsQos::dds_defaults`]).
pub(crate) fn from_rustdds(policies: &QosPolicies, kind: EndpointKind) -> DdsQos {
    let mut qos = DdsQos::dds_defaults(kind);
    qos.history = policies.history().map(|h| match h {
        History::KeepLast { depth } => DdsHistory::KeepLast(depth.unsigned_abs()),
        History::KeepAll => DdsHistory::KeepAll,
    });
    if let Some(r) = policies.reliability() {
        qos.reliability = match r {
            Reliability::BestEffort => DdsReliability::BestEffort,
            Reliability::Reliable { max_blocking_time } => DdsReliability::Reliable {
                max_blocking_time: from_rustdds_duration(max_blocking_time)
                    .unwrap_or(Duration::MAX),
            },
        };
    }
    if let Some(d) = policies.durability() {
        qos.durability = match d {
            Durability::Volatile => DdsDurability::Volatile,
            Durability::TransientLocal => DdsDurability::TransientLocal,
            Durability::Transient => DdsDurability::Transient,
            Durability::Persistent => DdsDurability::Persistent,
        };
    }
    qos.deadline = policies.deadline().and_then(|d| from_rustdds_duration(d.0));
    qos.lifespan = policies
        .lifespan()
        .and_then(|l| from_rustdds_duration(l.duration));
    if let Some(l) = policies.liveliness() {
        qos.liveliness = match l {
            Liveliness::Automatic { .. } => DdsLiveliness::Automatic,
            Liveliness::ManualByParticipant { .. } => DdsLiveliness::ManualByParticipant,
            Liveliness::ManualByTopic { .. } => DdsLiveliness::ManualByTopic,
        };
        qos.liveliness_lease = from_rustdds_duration(l.duration());
    }
    qos
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_rmw_contract::qos::{DurabilityPolicy, LivelinessPolicy, Qos, MAX_DDS_DURATION};

    /// What SEDP carries of a local endpoint's policies: no history, no resource limits
    /// (rustdds `sedp_messages.rs` `qos()`).
    fn as_discovered(p: &QosPolicies) -> QosPolicies {
        let mut b = QosPolicyBuilder::new();
        if let Some(x) = p.durability() {
            b = b.durability(x);
        }
        if let Some(x) = p.deadline() {
            b = b.deadline(x);
        }
        if let Some(x) = p.liveliness() {
            b = b.liveliness(x);
        }
        if let Some(x) = p.reliability() {
            b = b.reliability(x);
        }
        if let Some(x) = p.lifespan() {
            b = b.lifespan(x);
        }
        b.build()
    }

    #[test]
    fn profiles_survive_rustdds_and_sedp() {
        let custom = horus_ros_rmw_contract::qos::unusual_profile();
        for kind in [EndpointKind::Writer, EndpointKind::Reader] {
            for q in [Qos::default_profile(), Qos::services_default(), custom] {
                let dds = q.to_dds(kind).expect("valid profile");
                let policies = to_rustdds(&dds);
                assert_eq!(from_rustdds(&policies, kind), dds, "{kind:?} {q:?}");
                let remote = from_rustdds(&as_discovered(&policies), kind);
                assert_eq!(
                    remote,
                    DdsQos {
                        history: None,
                        ..dds
                    }
                );
            }
        }
        let p = to_rustdds(
            &Qos::default_profile()
                .to_dds(EndpointKind::Writer)
                .expect("ok"),
        );
        assert_eq!(p.history(), Some(History::KeepLast { depth: 10 }));
        assert_eq!(p.deadline(), None);
        assert_eq!(p.lifespan(), None);
    }

    #[test]
    fn absent_policies_take_dds_defaults_per_kind() {
        let empty = QosPolicies::qos_none();
        horus_ros_rmw_contract::qos::assert_dds_defaults_per_kind(
            &from_rustdds(&empty, EndpointKind::Writer),
            &from_rustdds(&empty, EndpointKind::Reader),
        );
    }

    #[test]
    fn non_ros_policies_and_negative_durations() {
        let p = QosPolicyBuilder::new()
            .durability(Durability::Persistent)
            .liveliness(Liveliness::ManualByParticipant {
                lease_duration: rustdds::Duration::from_secs(2),
            })
            .deadline(Deadline(rustdds::Duration::from_frac_seconds(-1.0)))
            .build();
        let q = Qos::from_dds(&from_rustdds(&p, EndpointKind::Reader));
        assert_eq!(q.durability, DurabilityPolicy::Unknown);
        assert_eq!(q.liveliness, LivelinessPolicy::Unknown);
        assert_eq!(q.liveliness_lease_duration.to_rmw_time(), (2, 0));
        assert!(q.deadline.is_infinite());
    }

    #[test]
    fn durations_round_trip_exactly() {
        for nanos in [
            1,
            2,
            999,
            1_000_000,
            100_000_000,
            123_456_789,
            999_999_999,
            1_000_000_001,
            86_400_000_000_007,
        ] {
            let d = Some(Duration::from_nanos(nanos));
            assert_eq!(
                from_rustdds_duration(to_rustdds_duration(d)),
                d,
                "{nanos} ns"
            );
        }
        let max = Some(MAX_DDS_DURATION);
        assert_eq!(from_rustdds_duration(to_rustdds_duration(max)), max);
        assert_eq!(to_rustdds_duration(None), rustdds::Duration::INFINITE);
        assert_eq!(from_rustdds_duration(rustdds::Duration::INFINITE), None);
    }
}
