//! [`DdsQos`]: an endpoint's DDS QoS in no DDS implementation's types, and the mapping between it
//! and [`Qos`]. Each backend maps [`DdsQos`] to its own types (rustdds: `dds/qos.rs`; Cyclone DDS:
//! `cyclone/qos.rs`).
//!
//! # ROS profile → DDS
//! As rmw_cyclonedds_cpp `create_readwrite_qos` (`src/rmw_node.cpp`, jazzy), which gives every
//! SYSTEM_DEFAULT a fixed value instead of leaving it to the DDS implementation:
//! - history: KEEP_LAST / SYSTEM_DEFAULT → `KeepLast(depth)`, depth 0
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
//! discovery listeners do. SEDP does not carry history, so a discovered endpoint's [`DdsQos`]
//! has none and gives history UNKNOWN, depth 0, as rmw_fastrtps reports it; a local endpoint's
//! carries history and gives it back. (A policy absent from what discovery carried takes its DDS
//! default, DDS 1.4 §2.2.3, when a backend reads it into a [`DdsQos`]: reliability RELIABLE for
//! a writer and BEST_EFFORT for a reader, durability VOLATILE, deadline / lifespan / lease
//! infinite, liveliness AUTOMATIC; negative durations become infinite, rmw
//! `rmw_time_from_nsec`.) DDS TRANSIENT and PERSISTENT durability and MANUAL_BY_PARTICIPANT
//! liveliness become UNKNOWN.

use std::time::Duration;

use super::{
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, Qos, QosDuration, QosError,
    ReliabilityPolicy,
};

/// `max_blocking_time` given to RELIABLE DDS endpoints: the DDS specification's default for
/// writers (also Fast DDS's). rmw_cyclonedds uses infinity; it only matters when a KEEP_ALL
/// writer's history is full.
pub const RELIABLE_MAX_BLOCKING_TIME: Duration = Duration::from_millis(100);

/// The longest finite DDS duration: `INT_MAX` s + 999999999 ns (rmw_dds_common
/// `clamp_rmw_time_to_dds_time`).
pub const MAX_DDS_DURATION: Duration = Duration::new(i32::MAX as u64, 999_999_999);

/// Which kind of DDS endpoint a QoS belongs to (DDS defaults and BEST_AVAILABLE rules differ).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum EndpointKind {
    /// A DataWriter: a publisher, a service's reply writer or a client's request writer.
    Writer,
    /// A DataReader: a subscription, a service's request reader or a client's reply reader.
    Reader,
}

/// DDS RELIABILITY.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DdsReliability {
    /// Samples may be lost.
    BestEffort,
    /// Samples are repaired until acknowledged; a write blocks at most `max_blocking_time` on a
    /// full history.
    Reliable {
        /// How long a write may block.
        max_blocking_time: Duration,
    },
}

/// DDS DURABILITY.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DdsDurability {
    /// Late joiners get nothing from before they matched.
    Volatile,
    /// The writer keeps its history for late joiners.
    TransientLocal,
    /// DDS TRANSIENT (no ROS equivalent).
    Transient,
    /// DDS PERSISTENT (no ROS equivalent).
    Persistent,
}

/// DDS HISTORY.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DdsHistory {
    /// Keep the last `n` samples (at most `i32::MAX`, as DDS counts them).
    KeepLast(u32),
    /// Keep every sample (bounded by resource limits).
    KeepAll,
}

/// DDS LIVELINESS kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DdsLiveliness {
    /// Asserted by the DDS implementation.
    Automatic,
    /// Asserted by the participant (no ROS equivalent).
    ManualByParticipant,
    /// Asserted by each write on the topic.
    ManualByTopic,
}

/// An endpoint's DDS QoS, as a backend sets it on an entity or reads it from discovery.
/// Durations are `None` when infinite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DdsQos {
    /// RELIABILITY.
    pub reliability: DdsReliability,
    /// DURABILITY.
    pub durability: DdsDurability,
    /// HISTORY; `None` when discovery did not carry it (SEDP never does).
    pub history: Option<DdsHistory>,
    /// DEADLINE period.
    pub deadline: Option<Duration>,
    /// LIFESPAN duration.
    pub lifespan: Option<Duration>,
    /// LIVELINESS kind.
    pub liveliness: DdsLiveliness,
    /// LIVELINESS lease duration.
    pub liveliness_lease: Option<Duration>,
}

impl DdsQos {
    /// The DDS defaults (DDS 1.4 §2.2.3) for an endpoint of `kind` whose discovery data carried
    /// no policy: RELIABLE for a writer and BEST_EFFORT for a reader, VOLATILE, AUTOMATIC,
    /// infinite durations, no history.
    pub fn dds_defaults(kind: EndpointKind) -> Self {
        Self {
            reliability: match kind {
                EndpointKind::Writer => DdsReliability::Reliable {
                    max_blocking_time: RELIABLE_MAX_BLOCKING_TIME,
                },
                EndpointKind::Reader => DdsReliability::BestEffort,
            },
            durability: DdsDurability::Volatile,
            history: None,
            deadline: None,
            lifespan: None,
            liveliness: DdsLiveliness::Automatic,
            liveliness_lease: None,
        }
    }
}

/// A specified rmw duration as a DDS duration (`None`: infinite; unspecified is infinite too),
/// clamped to [`MAX_DDS_DURATION`].
fn dds_duration(d: QosDuration) -> Option<Duration> {
    if d.is_default() || d.is_infinite() || d.is_best_available() {
        return None;
    }
    let nanos = Duration::from_nanos(u64::try_from(d.total_nanos()).unwrap_or(0));
    Some(nanos.min(MAX_DDS_DURATION))
}

/// A DDS duration as an rmw duration (rmw_cyclonedds `dds_duration_to_rmw`).
fn qos_duration(d: Option<Duration>) -> QosDuration {
    match d {
        None => QosDuration::Infinite,
        Some(d) => QosDuration::from_nanos(i64::try_from(d.as_nanos()).unwrap_or(i64::MAX)),
    }
}

impl Qos {
    /// The DDS QoS of an endpoint of `kind` with this profile (see the module documentation for
    /// the mapping).
    pub fn to_dds(&self, kind: EndpointKind) -> Result<DdsQos, QosError> {
        let qos = match kind {
            EndpointKind::Writer => self.resolve_best_available_for_publisher(&[]),
            EndpointKind::Reader => self.resolve_best_available_for_subscription(&[]),
        };
        // In the order rmw_cyclonedds' `create_readwrite_qos` sets them: history first.
        let history = Some(qos.dds_history()?);
        Ok(DdsQos {
            history,
            reliability: qos.dds_reliability()?,
            durability: qos.dds_durability()?,
            deadline: dds_duration(qos.deadline),
            lifespan: dds_duration(qos.lifespan),
            liveliness: qos.dds_liveliness()?,
            liveliness_lease: dds_duration(qos.liveliness_lease_duration),
        })
    }

    /// The ROS view of an endpoint's DDS QoS: a discovered endpoint's (history then UNKNOWN) or
    /// a local one's (see the module documentation).
    pub fn from_dds(dds: &DdsQos) -> Qos {
        let mut qos = Qos::unknown();
        (qos.history, qos.depth) = match dds.history {
            None => (HistoryPolicy::Unknown, 0),
            Some(DdsHistory::KeepLast(depth)) => {
                (HistoryPolicy::KeepLast, usize::try_from(depth).unwrap_or(0))
            }
            // rmw_cyclonedds reports KEEP_ALL with depth 0.
            Some(DdsHistory::KeepAll) => (HistoryPolicy::KeepAll, 0),
        };
        qos.reliability = match dds.reliability {
            DdsReliability::Reliable { .. } => ReliabilityPolicy::Reliable,
            DdsReliability::BestEffort => ReliabilityPolicy::BestEffort,
        };
        qos.durability = match dds.durability {
            DdsDurability::Volatile => DurabilityPolicy::Volatile,
            DdsDurability::TransientLocal => DurabilityPolicy::TransientLocal,
            DdsDurability::Transient | DdsDurability::Persistent => DurabilityPolicy::Unknown,
        };
        qos.deadline = qos_duration(dds.deadline);
        qos.lifespan = qos_duration(dds.lifespan);
        qos.liveliness = match dds.liveliness {
            DdsLiveliness::Automatic => LivelinessPolicy::Automatic,
            DdsLiveliness::ManualByTopic => LivelinessPolicy::ManualByTopic,
            DdsLiveliness::ManualByParticipant => LivelinessPolicy::Unknown,
        };
        qos.liveliness_lease_duration = qos_duration(dds.liveliness_lease);
        qos
    }

    fn dds_history(&self) -> Result<DdsHistory, QosError> {
        match self.history {
            HistoryPolicy::KeepLast | HistoryPolicy::SystemDefault => {
                let depth = i32::try_from(self.depth.max(1))
                    .map_err(|_| QosError::DepthTooLarge(self.depth))?;
                Ok(DdsHistory::KeepLast(depth.unsigned_abs()))
            }
            HistoryPolicy::KeepAll => Ok(DdsHistory::KeepAll),
            HistoryPolicy::Unknown => Err(QosError::UnknownPolicy { policy: "history" }),
        }
    }

    fn dds_reliability(&self) -> Result<DdsReliability, QosError> {
        match self.reliability {
            ReliabilityPolicy::Reliable
            | ReliabilityPolicy::SystemDefault
            // Unreachable after resolution; RELIABLE is what both resolutions pick alone.
            | ReliabilityPolicy::BestAvailable => Ok(DdsReliability::Reliable {
                max_blocking_time: RELIABLE_MAX_BLOCKING_TIME,
            }),
            ReliabilityPolicy::BestEffort => Ok(DdsReliability::BestEffort),
            ReliabilityPolicy::Unknown => Err(QosError::UnknownPolicy {
                policy: "reliability",
            }),
        }
    }

    fn dds_durability(&self) -> Result<DdsDurability, QosError> {
        match self.durability {
            DurabilityPolicy::Volatile | DurabilityPolicy::SystemDefault => {
                Ok(DdsDurability::Volatile)
            }
            // BEST_AVAILABLE is unreachable after resolution.
            DurabilityPolicy::TransientLocal | DurabilityPolicy::BestAvailable => {
                Ok(DdsDurability::TransientLocal)
            }
            DurabilityPolicy::Unknown => Err(QosError::UnknownPolicy {
                policy: "durability",
            }),
        }
    }

    fn dds_liveliness(&self) -> Result<DdsLiveliness, QosError> {
        match self.liveliness {
            // BEST_AVAILABLE is unreachable after resolution.
            LivelinessPolicy::Automatic
            | LivelinessPolicy::SystemDefault
            | LivelinessPolicy::BestAvailable => Ok(DdsLiveliness::Automatic),
            LivelinessPolicy::ManualByTopic => Ok(DdsLiveliness::ManualByTopic),
            LivelinessPolicy::Unknown => Err(QosError::UnknownPolicy {
                policy: "liveliness",
            }),
        }
    }

    /// The profile an endpoint created with `self` really has, as rmw reports its own endpoints
    /// (`dds_qos_to_rmw_qos` of the created entity): system defaults and default durations
    /// resolved to what DDS applies (e.g. AUTOMATIC liveliness, infinite durations).
    pub fn effective(&self, kind: EndpointKind) -> Qos {
        match self.to_dds(kind) {
            Ok(dds) => Qos {
                avoid_ros_namespace_conventions: self.avoid_ros_namespace_conventions,
                ..Qos::from_dds(&dds)
            },
            Err(_) => *self,
        }
    }
}

/// A profile with every policy away from its default (for the mapping tests of the backends).
#[doc(hidden)]
pub fn unusual_profile() -> Qos {
    Qos::sensor_data()
        .keep_all()
        .transient_local()
        .with_deadline(Duration::from_millis(100))
        .with_lifespan(Duration::new(3, 123_456_789))
        .with_liveliness(LivelinessPolicy::ManualByTopic)
        .with_liveliness_lease_duration(Duration::from_nanos(1))
}

/// Checks what a writer's and a reader's profiles read from DDS policies that are all absent
/// give (for the mapping tests of the backends): the DDS defaults per kind.
#[doc(hidden)]
pub fn assert_dds_defaults_per_kind(writer: &DdsQos, reader: &DdsQos) {
    let w = Qos::from_dds(writer);
    let r = Qos::from_dds(reader);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn to_dds(q: &Qos, kind: EndpointKind) -> DdsQos {
        match q.to_dds(kind) {
            Ok(p) => p,
            Err(e) => panic!("{q:?} did not convert: {e}"),
        }
    }

    #[test]
    fn default_profile_to_dds() {
        let p = to_dds(&Qos::default_profile(), EndpointKind::Writer);
        assert_eq!(p.history, Some(DdsHistory::KeepLast(10)));
        assert_eq!(
            p.reliability,
            DdsReliability::Reliable {
                max_blocking_time: RELIABLE_MAX_BLOCKING_TIME
            }
        );
        assert_eq!(p.durability, DdsDurability::Volatile);
        assert_eq!(p.liveliness, DdsLiveliness::Automatic);
        assert_eq!(p.liveliness_lease, None);
        assert_eq!(p.deadline, None);
        assert_eq!(p.lifespan, None);
    }

    #[test]
    fn system_default_maps_like_rmw_cyclonedds() {
        for kind in [EndpointKind::Writer, EndpointKind::Reader] {
            let p = to_dds(&Qos::system_default(), kind);
            assert_eq!(p.history, Some(DdsHistory::KeepLast(1)));
            assert!(matches!(p.reliability, DdsReliability::Reliable { .. }));
            assert_eq!(p.durability, DdsDurability::Volatile);
            assert_eq!(p.liveliness, DdsLiveliness::Automatic);
        }
    }

    #[test]
    fn best_available_resolved_as_with_no_endpoints() {
        let w = Qos::from_dds(&to_dds(&Qos::best_available(), EndpointKind::Writer));
        assert_eq!(
            (w.reliability, w.durability, w.liveliness),
            (
                ReliabilityPolicy::Reliable,
                DurabilityPolicy::TransientLocal,
                LivelinessPolicy::Automatic
            )
        );
        let r = Qos::from_dds(&to_dds(&Qos::best_available(), EndpointKind::Reader));
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
        let custom = unusual_profile();
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
                let back = Qos::from_dds(&to_dds(&q, kind));
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
        let discovered = DdsQos {
            history: None,
            ..to_dds(&Qos::default_profile(), EndpointKind::Writer)
        };
        let remote = Qos::from_dds(&discovered);
        assert_eq!((remote.history, remote.depth), (HistoryPolicy::Unknown, 0));
        assert_eq!(remote.reliability, ReliabilityPolicy::Reliable);
        assert_eq!(remote.durability, DurabilityPolicy::Volatile);
    }

    #[test]
    fn dds_defaults_per_kind() {
        assert_dds_defaults_per_kind(
            &DdsQos::dds_defaults(EndpointKind::Writer),
            &DdsQos::dds_defaults(EndpointKind::Reader),
        );
    }

    #[test]
    fn non_ros_dds_policies_become_unknown() {
        let q = Qos::from_dds(&DdsQos {
            durability: DdsDurability::Persistent,
            liveliness: DdsLiveliness::ManualByParticipant,
            liveliness_lease: Some(Duration::from_secs(2)),
            ..DdsQos::dds_defaults(EndpointKind::Reader)
        });
        assert_eq!(q.durability, DurabilityPolicy::Unknown);
        assert_eq!(q.liveliness, LivelinessPolicy::Unknown);
        assert_eq!(q.liveliness_lease_duration.to_rmw_time(), (2, 0));
    }

    #[test]
    fn durations_are_clamped_to_dds_range() {
        assert_eq!(dds_duration(QosDuration::Infinite), None);
        assert_eq!(dds_duration(QosDuration::Default), None);
        assert_eq!(
            dds_duration(QosDuration::from_nanos(123_456_789)),
            Some(Duration::from_nanos(123_456_789))
        );
        assert_eq!(
            qos_duration(dds_duration(QosDuration::from_rmw_time(3_000_000_000, 0))),
            QosDuration::from_rmw_time(2_147_483_647, 999_999_999)
        );
    }

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
