//! Mapping between [`Qos`] and rustdds [`QosPolicies`].
//!
//! # ROS profile → DDS
//! As rmw_cyclonedds_cpp `create_readwrite_qos` (`src/rmw_node.cpp`, jazzy), which gives every
//! SYSTEM_DEFAULT a fixed value instead of leaving it to the DDS implementation:
//! - history: KEEP_LAST / SYSTEM_DEFAULT → `KeepLast { depth }`, depth 0
//!   (`RMW_QOS_POLICY_DEPTH_SYSTEM_DEFAULT`) → 1; KEEP_ALL → `KeepAll`;
//! - reliability: RELIABLE / SYSTEM_DEFAULT → `Reliable` (max blocking time
//!   [`RELIABLE_MAX_BLOCKING_TIME`]), BEST_EFFORT → `BestEffort`;
//! - durability: VOLATILE / SYSTEM_DEFAULT → `Volatile`, TRANSIENT_LOCAL → `TransientLocal`;
//! - liveliness: AUTOMATIC / SYSTEM_DEFAULT → `Automatic`, MANUAL_BY_TOPIC → `ManualByTopic`,
//!   always set, lease unspecified → infinite;
//! - deadline and lifespan: set only when specified (else the DDS default, infinite);
//! - infinite durations → DDS infinite; finite ones beyond DDS's `i32` seconds are clamped to
//!   `INT_MAX` s + 999999999 ns (rmw_dds_common `clamp_rmw_time_to_dds_time`);
//! - UNKNOWN policies are refused ([`QosError::UnknownPolicy`]), as both RMWs do.
//!
//! rmw_fastrtps instead leaves SYSTEM_DEFAULT policies at Fast DDS's entity defaults (whose
//! reader reliability is BEST_EFFORT); we do not copy that.
//!
//! BEST_AVAILABLE: ROS resolves it once, when the endpoint is created, from the endpoints then
//! discovered (see `Qos::resolve_best_available_for_*`). Callers that know them should resolve
//! first. Whatever is still BEST_AVAILABLE here is resolved as ROS would with no endpoint
//! discovered yet: a writer gets RELIABLE, TRANSIENT_LOCAL, AUTOMATIC; a reader RELIABLE,
//! TRANSIENT_LOCAL, MANUAL_BY_TOPIC; deadline and lease default. Service endpoints should call
//! `Qos::resolve_best_available_for_services` first, as ROS does.
//!
//! # DDS → ROS profile
//! As rmw_fastrtps_shared_cpp `rtps_qos_to_rmw_qos` / `dds_qos_to_rmw_qos` (`qos.hpp`) and
//! rmw_cyclonedds `dds_qos_to_rmw_qos`, starting from `rmw_qos_profile_unknown` like their
//! discovery listeners do. SEDP does not carry history, so a discovered endpoint (rustdds
//! `DiscoveredWriterData::qos()` has no history) gives history UNKNOWN, depth 0, as rmw_fastrtps
//! reports it; a local endpoint's policies carry history and give it back. A policy absent from
//! the policies takes its DDS default (DDS 1.4 §2.2.3): reliability RELIABLE for a writer and
//! BEST_EFFORT for a reader, durability VOLATILE, deadline / lifespan / lease infinite, liveliness
//! AUTOMATIC. DDS TRANSIENT and PERSISTENT durability and MANUAL_BY_PARTICIPANT liveliness become
//! UNKNOWN; negative durations become infinite (rmw `rmw_time_from_nsec`).

use std::time::Duration;

use rustdds::{
    policy::{Durability, History, Liveliness, Reliability},
    QosPolicies, QosPolicyBuilder,
};

use super::{
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, Qos, QosDuration, QosError,
    ReliabilityPolicy,
};

/// `max_blocking_time` given to RELIABLE DDS endpoints: the DDS specification's default for
/// writers (also Fast DDS's). rmw_cyclonedds uses infinity; it only matters when a KEEP_ALL
/// writer's history is full.
pub const RELIABLE_MAX_BLOCKING_TIME: Duration = Duration::from_millis(100);

const NANOS_PER_SEC: i64 = 1_000_000_000;

/// Which kind of DDS endpoint a QoS belongs to (DDS defaults and BEST_AVAILABLE rules differ).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum EndpointKind {
    /// A DataWriter: a publisher, a service's reply writer or a client's request writer.
    Writer,
    /// A DataReader: a subscription, a service's request reader or a client's reply reader.
    Reader,
}

/// A specified rmw duration as a DDS duration; `None` for unspecified.
fn to_dds_duration(d: QosDuration) -> Option<rustdds::Duration> {
    if d.is_default() {
        return None;
    }
    if d.is_infinite() {
        return Some(rustdds::Duration::INFINITE);
    }
    // rmw_dds_common clamp_rmw_time_to_dds_time: at most INT_MAX s + (10^9 - 1) ns.
    let max = i64::from(i32::MAX) * NANOS_PER_SEC + (NANOS_PER_SEC - 1);
    Some(rustdds::Duration::from_nanos(d.total_nanos().min(max)))
}

/// A DDS duration as an rmw duration (rmw_cyclonedds `dds_duration_to_rmw`).
fn from_dds_duration(d: rustdds::Duration) -> QosDuration {
    if d == rustdds::Duration::INFINITE {
        return QosDuration::Infinite;
    }
    // RTPS durations count 2^-32 s; rustdds's to_nanoseconds rounds down, so a value made by
    // from_nanos(n) can come back as n - 1. Take the n that maps back to exactly `d`.
    let nanos = d.to_nanoseconds();
    let nanos = match nanos.checked_add(1) {
        Some(up) if rustdds::Duration::from_nanos(up) == d => up,
        _ => nanos,
    };
    QosDuration::from_nanos(nanos)
}

impl Qos {
    /// The rustdds QoS policies for a DDS endpoint of `kind` with this profile (see the module
    /// documentation for the mapping).
    pub fn to_dds(&self, kind: EndpointKind) -> Result<QosPolicies, QosError> {
        let qos = match kind {
            EndpointKind::Writer => self.resolve_best_available_for_publisher(&[]),
            EndpointKind::Reader => self.resolve_best_available_for_subscription(&[]),
        };
        let mut builder = QosPolicyBuilder::new()
            .history(qos.dds_history()?)
            .reliability(qos.dds_reliability()?)
            .durability(qos.dds_durability()?)
            .liveliness(qos.dds_liveliness()?);
        if let Some(d) = to_dds_duration(qos.deadline) {
            builder = builder.deadline(rustdds::policy::Deadline(d));
        }
        if let Some(duration) = to_dds_duration(qos.lifespan) {
            builder = builder.lifespan(rustdds::policy::Lifespan { duration });
        }
        Ok(builder.build())
    }

    /// The ROS view of a DDS endpoint's QoS policies: a discovered endpoint's (history then
    /// UNKNOWN) or a local one's (see the module documentation).
    pub fn from_dds(policies: &QosPolicies, kind: EndpointKind) -> Qos {
        let mut qos = Qos::unknown();
        (qos.history, qos.depth) = match policies.history() {
            None => (HistoryPolicy::Unknown, 0),
            Some(History::KeepLast { depth }) => {
                (HistoryPolicy::KeepLast, usize::try_from(depth).unwrap_or(0))
            }
            // rmw_cyclonedds reports KEEP_ALL with depth 0.
            Some(History::KeepAll) => (HistoryPolicy::KeepAll, 0),
        };
        qos.reliability = match (policies.reliability(), kind) {
            (Some(Reliability::Reliable { .. }), _) | (None, EndpointKind::Writer) => {
                ReliabilityPolicy::Reliable
            }
            (Some(Reliability::BestEffort), _) | (None, EndpointKind::Reader) => {
                ReliabilityPolicy::BestEffort
            }
        };
        qos.durability = match policies.durability() {
            None | Some(Durability::Volatile) => DurabilityPolicy::Volatile,
            Some(Durability::TransientLocal) => DurabilityPolicy::TransientLocal,
            Some(Durability::Transient | Durability::Persistent) => DurabilityPolicy::Unknown,
        };
        qos.deadline = policies
            .deadline()
            .map_or(QosDuration::Infinite, |d| from_dds_duration(d.0));
        qos.lifespan = policies
            .lifespan()
            .map_or(QosDuration::Infinite, |l| from_dds_duration(l.duration));
        (qos.liveliness, qos.liveliness_lease_duration) = match policies.liveliness() {
            None => (LivelinessPolicy::Automatic, QosDuration::Infinite),
            Some(l) => {
                let kind = match l {
                    Liveliness::Automatic { .. } => LivelinessPolicy::Automatic,
                    Liveliness::ManualByTopic { .. } => LivelinessPolicy::ManualByTopic,
                    Liveliness::ManualByParticipant { .. } => LivelinessPolicy::Unknown,
                };
                (kind, from_dds_duration(l.duration()))
            }
        };
        qos
    }

    fn dds_history(&self) -> Result<History, QosError> {
        match self.history {
            HistoryPolicy::KeepLast | HistoryPolicy::SystemDefault => {
                let depth = i32::try_from(self.depth.max(1))
                    .map_err(|_| QosError::DepthTooLarge(self.depth))?;
                Ok(History::KeepLast { depth })
            }
            HistoryPolicy::KeepAll => Ok(History::KeepAll),
            HistoryPolicy::Unknown => Err(QosError::UnknownPolicy { policy: "history" }),
        }
    }

    fn dds_reliability(&self) -> Result<Reliability, QosError> {
        match self.reliability {
            ReliabilityPolicy::Reliable
            | ReliabilityPolicy::SystemDefault
            // Unreachable after resolution; RELIABLE is what both resolutions pick alone.
            | ReliabilityPolicy::BestAvailable => Ok(Reliability::Reliable {
                max_blocking_time: RELIABLE_MAX_BLOCKING_TIME.into(),
            }),
            ReliabilityPolicy::BestEffort => Ok(Reliability::BestEffort),
            ReliabilityPolicy::Unknown => Err(QosError::UnknownPolicy {
                policy: "reliability",
            }),
        }
    }

    fn dds_durability(&self) -> Result<Durability, QosError> {
        match self.durability {
            DurabilityPolicy::Volatile | DurabilityPolicy::SystemDefault => {
                Ok(Durability::Volatile)
            }
            // BEST_AVAILABLE is unreachable after resolution.
            DurabilityPolicy::TransientLocal | DurabilityPolicy::BestAvailable => {
                Ok(Durability::TransientLocal)
            }
            DurabilityPolicy::Unknown => Err(QosError::UnknownPolicy {
                policy: "durability",
            }),
        }
    }

    fn dds_liveliness(&self) -> Result<Liveliness, QosError> {
        let lease_duration = if self.liveliness_lease_duration.is_best_available() {
            // Unreachable after resolution.
            rustdds::Duration::INFINITE
        } else {
            to_dds_duration(self.liveliness_lease_duration).unwrap_or(rustdds::Duration::INFINITE)
        };
        match self.liveliness {
            // BEST_AVAILABLE is unreachable after resolution.
            LivelinessPolicy::Automatic
            | LivelinessPolicy::SystemDefault
            | LivelinessPolicy::BestAvailable => Ok(Liveliness::Automatic { lease_duration }),
            LivelinessPolicy::ManualByTopic => Ok(Liveliness::ManualByTopic { lease_duration }),
            LivelinessPolicy::Unknown => Err(QosError::UnknownPolicy {
                policy: "liveliness",
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    fn to_dds(q: &Qos, kind: EndpointKind) -> QosPolicies {
        match q.to_dds(kind) {
            Ok(p) => p,
            Err(e) => panic!("{q:?} did not convert: {e}"),
        }
    }

    #[test]
    fn default_profile_to_dds() {
        let p = to_dds(&Qos::default_profile(), EndpointKind::Writer);
        assert_eq!(p.history(), Some(History::KeepLast { depth: 10 }));
        assert_eq!(
            p.reliability(),
            Some(Reliability::Reliable {
                max_blocking_time: RELIABLE_MAX_BLOCKING_TIME.into()
            })
        );
        assert_eq!(p.durability(), Some(Durability::Volatile));
        assert_eq!(
            p.liveliness(),
            Some(Liveliness::Automatic {
                lease_duration: rustdds::Duration::INFINITE
            })
        );
        assert_eq!(p.deadline(), None);
        assert_eq!(p.lifespan(), None);
    }

    #[test]
    fn system_default_maps_like_rmw_cyclonedds() {
        for kind in [EndpointKind::Writer, EndpointKind::Reader] {
            let p = to_dds(&Qos::system_default(), kind);
            assert_eq!(p.history(), Some(History::KeepLast { depth: 1 }));
            assert!(p.is_reliable());
            assert!(p.is_volatile());
            assert!(matches!(p.liveliness(), Some(Liveliness::Automatic { .. })));
        }
    }

    #[test]
    fn best_available_resolved_as_with_no_endpoints() {
        let w = Qos::from_dds(
            &to_dds(&Qos::best_available(), EndpointKind::Writer),
            EndpointKind::Writer,
        );
        assert_eq!(
            (w.reliability, w.durability, w.liveliness),
            (
                ReliabilityPolicy::Reliable,
                DurabilityPolicy::TransientLocal,
                LivelinessPolicy::Automatic
            )
        );
        let r = Qos::from_dds(
            &to_dds(&Qos::best_available(), EndpointKind::Reader),
            EndpointKind::Reader,
        );
        assert_eq!(r.liveliness, LivelinessPolicy::ManualByTopic);
        assert_eq!(r.deadline, QosDuration::Infinite);
    }

    #[test]
    fn unknown_and_oversized_are_refused() {
        assert_eq!(
            Qos::unknown().to_dds(EndpointKind::Writer),
            Err(QosError::UnknownPolicy { policy: "history" })
        );
        assert_eq!(
            Qos::default_profile()
                .with_liveliness(LivelinessPolicy::Unknown)
                .to_dds(EndpointKind::Reader),
            Err(QosError::UnknownPolicy {
                policy: "liveliness"
            })
        );
        let big = usize::try_from(i32::MAX).unwrap_or(usize::MAX) + 1;
        assert_eq!(
            Qos::default_profile()
                .keep_last(big)
                .to_dds(EndpointKind::Writer),
            Err(QosError::DepthTooLarge(big))
        );
    }

    #[test]
    fn round_trip_local_endpoint() {
        // Unspecified durations come back as DDS's infinite, as ROS reports them.
        let custom = Qos::sensor_data()
            .keep_all()
            .transient_local()
            .with_deadline(Duration::from_millis(100))
            .with_lifespan(Duration::new(3, 123_456_789))
            .with_liveliness(LivelinessPolicy::ManualByTopic)
            .with_liveliness_lease_duration(Duration::from_nanos(1));
        for kind in [EndpointKind::Writer, EndpointKind::Reader] {
            for q in [
                Qos::default_profile(),
                Qos::services_default(),
                Qos::parameters(),
                Qos::parameter_events(),
                Qos::sensor_data(),
                Qos::rosout_default(),
                Qos::action_status_default(),
                custom,
            ] {
                let back = Qos::from_dds(&to_dds(&q, kind), kind);
                let expected = Qos {
                    depth: if q.history == HistoryPolicy::KeepAll {
                        0
                    } else {
                        q.depth
                    },
                    deadline: if q.deadline.is_default() {
                        QosDuration::Infinite
                    } else {
                        q.deadline
                    },
                    lifespan: if q.lifespan.is_default() {
                        QosDuration::Infinite
                    } else {
                        q.lifespan
                    },
                    liveliness: if q.liveliness == LivelinessPolicy::SystemDefault {
                        LivelinessPolicy::Automatic
                    } else {
                        q.liveliness
                    },
                    liveliness_lease_duration: if q.liveliness_lease_duration.is_default() {
                        QosDuration::Infinite
                    } else {
                        q.liveliness_lease_duration
                    },
                    ..q
                };
                assert_eq!(back, expected, "{kind:?} {q:?}");
            }
        }
    }

    #[test]
    fn discovered_endpoint_has_unknown_history() {
        let local = to_dds(&Qos::default_profile(), EndpointKind::Writer);
        let remote = Qos::from_dds(&as_discovered(&local), EndpointKind::Writer);
        assert_eq!((remote.history, remote.depth), (HistoryPolicy::Unknown, 0));
        assert_eq!(remote.reliability, ReliabilityPolicy::Reliable);
        assert_eq!(remote.durability, DurabilityPolicy::Volatile);
    }

    #[test]
    fn absent_policies_take_dds_defaults_per_kind() {
        let empty = QosPolicies::qos_none();
        let w = Qos::from_dds(&empty, EndpointKind::Writer);
        let r = Qos::from_dds(&empty, EndpointKind::Reader);
        assert_eq!(w.reliability, ReliabilityPolicy::Reliable);
        assert_eq!(r.reliability, ReliabilityPolicy::BestEffort);
        for q in [w, r] {
            assert_eq!(q.history, HistoryPolicy::Unknown);
            assert_eq!(q.durability, DurabilityPolicy::Volatile);
            assert_eq!(q.liveliness, LivelinessPolicy::Automatic);
            assert!(q.deadline.is_infinite() && q.lifespan.is_infinite());
            assert!(q.liveliness_lease_duration.is_infinite());
            assert!(!q.avoid_ros_namespace_conventions);
        }
    }

    #[test]
    fn non_ros_dds_policies_become_unknown() {
        let p = QosPolicyBuilder::new()
            .durability(Durability::Persistent)
            .liveliness(Liveliness::ManualByParticipant {
                lease_duration: rustdds::Duration::from_secs(2),
            })
            .deadline(rustdds::policy::Deadline(
                rustdds::Duration::from_frac_seconds(-1.0),
            ))
            .build();
        let q = Qos::from_dds(&p, EndpointKind::Reader);
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
            i64::from(i32::MAX) * NANOS_PER_SEC + 999_999_999,
        ] {
            let d = QosDuration::from_nanos(nanos);
            let dds = to_dds_duration(d).map(from_dds_duration);
            assert_eq!(dds, Some(d), "{nanos} ns");
        }
        assert_eq!(
            to_dds_duration(QosDuration::Infinite),
            Some(rustdds::Duration::INFINITE)
        );
        assert_eq!(to_dds_duration(QosDuration::Default), None);
        // Beyond DDS's range: clamped to INT_MAX s + 999999999 ns.
        let clamped =
            to_dds_duration(QosDuration::from_rmw_time(3_000_000_000, 0)).map(from_dds_duration);
        assert_eq!(
            clamped,
            Some(QosDuration::from_rmw_time(2_147_483_647, 999_999_999))
        );
    }
}

impl Qos {
    /// The profile an endpoint created with `self` really has, as rmw reports its own endpoints
    /// (`dds_qos_to_rmw_qos` of the created entity): system defaults and default durations
    /// resolved to what DDS applies (e.g. AUTOMATIC liveliness, infinite durations).
    pub fn effective(&self, kind: EndpointKind) -> Qos {
        match self.to_dds(kind) {
            Ok(policies) => Qos {
                avoid_ros_namespace_conventions: self.avoid_ros_namespace_conventions,
                ..Qos::from_dds(&policies, kind)
            },
            Err(_) => *self,
        }
    }
}

#[cfg(test)]
mod effective_tests {
    use super::*;

    #[test]
    fn system_defaults_resolve_to_what_dds_applies() {
        let q = Qos::services_default().effective(EndpointKind::Writer);
        assert_eq!(q.reliability, ReliabilityPolicy::Reliable);
        assert_eq!(q.durability, DurabilityPolicy::Volatile);
        assert_eq!((q.history, q.depth), (HistoryPolicy::KeepLast, 10));
        assert_eq!(q.liveliness, LivelinessPolicy::Automatic);
        assert!(q.deadline.is_infinite() && q.lifespan.is_infinite());
        assert!(q.liveliness_lease_duration.is_infinite());
        let avoid = Qos::default_profile().with_avoid_ros_namespace_conventions(true);
        assert!(
            avoid
                .effective(EndpointKind::Reader)
                .avoid_ros_namespace_conventions
        );
    }
}
