//! Resolving BEST_AVAILABLE policies against the matched endpoints.
//!
//! Same rules as rmw_dds_common `qos_profile_get_best_available_for_subscription`,
//! `qos_profile_get_best_available_for_publisher` and
//! `qos_profile_update_best_available_for_services` (rmw_dds_common `src/qos.cpp`, jazzy), which
//! rmw_fastrtps and rmw_cyclonedds apply once, when an endpoint is created, to the QoS of the
//! endpoints then discovered on the topic. Like them, nothing is re-resolved later.

use super::{DurabilityPolicy, LivelinessPolicy, Qos, QosDuration, ReliabilityPolicy};

impl Qos {
    /// Resolves BEST_AVAILABLE policies of a subscription from the QoS of the publishers
    /// currently known on its topic: RELIABLE / TRANSIENT_LOCAL / MANUAL_BY_TOPIC only if every
    /// publisher has it (so also with no publishers at all); deadline and lease the largest
    /// non-default among the publishers, or default.
    #[must_use]
    pub fn resolve_best_available_for_subscription(&self, publishers: &[Qos]) -> Qos {
        let mut qos = *self;
        let all = |f: &dyn Fn(&Qos) -> bool| publishers.iter().all(f);
        if qos.reliability == ReliabilityPolicy::BestAvailable {
            qos.reliability = if all(&|p| p.reliability == ReliabilityPolicy::Reliable) {
                ReliabilityPolicy::Reliable
            } else {
                ReliabilityPolicy::BestEffort
            };
        }
        if qos.durability == DurabilityPolicy::BestAvailable {
            qos.durability = if all(&|p| p.durability == DurabilityPolicy::TransientLocal) {
                DurabilityPolicy::TransientLocal
            } else {
                DurabilityPolicy::Volatile
            };
        }
        if qos.liveliness == LivelinessPolicy::BestAvailable {
            qos.liveliness = if all(&|p| p.liveliness == LivelinessPolicy::ManualByTopic) {
                LivelinessPolicy::ManualByTopic
            } else {
                LivelinessPolicy::Automatic
            };
        }
        let largest = |get: fn(&Qos) -> QosDuration| {
            publishers
                .iter()
                .map(get)
                .filter(|d| !d.is_default())
                .max()
                .unwrap_or(QosDuration::Default)
        };
        if qos.deadline.is_best_available() {
            qos.deadline = largest(|p| p.deadline);
        }
        if qos.liveliness_lease_duration.is_best_available() {
            qos.liveliness_lease_duration = largest(|p| p.liveliness_lease_duration);
        }
        qos
    }

    /// Resolves BEST_AVAILABLE policies of a publisher from the QoS of the subscriptions
    /// currently known on its topic: always RELIABLE and TRANSIENT_LOCAL; MANUAL_BY_TOPIC if any
    /// subscription has it, else AUTOMATIC; deadline and lease the smallest non-default among the
    /// subscriptions, or default.
    #[must_use]
    pub fn resolve_best_available_for_publisher(&self, subscriptions: &[Qos]) -> Qos {
        let mut qos = *self;
        if qos.reliability == ReliabilityPolicy::BestAvailable {
            qos.reliability = ReliabilityPolicy::Reliable;
        }
        if qos.durability == DurabilityPolicy::BestAvailable {
            qos.durability = DurabilityPolicy::TransientLocal;
        }
        if qos.liveliness == LivelinessPolicy::BestAvailable {
            let any_manual = subscriptions
                .iter()
                .any(|s| s.liveliness == LivelinessPolicy::ManualByTopic);
            qos.liveliness = if any_manual {
                LivelinessPolicy::ManualByTopic
            } else {
                LivelinessPolicy::Automatic
            };
        }
        let smallest = |get: fn(&Qos) -> QosDuration| {
            subscriptions
                .iter()
                .map(get)
                .filter(|d| !d.is_default())
                .min()
                .unwrap_or(QosDuration::Default)
        };
        if qos.deadline.is_best_available() {
            qos.deadline = smallest(|s| s.deadline);
        }
        if qos.liveliness_lease_duration.is_best_available() {
            qos.liveliness_lease_duration = smallest(|s| s.liveliness_lease_duration);
        }
        qos
    }

    /// Replaces BEST_AVAILABLE policies by those of `services_default`, as ROS does for service
    /// servers and clients.
    #[must_use]
    pub fn resolve_best_available_for_services(&self) -> Qos {
        let services = Qos::services_default();
        let mut qos = *self;
        if qos.reliability == ReliabilityPolicy::BestAvailable {
            qos.reliability = services.reliability;
        }
        if qos.durability == DurabilityPolicy::BestAvailable {
            qos.durability = services.durability;
        }
        if qos.liveliness == LivelinessPolicy::BestAvailable {
            qos.liveliness = services.liveliness;
        }
        if qos.deadline.is_best_available() {
            qos.deadline = services.deadline;
        }
        if qos.liveliness_lease_duration.is_best_available() {
            qos.liveliness_lease_duration = services.liveliness_lease_duration;
        }
        qos
    }
}

#[cfg(test)]
mod tests {
    //! Cases from rmw_dds_common `test/test_qos.cpp` (jazzy),
    //! `test_qos_profile_get_best_available_for_{subscription,publisher}` and
    //! `test_qos_profile_update_best_available_for_services`.
    use super::*;

    fn secs(s: u64) -> QosDuration {
        QosDuration::from_rmw_time(s, 0)
    }

    fn keep_all(
        r: ReliabilityPolicy,
        d: DurabilityPolicy,
        deadline: QosDuration,
        l: LivelinessPolicy,
        lease: QosDuration,
    ) -> Qos {
        Qos::default_profile()
            .keep_all()
            .with_depth(1)
            .with_reliability(r)
            .with_durability(d)
            .with_deadline(deadline)
            .with_liveliness(l)
            .with_liveliness_lease_duration(lease)
    }

    #[test]
    fn subscription() {
        use DurabilityPolicy as D;
        use LivelinessPolicy as L;
        use ReliabilityPolicy as R;
        let ba = Qos::best_available();
        let none = ba.resolve_best_available_for_subscription(&[]);
        assert_eq!(
            (none.reliability, none.durability, none.liveliness),
            (R::Reliable, D::TransientLocal, L::ManualByTopic)
        );
        assert!(none.deadline.is_default() && none.liveliness_lease_duration.is_default());

        let one = keep_all(
            R::Reliable,
            D::TransientLocal,
            QosDuration::Default,
            L::ManualByTopic,
            QosDuration::Default,
        );
        let r = ba.resolve_best_available_for_subscription(&[one]);
        assert_eq!(
            (r.reliability, r.durability, r.liveliness),
            (one.reliability, one.durability, one.liveliness)
        );
        assert_eq!(
            (r.deadline, r.liveliness_lease_duration),
            (one.deadline, one.liveliness_lease_duration)
        );

        let pubs = [
            keep_all(
                R::Reliable,
                D::TransientLocal,
                QosDuration::Default,
                L::Automatic,
                secs(1),
            ),
            keep_all(
                R::BestEffort,
                D::TransientLocal,
                secs(3),
                L::ManualByTopic,
                QosDuration::Default,
            ),
            keep_all(R::Reliable, D::Volatile, secs(2), L::ManualByTopic, secs(2)),
        ];
        let r = ba.resolve_best_available_for_subscription(&pubs);
        assert_eq!(
            (r.reliability, r.durability, r.liveliness),
            (R::BestEffort, D::Volatile, L::Automatic)
        );
        assert_eq!(
            (r.deadline, r.liveliness_lease_duration),
            (secs(3), secs(2))
        );
    }

    #[test]
    fn publisher() {
        use DurabilityPolicy as D;
        use LivelinessPolicy as L;
        use ReliabilityPolicy as R;
        let ba = Qos::best_available();
        let none = ba.resolve_best_available_for_publisher(&[]);
        assert_eq!(
            (none.reliability, none.durability, none.liveliness),
            (R::Reliable, D::TransientLocal, L::Automatic)
        );
        assert!(none.deadline.is_default() && none.liveliness_lease_duration.is_default());

        let subs = [
            keep_all(
                R::BestEffort,
                D::TransientLocal,
                QosDuration::Default,
                L::Automatic,
                secs(1),
            ),
            keep_all(
                R::Reliable,
                D::Volatile,
                secs(3),
                L::ManualByTopic,
                QosDuration::Default,
            ),
            keep_all(R::BestEffort, D::Volatile, secs(2), L::Automatic, secs(2)),
        ];
        let r = ba.resolve_best_available_for_publisher(&subs);
        assert_eq!(
            (r.reliability, r.durability, r.liveliness),
            (R::Reliable, D::TransientLocal, L::ManualByTopic)
        );
        assert_eq!(
            (r.deadline, r.liveliness_lease_duration),
            (secs(2), secs(1))
        );
    }

    #[test]
    fn services() {
        let r = Qos::best_available().resolve_best_available_for_services();
        let s = Qos::services_default();
        assert_eq!(
            (r.reliability, r.durability, r.liveliness),
            (s.reliability, s.durability, s.liveliness)
        );
        assert_eq!(
            (r.deadline, r.liveliness_lease_duration),
            (s.deadline, s.liveliness_lease_duration)
        );
        assert!(!r.has_best_available_policy());
    }
}
