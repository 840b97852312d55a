//! Publisher/subscription QoS compatibility, as `rmw_qos_profile_check_compatible`.
//!
//! Both DDS RMWs in Jazzy implement it with rmw_dds_common `qos_profile_check_compatible`
//! (rmw_dds_common `src/qos.cpp`, jazzy); this is that logic with the same messages, typos
//! included ("durabilty"), joined the same way (each ends with `;`, errors before warnings,
//! warnings only when there is no error). BEST_AVAILABLE policies yield neither error nor warning,
//! as there.

use super::{DurabilityPolicy, LivelinessPolicy, Qos, ReliabilityPolicy};

/// The outcome of [`check_compatible`]: `rmw_qos_compatibility_type_t` with its reason text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum QosCompatibility {
    /// `RMW_QOS_COMPATIBILITY_OK`.
    Ok,
    /// `RMW_QOS_COMPATIBILITY_WARNING`: may not match (a policy is system default or unknown).
    Warning(String),
    /// `RMW_QOS_COMPATIBILITY_ERROR`: cannot match.
    Error(String),
}

/// rmw's name of a policy value, or `"unknown"` where rmw's `*_to_str` gives NULL.
fn rmw_name(name: Option<&'static str>) -> &'static str {
    name.unwrap_or("unknown")
}

/// Checks whether a publisher with `publisher` QoS and a subscription with `subscription` QoS
/// can communicate (rmw_dds_common `qos_profile_check_compatible`).
pub fn check_compatible(publisher: &Qos, subscription: &Qos) -> QosCompatibility {
    let errors = errors(publisher, subscription);
    if !errors.is_empty() {
        return QosCompatibility::Error(errors);
    }
    let warnings = warnings(publisher, subscription);
    if warnings.is_empty() {
        QosCompatibility::Ok
    } else {
        QosCompatibility::Warning(warnings)
    }
}

/// The policies on which a publisher of `publisher` QoS and a reader of `reader` QoS cannot
/// match ([`check_compatible`]'s errors, by policy), with their DDS policy ids, in Cyclone DDS's
/// order of checking (`qos_match_mask_p`): what an incompatible-QoS event names as the last
/// incompatible policy (Fast DDS: the highest id; Cyclone DDS: the first it checks).
pub fn incompatible_policies(publisher: &Qos, reader: &Qos) -> Vec<(u32, &'static str)> {
    let mut failing = Vec::new();
    if publisher.reliability == ReliabilityPolicy::BestEffort
        && reader.reliability == ReliabilityPolicy::Reliable
    {
        failing.push((11, "RELIABILITY"));
    }
    if publisher.durability == DurabilityPolicy::Volatile
        && reader.durability == DurabilityPolicy::TransientLocal
    {
        failing.push((2, "DURABILITY"));
    }
    let (p, r) = (publisher.deadline, reader.deadline);
    if !r.is_default() && (p.is_default() || r < p) {
        failing.push((4, "DEADLINE"));
    }
    let (p, r) = (
        publisher.liveliness_lease_duration,
        reader.liveliness_lease_duration,
    );
    if (publisher.liveliness == LivelinessPolicy::Automatic
        && reader.liveliness == LivelinessPolicy::ManualByTopic)
        || (!r.is_default() && (p.is_default() || r < p))
    {
        failing.push((8, "LIVELINESS"));
    }
    failing
}

/// The `ERROR: ...;` part of the reason.
fn errors(publisher: &Qos, subscription: &Qos) -> String {
    let mut reason = String::new();
    if publisher.reliability == ReliabilityPolicy::BestEffort
        && subscription.reliability == ReliabilityPolicy::Reliable
    {
        reason.push_str("ERROR: Best effort publisher and reliable subscription;");
    }
    if publisher.durability == DurabilityPolicy::Volatile
        && subscription.durability == DurabilityPolicy::TransientLocal
    {
        reason.push_str("ERROR: Volatile publisher and transient local subscription;");
    }
    let (pub_deadline, sub_deadline) = (publisher.deadline, subscription.deadline);
    if pub_deadline.is_default() && !sub_deadline.is_default() {
        reason.push_str("ERROR: Subscription has a deadline, but publisher does not;");
    }
    if !pub_deadline.is_default() && !sub_deadline.is_default() && sub_deadline < pub_deadline {
        reason.push_str("ERROR: Subscription deadline is less than publisher deadline;");
    }
    if publisher.liveliness == LivelinessPolicy::Automatic
        && subscription.liveliness == LivelinessPolicy::ManualByTopic
    {
        reason.push_str(
            "ERROR: Publisher's liveliness is automatic and subscription's is manual by topic;",
        );
    }
    let (pub_lease, sub_lease) = (
        publisher.liveliness_lease_duration,
        subscription.liveliness_lease_duration,
    );
    if pub_lease.is_default() && !sub_lease.is_default() {
        reason.push_str(
            "ERROR: Subscription has a liveliness lease duration, but publisher does not;",
        );
    }
    if !pub_lease.is_default() && !sub_lease.is_default() && sub_lease < pub_lease {
        reason.push_str("ERROR: Subscription liveliness lease duration is less than publisher;");
    }
    reason
}

/// The `WARNING: ...;` part of the reason (only consulted when there is no error).
fn warnings(publisher: &Qos, subscription: &Qos) -> String {
    use DurabilityPolicy as D;
    use LivelinessPolicy as L;
    use ReliabilityPolicy as R;
    let mut reason = String::new();

    let pub_rel = rmw_name(publisher.reliability.as_rmw_str());
    let sub_rel = rmw_name(subscription.reliability.as_rmw_str());
    let pub_rel_unknown = matches!(publisher.reliability, R::SystemDefault | R::Unknown);
    let sub_rel_unknown = matches!(subscription.reliability, R::SystemDefault | R::Unknown);
    if pub_rel_unknown && sub_rel_unknown {
        reason.push_str(&format!(
            "WARNING: Publisher reliability is {pub_rel} and subscription reliability is {sub_rel};"
        ));
    } else if pub_rel_unknown && subscription.reliability == R::Reliable {
        reason.push_str(&format!(
            "WARNING: Reliable subscription, but publisher is {pub_rel};"
        ));
    } else if publisher.reliability == R::BestEffort && sub_rel_unknown {
        reason.push_str(&format!(
            "WARNING: Best effort publisher, but subscription is {sub_rel};"
        ));
    }

    let pub_dur = rmw_name(publisher.durability.as_rmw_str());
    let sub_dur = rmw_name(subscription.durability.as_rmw_str());
    let pub_dur_unknown = matches!(publisher.durability, D::SystemDefault | D::Unknown);
    let sub_dur_unknown = matches!(subscription.durability, D::SystemDefault | D::Unknown);
    if pub_dur_unknown && sub_dur_unknown {
        // "durabilty" [sic], as in rmw_dds_common.
        reason.push_str(&format!(
            "WARNING: Publisher durabilty is {pub_dur} and subscription durability is {sub_dur};"
        ));
    } else if pub_dur_unknown && subscription.durability == D::TransientLocal {
        reason.push_str(&format!(
            "WARNING: Transient local subscription, but publisher is {pub_dur};"
        ));
    } else if publisher.durability == D::Volatile && sub_dur_unknown {
        reason.push_str(&format!(
            "WARNING: Volatile publisher, but subscription is {sub_dur};"
        ));
    }

    let pub_live = rmw_name(publisher.liveliness.as_rmw_str());
    let sub_live = rmw_name(subscription.liveliness.as_rmw_str());
    let pub_live_unknown = matches!(publisher.liveliness, L::SystemDefault | L::Unknown);
    let sub_live_unknown = matches!(subscription.liveliness, L::SystemDefault | L::Unknown);
    if pub_live_unknown && sub_live_unknown {
        reason.push_str(&format!(
            "WARNING: Publisher liveliness is {pub_live} and subscription liveliness is {sub_live};"
        ));
    } else if pub_live_unknown && subscription.liveliness == L::ManualByTopic {
        reason.push_str(&format!(
            "WARNING: Subscription's liveliness is manual by topic, but publisher's is {pub_live};"
        ));
    } else if publisher.liveliness == L::Automatic && sub_live_unknown {
        reason.push_str(&format!(
            "WARNING: Publisher's liveliness is automatic, but subscription's is {sub_live};"
        ));
    }
    reason
}

#[cfg(test)]
mod tests {
    //! Cases from rmw_dds_common `test/test_qos.cpp` (jazzy), `test_qos_profile_check_compatible_*`.
    use std::time::Duration;

    use super::*;
    use crate::qos::QosDuration;

    /// `get_qos_profile_fixture()` of test_qos.cpp.
    fn fixture() -> Qos {
        Qos::default_profile()
            .keep_last(5)
            .with_liveliness(LivelinessPolicy::Automatic)
    }

    fn rmw_time(sec: u64, nsec: u64) -> QosDuration {
        QosDuration::from_rmw_time(sec, nsec)
    }

    fn is_ok(c: &QosCompatibility) -> bool {
        *c == QosCompatibility::Ok
    }
    fn is_warning(c: &QosCompatibility) -> bool {
        matches!(c, QosCompatibility::Warning(r) if !r.is_empty())
    }
    fn is_error(c: &QosCompatibility) -> bool {
        matches!(c, QosCompatibility::Error(r) if !r.is_empty())
    }

    #[test]
    fn reliability() {
        use ReliabilityPolicy::*;
        let check = |p, s| {
            check_compatible(
                &fixture().with_reliability(p),
                &fixture().with_reliability(s),
            )
        };
        assert!(is_ok(&check(Reliable, Reliable)));
        assert!(is_ok(&check(Reliable, BestEffort)));
        assert!(is_ok(&check(BestEffort, BestEffort)));
        assert_eq!(
            check(BestEffort, Reliable),
            QosCompatibility::Error(
                "ERROR: Best effort publisher and reliable subscription;".into()
            )
        );
    }

    #[test]
    fn durability() {
        use DurabilityPolicy::*;
        let check =
            |p, s| check_compatible(&fixture().with_durability(p), &fixture().with_durability(s));
        assert!(is_ok(&check(Volatile, Volatile)));
        assert!(is_error(&check(Volatile, TransientLocal)));
        assert!(is_ok(&check(TransientLocal, TransientLocal)));
        assert!(is_ok(&check(TransientLocal, Volatile)));
    }

    #[test]
    fn deadline() {
        let check = |p: QosDuration, s: QosDuration| {
            check_compatible(&fixture().with_deadline(p), &fixture().with_deadline(s))
        };
        let default = QosDuration::Default;
        assert!(is_ok(&check(default, default)));
        assert_eq!(
            check(default, rmw_time(1, 0)),
            QosCompatibility::Error(
                "ERROR: Subscription has a deadline, but publisher does not;".into()
            )
        );
        assert_eq!(
            check(rmw_time(1, 1), rmw_time(1, 0)),
            QosCompatibility::Error(
                "ERROR: Subscription deadline is less than publisher deadline;".into()
            )
        );
        assert!(is_ok(&check(rmw_time(1, 1), rmw_time(1, 1))));
        assert!(is_ok(&check(rmw_time(1, 1), rmw_time(2, 0))));
    }

    #[test]
    fn liveliness() {
        use LivelinessPolicy::*;
        let check =
            |p, s| check_compatible(&fixture().with_liveliness(p), &fixture().with_liveliness(s));
        assert!(is_ok(&check(Automatic, Automatic)));
        assert!(is_error(&check(Automatic, ManualByTopic)));
        assert!(is_ok(&check(ManualByTopic, ManualByTopic)));
        assert!(is_ok(&check(ManualByTopic, Automatic)));
    }

    #[test]
    fn liveliness_lease_duration() {
        let check = |p: QosDuration, s: QosDuration| {
            check_compatible(
                &fixture().with_liveliness_lease_duration(p),
                &fixture().with_liveliness_lease_duration(s),
            )
        };
        let default = QosDuration::Default;
        assert!(is_ok(&check(default, default)));
        assert!(is_error(&check(default, rmw_time(1, 0))));
        assert!(is_ok(&check(rmw_time(1, 0), rmw_time(1, 0))));
        assert_eq!(
            check(rmw_time(1, 1), rmw_time(1, 0)),
            QosCompatibility::Error(
                "ERROR: Subscription liveliness lease duration is less than publisher;".into()
            )
        );
        assert!(is_ok(&check(rmw_time(1, 1), rmw_time(2, 1))));
    }

    #[test]
    fn system_default_and_unknown_warn() {
        use DurabilityPolicy as D;
        use LivelinessPolicy as L;
        use ReliabilityPolicy as R;
        for unknown_rel in [R::SystemDefault, R::Unknown] {
            let rel = |p, s| {
                check_compatible(
                    &fixture().with_reliability(p),
                    &fixture().with_reliability(s),
                )
            };
            assert!(is_warning(&rel(R::BestEffort, unknown_rel)));
            assert!(is_warning(&rel(unknown_rel, R::Reliable)));
            assert!(is_warning(&rel(unknown_rel, unknown_rel)));
        }
        for unknown_dur in [D::SystemDefault, D::Unknown] {
            let dur = |p, s| {
                check_compatible(&fixture().with_durability(p), &fixture().with_durability(s))
            };
            assert!(is_warning(&dur(D::Volatile, unknown_dur)));
            assert!(is_warning(&dur(unknown_dur, D::TransientLocal)));
            assert!(is_warning(&dur(unknown_dur, unknown_dur)));
        }
        for unknown_live in [L::SystemDefault, L::Unknown] {
            let live = |p, s| {
                check_compatible(&fixture().with_liveliness(p), &fixture().with_liveliness(s))
            };
            assert!(is_warning(&live(L::Automatic, unknown_live)));
            assert!(is_warning(&live(unknown_live, L::ManualByTopic)));
            assert!(is_warning(&live(unknown_live, unknown_live)));
        }
    }

    #[test]
    fn reason_texts_join_like_rmw() {
        // Both errors, in rmw's order; warnings are suppressed when there is an error.
        let publisher = fixture()
            .best_effort()
            .with_durability(DurabilityPolicy::Volatile)
            .with_liveliness(LivelinessPolicy::SystemDefault);
        let subscription = fixture()
            .transient_local()
            .with_liveliness(LivelinessPolicy::Unknown);
        assert_eq!(
            check_compatible(&publisher, &subscription),
            QosCompatibility::Error(
                "ERROR: Best effort publisher and reliable subscription;\
                 ERROR: Volatile publisher and transient local subscription;"
                    .into()
            )
        );
        // system_default / unknown everywhere: three warnings with rmw's names.
        assert_eq!(
            check_compatible(&Qos::system_default(), &Qos::unknown()),
            QosCompatibility::Warning(
                "WARNING: Publisher reliability is system_default and subscription reliability \
                 is unknown;\
                 WARNING: Publisher durabilty is system_default and subscription durability is \
                 unknown;\
                 WARNING: Publisher liveliness is system_default and subscription liveliness is \
                 unknown;"
                    .into()
            )
        );
        // A ros2cli default publisher vs. a remote endpoint seen through discovery.
        let remote = fixture().with_deadline(Duration::from_millis(100));
        assert!(is_error(&check_compatible(
            &Qos::default_profile(),
            &remote
        )));
    }

    #[test]
    fn best_available_is_neither_error_nor_warning() {
        assert!(is_ok(&check_compatible(
            &Qos::best_available(),
            &Qos::best_available()
        )));
    }

    #[test]
    fn incompatible_policies_are_the_errors_by_policy() {
        let reliable = Qos {
            reliability: ReliabilityPolicy::Reliable,
            durability: DurabilityPolicy::TransientLocal,
            ..Qos::default()
        };
        let best_effort = Qos {
            reliability: ReliabilityPolicy::BestEffort,
            durability: DurabilityPolicy::Volatile,
            ..Qos::default()
        };
        assert_eq!(
            incompatible_policies(&best_effort, &reliable),
            vec![(11, "RELIABILITY"), (2, "DURABILITY")]
        );
        assert!(matches!(
            check_compatible(&best_effort, &reliable),
            QosCompatibility::Error(_)
        ));
        assert!(incompatible_policies(&reliable, &best_effort).is_empty());
        assert!(!matches!(
            check_compatible(&reliable, &best_effort),
            QosCompatibility::Error(_)
        ));
    }
}
