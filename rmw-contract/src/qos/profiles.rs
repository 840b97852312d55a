//! The standard ROS 2 Jazzy QoS profiles.
//!
//! Values from rmw `include/rmw/qos_profiles.h` (jazzy branch), except `rosout_default`
//! (rcl `include/rcl/logging_rosout.h`, rcl 9.2.0 = jazzy) and `action_status_default`
//! (rcl_action `include/rcl_action/default_qos.h`); rclpy's `QoSPresetProfiles` offers the same
//! set minus rosout. In all of them deadline, lifespan and lease are `RMW_DURATION_UNSPECIFIED`
//! unless noted, liveliness is SYSTEM_DEFAULT and `avoid_ros_namespace_conventions` false.

use std::time::Duration;

use super::{
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, Qos, QosDuration, ReliabilityPolicy,
};

/// The common shape of the standard profiles.
const fn profile(
    history: HistoryPolicy,
    depth: usize,
    reliability: ReliabilityPolicy,
    durability: DurabilityPolicy,
) -> Qos {
    Qos {
        history,
        depth,
        reliability,
        durability,
        deadline: QosDuration::Default,
        lifespan: QosDuration::Default,
        liveliness: LivelinessPolicy::SystemDefault,
        liveliness_lease_duration: QosDuration::Default,
        avoid_ros_namespace_conventions: false,
    }
}

impl Qos {
    /// `rmw_qos_profile_default`: KEEP_LAST 10, RELIABLE, VOLATILE.
    pub const fn default_profile() -> Self {
        profile(
            HistoryPolicy::KeepLast,
            10,
            ReliabilityPolicy::Reliable,
            DurabilityPolicy::Volatile,
        )
    }

    /// `rmw_qos_profile_services_default`: KEEP_LAST 10, RELIABLE, VOLATILE.
    pub const fn services_default() -> Self {
        profile(
            HistoryPolicy::KeepLast,
            10,
            ReliabilityPolicy::Reliable,
            DurabilityPolicy::Volatile,
        )
    }

    /// `rmw_qos_profile_parameters`: KEEP_LAST 1000, RELIABLE, VOLATILE.
    pub const fn parameters() -> Self {
        profile(
            HistoryPolicy::KeepLast,
            1000,
            ReliabilityPolicy::Reliable,
            DurabilityPolicy::Volatile,
        )
    }

    /// `rmw_qos_profile_parameter_events`: KEEP_LAST 1000, RELIABLE, VOLATILE.
    pub const fn parameter_events() -> Self {
        profile(
            HistoryPolicy::KeepLast,
            1000,
            ReliabilityPolicy::Reliable,
            DurabilityPolicy::Volatile,
        )
    }

    /// `rmw_qos_profile_sensor_data`: KEEP_LAST 5, BEST_EFFORT, VOLATILE.
    pub const fn sensor_data() -> Self {
        profile(
            HistoryPolicy::KeepLast,
            5,
            ReliabilityPolicy::BestEffort,
            DurabilityPolicy::Volatile,
        )
    }

    /// `rmw_qos_profile_system_default`: every policy SYSTEM_DEFAULT, depth 0
    /// (`RMW_QOS_POLICY_DEPTH_SYSTEM_DEFAULT`).
    pub const fn system_default() -> Self {
        profile(
            HistoryPolicy::SystemDefault,
            0,
            ReliabilityPolicy::SystemDefault,
            DurabilityPolicy::SystemDefault,
        )
    }

    /// `rmw_qos_profile_best_available`: KEEP_LAST 10; reliability, durability, liveliness,
    /// deadline and lease BEST_AVAILABLE; lifespan default.
    pub const fn best_available() -> Self {
        let mut qos = profile(
            HistoryPolicy::KeepLast,
            10,
            ReliabilityPolicy::BestAvailable,
            DurabilityPolicy::BestAvailable,
        );
        qos.deadline = QosDuration::BestAvailable;
        qos.liveliness = LivelinessPolicy::BestAvailable;
        qos.liveliness_lease_duration = QosDuration::BestAvailable;
        qos
    }

    /// `rmw_qos_profile_unknown`: history, reliability, durability and liveliness UNKNOWN,
    /// depth 0, durations default. What ROS starts from for a discovered endpoint.
    pub const fn unknown() -> Self {
        let mut qos = profile(
            HistoryPolicy::Unknown,
            0,
            ReliabilityPolicy::Unknown,
            DurabilityPolicy::Unknown,
        );
        qos.liveliness = LivelinessPolicy::Unknown;
        qos
    }

    /// rcl `rcl_qos_profile_rosout_default`: KEEP_LAST 1000, RELIABLE, TRANSIENT_LOCAL,
    /// lifespan 10 s.
    pub const fn rosout_default() -> Self {
        let mut qos = profile(
            HistoryPolicy::KeepLast,
            1000,
            ReliabilityPolicy::Reliable,
            DurabilityPolicy::TransientLocal,
        );
        qos.lifespan = QosDuration::Finite(Duration::from_secs(10));
        qos
    }

    /// rcl_action `rcl_action_qos_profile_status_default`: KEEP_LAST 1, RELIABLE,
    /// TRANSIENT_LOCAL.
    pub const fn action_status_default() -> Self {
        profile(
            HistoryPolicy::KeepLast,
            1,
            ReliabilityPolicy::Reliable,
            DurabilityPolicy::TransientLocal,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Compact (history, depth, reliability, durability, liveliness) view of a profile.
    fn shape(
        q: &Qos,
    ) -> (
        HistoryPolicy,
        usize,
        ReliabilityPolicy,
        DurabilityPolicy,
        LivelinessPolicy,
    ) {
        (
            q.history,
            q.depth,
            q.reliability,
            q.durability,
            q.liveliness,
        )
    }

    #[test]
    fn standard_profiles_match_rmw_jazzy() {
        use DurabilityPolicy as D;
        use HistoryPolicy as H;
        use LivelinessPolicy as L;
        use ReliabilityPolicy as R;
        let sd = L::SystemDefault;
        assert_eq!(
            shape(&Qos::default_profile()),
            (H::KeepLast, 10, R::Reliable, D::Volatile, sd)
        );
        assert_eq!(
            shape(&Qos::services_default()),
            (H::KeepLast, 10, R::Reliable, D::Volatile, sd)
        );
        assert_eq!(
            shape(&Qos::parameters()),
            (H::KeepLast, 1000, R::Reliable, D::Volatile, sd)
        );
        assert_eq!(
            shape(&Qos::parameter_events()),
            (H::KeepLast, 1000, R::Reliable, D::Volatile, sd)
        );
        assert_eq!(
            shape(&Qos::sensor_data()),
            (H::KeepLast, 5, R::BestEffort, D::Volatile, sd)
        );
        assert_eq!(
            shape(&Qos::system_default()),
            (H::SystemDefault, 0, R::SystemDefault, D::SystemDefault, sd)
        );
        assert_eq!(
            shape(&Qos::best_available()),
            (
                H::KeepLast,
                10,
                R::BestAvailable,
                D::BestAvailable,
                L::BestAvailable
            )
        );
        assert_eq!(
            shape(&Qos::unknown()),
            (H::Unknown, 0, R::Unknown, D::Unknown, L::Unknown)
        );
        assert_eq!(
            shape(&Qos::rosout_default()),
            (H::KeepLast, 1000, R::Reliable, D::TransientLocal, sd)
        );
        assert_eq!(
            shape(&Qos::action_status_default()),
            (H::KeepLast, 1, R::Reliable, D::TransientLocal, sd)
        );
        assert_eq!(Qos::default(), Qos::default_profile());
    }

    #[test]
    fn standard_profile_durations() {
        for q in [
            Qos::default_profile(),
            Qos::services_default(),
            Qos::parameters(),
            Qos::parameter_events(),
            Qos::sensor_data(),
            Qos::system_default(),
            Qos::unknown(),
            Qos::action_status_default(),
        ] {
            assert!(q.deadline.is_default() && q.lifespan.is_default());
            assert!(q.liveliness_lease_duration.is_default());
            assert!(!q.avoid_ros_namespace_conventions);
            assert!(!q.has_best_available_policy());
        }
        let ba = Qos::best_available();
        assert_eq!(ba.deadline.to_rmw_time(), (9_223_372_036, 854_775_806));
        assert_eq!(
            ba.liveliness_lease_duration.to_rmw_time(),
            (9_223_372_036, 854_775_806)
        );
        assert!(ba.lifespan.is_default());
        assert!(ba.has_best_available_policy());
        assert_eq!(Qos::rosout_default().lifespan.to_rmw_time(), (10, 0));
    }
}
