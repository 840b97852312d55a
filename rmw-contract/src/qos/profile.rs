//! `Qos`: a ROS 2 QoS profile, field for field `rmw_qos_profile_t` (rmw `include/rmw/types.h`).

use super::{DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QosDuration, ReliabilityPolicy};

/// A ROS 2 QoS profile, mirroring `rmw_qos_profile_t`.
///
/// `Default` is `rmw_qos_profile_default` ([`Qos::default_profile`]).
/// It (de)serializes with serde field by field (graph snapshots carry it between processes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Qos {
    /// History policy.
    pub history: HistoryPolicy,
    /// Queue size for KEEP_LAST; 0 is `RMW_QOS_POLICY_DEPTH_SYSTEM_DEFAULT`.
    pub depth: usize,
    /// Reliability policy.
    pub reliability: ReliabilityPolicy,
    /// Durability policy.
    pub durability: DurabilityPolicy,
    /// Period within which a new sample is expected.
    pub deadline: QosDuration,
    /// Age after which a sample is no longer delivered.
    pub lifespan: QosDuration,
    /// Liveliness policy.
    pub liveliness: LivelinessPolicy,
    /// Time within which a publisher must show it is alive.
    pub liveliness_lease_duration: QosDuration,
    /// If true, names are used as given, without the `rt/`-style ROS prefixes.
    pub avoid_ros_namespace_conventions: bool,
}

impl Default for Qos {
    fn default() -> Self {
        Self::default_profile()
    }
}

impl Qos {
    /// KEEP_LAST with the given depth.
    #[must_use]
    pub fn keep_last(mut self, depth: usize) -> Self {
        self.history = HistoryPolicy::KeepLast;
        self.depth = depth;
        self
    }

    /// KEEP_ALL (depth is left as is; DDS ignores it).
    #[must_use]
    pub fn keep_all(mut self) -> Self {
        self.history = HistoryPolicy::KeepAll;
        self
    }

    /// Sets the history policy.
    #[must_use]
    pub fn with_history(mut self, history: HistoryPolicy) -> Self {
        self.history = history;
        self
    }

    /// Sets the depth.
    #[must_use]
    pub fn with_depth(mut self, depth: usize) -> Self {
        self.depth = depth;
        self
    }

    /// Sets the reliability policy.
    #[must_use]
    pub fn with_reliability(mut self, reliability: ReliabilityPolicy) -> Self {
        self.reliability = reliability;
        self
    }

    /// RELIABLE.
    #[must_use]
    pub fn reliable(self) -> Self {
        self.with_reliability(ReliabilityPolicy::Reliable)
    }

    /// BEST_EFFORT.
    #[must_use]
    pub fn best_effort(self) -> Self {
        self.with_reliability(ReliabilityPolicy::BestEffort)
    }

    /// Sets the durability policy.
    #[must_use]
    pub fn with_durability(mut self, durability: DurabilityPolicy) -> Self {
        self.durability = durability;
        self
    }

    /// TRANSIENT_LOCAL.
    #[must_use]
    pub fn transient_local(self) -> Self {
        self.with_durability(DurabilityPolicy::TransientLocal)
    }

    /// VOLATILE.
    #[must_use]
    pub fn volatile(self) -> Self {
        self.with_durability(DurabilityPolicy::Volatile)
    }

    /// Sets the deadline.
    #[must_use]
    pub fn with_deadline(mut self, deadline: impl Into<QosDuration>) -> Self {
        self.deadline = deadline.into();
        self
    }

    /// Sets the lifespan.
    #[must_use]
    pub fn with_lifespan(mut self, lifespan: impl Into<QosDuration>) -> Self {
        self.lifespan = lifespan.into();
        self
    }

    /// Sets the liveliness policy.
    #[must_use]
    pub fn with_liveliness(mut self, liveliness: LivelinessPolicy) -> Self {
        self.liveliness = liveliness;
        self
    }

    /// Sets the liveliness lease duration.
    #[must_use]
    pub fn with_liveliness_lease_duration(mut self, lease: impl Into<QosDuration>) -> Self {
        self.liveliness_lease_duration = lease.into();
        self
    }

    /// Sets `avoid_ros_namespace_conventions`.
    #[must_use]
    pub fn with_avoid_ros_namespace_conventions(mut self, avoid: bool) -> Self {
        self.avoid_ros_namespace_conventions = avoid;
        self
    }

    /// Whether any policy is BEST_AVAILABLE, i.e. must be resolved against the matched endpoints
    /// (rmw_dds_common `_qos_profile_has_best_available_policy`).
    pub fn has_best_available_policy(&self) -> bool {
        self.reliability == ReliabilityPolicy::BestAvailable
            || self.durability == DurabilityPolicy::BestAvailable
            || self.liveliness == LivelinessPolicy::BestAvailable
            || self.deadline.is_best_available()
            || self.liveliness_lease_duration.is_best_available()
    }
}
