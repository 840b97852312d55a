//! The enumerated QoS policies of `rmw_qos_profile_t` (rmw `include/rmw/types.h`, jazzy).
//!
//! Each has two spellings:
//! - `Display` gives the upper-case name that rclpy's policy enums carry and ros2cli prints
//!   (rclpy `qos.py`: `ReliabilityPolicy.RELIABLE.name == "RELIABLE"`);
//! - [`as_rmw_str`](ReliabilityPolicy::as_rmw_str) gives rmw's lower-case name
//!   (rmw `src/qos_string_conversions.c`), `None` for UNKNOWN as there, and `FromStr`
//!   parses those names (ASCII case-insensitively, so the upper-case ones parse too).

use std::{fmt, str::FromStr};

use super::QosError;

/// Parses `s` as one of `names` (ASCII case-insensitive), else `InvalidPolicyName`.
fn parse_name<T: Copy>(policy: &'static str, s: &str, names: &[(&str, T)]) -> Result<T, QosError> {
    names
        .iter()
        .find(|(name, _)| name.eq_ignore_ascii_case(s))
        .map(|(_, value)| *value)
        .ok_or_else(|| QosError::InvalidPolicyName {
            policy,
            value: s.to_owned(),
        })
}

/// `rmw_qos_history_policy_t`: how many samples are kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum HistoryPolicy {
    /// `RMW_QOS_POLICY_HISTORY_SYSTEM_DEFAULT`.
    SystemDefault,
    /// `RMW_QOS_POLICY_HISTORY_KEEP_LAST`: keep the last `depth` samples.
    KeepLast,
    /// `RMW_QOS_POLICY_HISTORY_KEEP_ALL`: keep all samples, subject to resource limits.
    KeepAll,
    /// `RMW_QOS_POLICY_HISTORY_UNKNOWN`: not known (e.g. a remote endpoint: DDS discovery does
    /// not carry history).
    Unknown,
}

impl HistoryPolicy {
    /// rmw's lower-case name (`rmw_qos_history_policy_to_str`); `None` for UNKNOWN.
    pub fn as_rmw_str(&self) -> Option<&'static str> {
        match self {
            Self::SystemDefault => Some("system_default"),
            Self::KeepLast => Some("keep_last"),
            Self::KeepAll => Some("keep_all"),
            Self::Unknown => None,
        }
    }

    /// The upper-case name rclpy and ros2cli show.
    pub fn name(&self) -> &'static str {
        match self {
            Self::SystemDefault => "SYSTEM_DEFAULT",
            Self::KeepLast => "KEEP_LAST",
            Self::KeepAll => "KEEP_ALL",
            Self::Unknown => "UNKNOWN",
        }
    }
}

/// `rmw_qos_reliability_policy_t`: whether delivery is guaranteed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ReliabilityPolicy {
    /// `RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT`.
    SystemDefault,
    /// `RMW_QOS_POLICY_RELIABILITY_RELIABLE`.
    Reliable,
    /// `RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT`.
    BestEffort,
    /// `RMW_QOS_POLICY_RELIABILITY_UNKNOWN`.
    Unknown,
    /// `RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE`: chosen from the matched endpoints.
    BestAvailable,
}

impl ReliabilityPolicy {
    /// rmw's lower-case name (`rmw_qos_reliability_policy_to_str`); `None` for UNKNOWN.
    pub fn as_rmw_str(&self) -> Option<&'static str> {
        match self {
            Self::SystemDefault => Some("system_default"),
            Self::Reliable => Some("reliable"),
            Self::BestEffort => Some("best_effort"),
            Self::BestAvailable => Some("best_available"),
            Self::Unknown => None,
        }
    }

    /// The upper-case name rclpy and ros2cli show.
    pub fn name(&self) -> &'static str {
        match self {
            Self::SystemDefault => "SYSTEM_DEFAULT",
            Self::Reliable => "RELIABLE",
            Self::BestEffort => "BEST_EFFORT",
            Self::Unknown => "UNKNOWN",
            Self::BestAvailable => "BEST_AVAILABLE",
        }
    }
}

/// `rmw_qos_durability_policy_t`: whether late joiners get earlier samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum DurabilityPolicy {
    /// `RMW_QOS_POLICY_DURABILITY_SYSTEM_DEFAULT`.
    SystemDefault,
    /// `RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL`.
    TransientLocal,
    /// `RMW_QOS_POLICY_DURABILITY_VOLATILE`.
    Volatile,
    /// `RMW_QOS_POLICY_DURABILITY_UNKNOWN` (also what DDS TRANSIENT / PERSISTENT map to).
    Unknown,
    /// `RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE`: chosen from the matched endpoints.
    BestAvailable,
}

impl DurabilityPolicy {
    /// rmw's lower-case name (`rmw_qos_durability_policy_to_str`); `None` for UNKNOWN.
    pub fn as_rmw_str(&self) -> Option<&'static str> {
        match self {
            Self::SystemDefault => Some("system_default"),
            Self::TransientLocal => Some("transient_local"),
            Self::Volatile => Some("volatile"),
            Self::BestAvailable => Some("best_available"),
            Self::Unknown => None,
        }
    }

    /// The upper-case name rclpy and ros2cli show.
    pub fn name(&self) -> &'static str {
        match self {
            Self::SystemDefault => "SYSTEM_DEFAULT",
            Self::TransientLocal => "TRANSIENT_LOCAL",
            Self::Volatile => "VOLATILE",
            Self::Unknown => "UNKNOWN",
            Self::BestAvailable => "BEST_AVAILABLE",
        }
    }
}

/// `rmw_qos_liveliness_policy_t`: how a publisher shows it is alive
/// (the deprecated MANUAL_BY_NODE is not represented).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum LivelinessPolicy {
    /// `RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT`.
    SystemDefault,
    /// `RMW_QOS_POLICY_LIVELINESS_AUTOMATIC`.
    Automatic,
    /// `RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC`.
    ManualByTopic,
    /// `RMW_QOS_POLICY_LIVELINESS_UNKNOWN` (also what DDS MANUAL_BY_PARTICIPANT maps to).
    Unknown,
    /// `RMW_QOS_POLICY_LIVELINESS_BEST_AVAILABLE`: chosen from the matched endpoints.
    BestAvailable,
}

impl LivelinessPolicy {
    /// rmw's lower-case name (`rmw_qos_liveliness_policy_to_str`); `None` for UNKNOWN.
    pub fn as_rmw_str(&self) -> Option<&'static str> {
        match self {
            Self::SystemDefault => Some("system_default"),
            Self::Automatic => Some("automatic"),
            Self::ManualByTopic => Some("manual_by_topic"),
            Self::BestAvailable => Some("best_available"),
            Self::Unknown => None,
        }
    }

    /// The upper-case name rclpy and ros2cli show.
    pub fn name(&self) -> &'static str {
        match self {
            Self::SystemDefault => "SYSTEM_DEFAULT",
            Self::Automatic => "AUTOMATIC",
            Self::ManualByTopic => "MANUAL_BY_TOPIC",
            Self::Unknown => "UNKNOWN",
            Self::BestAvailable => "BEST_AVAILABLE",
        }
    }
}

impl fmt::Display for HistoryPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for ReliabilityPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for DurabilityPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for LivelinessPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Parses rmw's names (`rmw_qos_history_policy_from_str`), case-insensitively.
impl FromStr for HistoryPolicy {
    type Err = QosError;
    fn from_str(s: &str) -> Result<Self, QosError> {
        parse_name(
            "history",
            s,
            &[
                ("system_default", Self::SystemDefault),
                ("keep_last", Self::KeepLast),
                ("keep_all", Self::KeepAll),
            ],
        )
    }
}

/// Parses rmw's names (`rmw_qos_reliability_policy_from_str`), case-insensitively.
impl FromStr for ReliabilityPolicy {
    type Err = QosError;
    fn from_str(s: &str) -> Result<Self, QosError> {
        parse_name(
            "reliability",
            s,
            &[
                ("system_default", Self::SystemDefault),
                ("reliable", Self::Reliable),
                ("best_effort", Self::BestEffort),
                ("best_available", Self::BestAvailable),
            ],
        )
    }
}

/// Parses rmw's names (`rmw_qos_durability_policy_from_str`), case-insensitively.
impl FromStr for DurabilityPolicy {
    type Err = QosError;
    fn from_str(s: &str) -> Result<Self, QosError> {
        parse_name(
            "durability",
            s,
            &[
                ("system_default", Self::SystemDefault),
                ("transient_local", Self::TransientLocal),
                ("volatile", Self::Volatile),
                ("best_available", Self::BestAvailable),
            ],
        )
    }
}

/// Parses rmw's names (`rmw_qos_liveliness_policy_from_str`), case-insensitively.
impl FromStr for LivelinessPolicy {
    type Err = QosError;
    fn from_str(s: &str) -> Result<Self, QosError> {
        parse_name(
            "liveliness",
            s,
            &[
                ("system_default", Self::SystemDefault),
                ("automatic", Self::Automatic),
                ("manual_by_topic", Self::ManualByTopic),
                ("best_available", Self::BestAvailable),
            ],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_rclpy_and_rmw() {
        assert_eq!(ReliabilityPolicy::BestEffort.to_string(), "BEST_EFFORT");
        assert_eq!(
            ReliabilityPolicy::BestEffort.as_rmw_str(),
            Some("best_effort")
        );
        assert_eq!(
            DurabilityPolicy::TransientLocal.to_string(),
            "TRANSIENT_LOCAL"
        );
        assert_eq!(
            LivelinessPolicy::ManualByTopic.to_string(),
            "MANUAL_BY_TOPIC"
        );
        assert_eq!(HistoryPolicy::KeepAll.to_string(), "KEEP_ALL");
        assert_eq!(HistoryPolicy::Unknown.as_rmw_str(), None);
    }

    #[test]
    fn parses_rmw_names() {
        // The table of rmw test/test_qos_string_conversions.cpp (jazzy), both directions.
        for p in [
            ReliabilityPolicy::SystemDefault,
            ReliabilityPolicy::Reliable,
            ReliabilityPolicy::BestEffort,
            ReliabilityPolicy::BestAvailable,
        ] {
            let name = p.as_rmw_str().unwrap_or_default();
            assert_eq!(name.parse::<ReliabilityPolicy>(), Ok(p));
        }
        assert_eq!(
            "KEEP_LAST".parse::<HistoryPolicy>(),
            Ok(HistoryPolicy::KeepLast)
        );
        assert_eq!(
            "manual_by_topic".parse::<LivelinessPolicy>(),
            Ok(LivelinessPolicy::ManualByTopic)
        );
        assert_eq!(
            "transient_local".parse::<DurabilityPolicy>(),
            Ok(DurabilityPolicy::TransientLocal)
        );
        assert!(matches!(
            "unknown".parse::<DurabilityPolicy>(),
            Err(QosError::InvalidPolicyName {
                policy: "durability",
                ..
            })
        ));
        assert!("bad".parse::<ReliabilityPolicy>().is_err());
    }
}
