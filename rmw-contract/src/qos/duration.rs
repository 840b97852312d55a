//! `QosDuration`: the deadline / lifespan / liveliness-lease values of an rmw QoS profile.
//!
//! rmw keeps these as `rmw_time_t {u64 sec; u64 nsec}` with two reserved values
//! (rmw `include/rmw/time.h`, jazzy): `RMW_DURATION_UNSPECIFIED = {0, 0}` ("use the
//! middleware's default") and `RMW_DURATION_INFINITE = {9223372036, 854775807}` (INT64_MAX ns);
//! `rmw/types.h` adds `RMW_QOS_DEADLINE_BEST_AVAILABLE` and
//! `RMW_QOS_LIVELINESS_LEASE_DURATION_BEST_AVAILABLE` = INFINITE - 1 ns.
//! rmw compares times by their total nanoseconds, saturated at INT64_MAX
//! (`rmw_time_equal` / `rmw_time_total_nsec` in rmw `src/time.c`); so does this type.

use std::{cmp::Ordering, fmt, hash::Hash, time::Duration};

const NANOS_PER_SEC: u64 = 1_000_000_000;

/// An rmw QoS duration: unspecified (default), infinite, best available, or a finite value.
///
/// Equality, ordering and hashing use the total nanoseconds ([`QosDuration::total_nanos`]),
/// as rmw does, so `Finite(Duration::ZERO)` equals `Default`.
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub enum QosDuration {
    /// `RMW_DURATION_UNSPECIFIED` (`{0, 0}`): the middleware's default.
    #[default]
    Default,
    /// `RMW_DURATION_INFINITE` (INT64_MAX nanoseconds).
    Infinite,
    /// `RMW_QOS_DEADLINE_BEST_AVAILABLE` / `RMW_QOS_LIVELINESS_LEASE_DURATION_BEST_AVAILABLE`
    /// (INT64_MAX - 1 nanoseconds): chosen from the matched endpoints when created.
    BestAvailable,
    /// An explicit duration.
    Finite(Duration),
}

impl QosDuration {
    /// Total nanoseconds as `rmw_time_total_nsec` computes them (saturating at `i64::MAX`).
    pub fn total_nanos(&self) -> i64 {
        match self {
            Self::Default => 0,
            Self::Infinite => i64::MAX,
            Self::BestAvailable => i64::MAX - 1,
            Self::Finite(d) => i64::try_from(d.as_nanos()).unwrap_or(i64::MAX),
        }
    }

    /// From total nanoseconds, as `rmw_time_from_nsec` does (negative means infinite), mapping
    /// the reserved values to their variants.
    pub fn from_nanos(nanos: i64) -> Self {
        match nanos {
            0 => Self::Default,
            i64::MAX => Self::Infinite,
            n if n == i64::MAX - 1 => Self::BestAvailable,
            n => match u64::try_from(n) {
                Ok(n) => Self::Finite(Duration::from_nanos(n)),
                Err(_) => Self::Infinite,
            },
        }
    }

    /// From an `rmw_time_t {sec, nsec}` pair.
    pub fn from_rmw_time(sec: u64, nsec: u64) -> Self {
        // rmw_time_total_nsec: saturate at INT64_MAX.
        let total = sec
            .checked_mul(NANOS_PER_SEC)
            .and_then(|s| s.checked_add(nsec))
            .and_then(|t| i64::try_from(t).ok())
            .unwrap_or(i64::MAX);
        Self::from_nanos(total)
    }

    /// As a normalized `rmw_time_t {sec, nsec}` pair; the reserved values give exactly rmw's
    /// constants.
    pub fn to_rmw_time(&self) -> (u64, u64) {
        let total = self.total_nanos().unsigned_abs();
        (total / NANOS_PER_SEC, total % NANOS_PER_SEC)
    }

    /// Whether this is `RMW_DURATION_UNSPECIFIED`.
    pub fn is_default(&self) -> bool {
        self.total_nanos() == 0
    }

    /// Whether this is `RMW_DURATION_INFINITE`.
    pub fn is_infinite(&self) -> bool {
        self.total_nanos() == i64::MAX
    }

    /// Whether this is the BEST_AVAILABLE marker value.
    pub fn is_best_available(&self) -> bool {
        self.total_nanos() == i64::MAX - 1
    }
}

impl From<Duration> for QosDuration {
    fn from(d: Duration) -> Self {
        Self::from_nanos(i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
    }
}

impl PartialEq for QosDuration {
    fn eq(&self, other: &Self) -> bool {
        self.total_nanos() == other.total_nanos()
    }
}

impl Eq for QosDuration {}

impl Hash for QosDuration {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.total_nanos().hash(state);
    }
}

impl PartialOrd for QosDuration {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for QosDuration {
    fn cmp(&self, other: &Self) -> Ordering {
        self.total_nanos().cmp(&other.total_nanos())
    }
}

/// rclpy `Duration.__str__` (rclpy `duration.py`): `Infinite` or `<n> nanoseconds`.
impl fmt::Display for QosDuration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_infinite() {
            f.write_str("Infinite")
        } else {
            write!(f, "{} nanoseconds", self.total_nanos())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reserved_rmw_times() {
        // RMW_DURATION_INFINITE / RMW_DURATION_UNSPECIFIED (rmw time.h) and the BEST_AVAILABLE
        // marker (rmw types.h).
        assert_eq!(
            QosDuration::from_rmw_time(9_223_372_036, 854_775_807),
            QosDuration::Infinite
        );
        assert_eq!(QosDuration::from_rmw_time(0, 0), QosDuration::Default);
        assert!(QosDuration::from_rmw_time(9_223_372_036, 854_775_806).is_best_available());
        assert_eq!(
            QosDuration::Infinite.to_rmw_time(),
            (9_223_372_036, 854_775_807)
        );
        assert_eq!(
            QosDuration::BestAvailable.to_rmw_time(),
            (9_223_372_036, 854_775_806)
        );
        assert_eq!(
            QosDuration::from_rmw_time(u64::MAX, 0),
            QosDuration::Infinite
        );
        assert_eq!(QosDuration::from_nanos(-5), QosDuration::Infinite);
    }

    #[test]
    fn equality_by_total_nanos() {
        assert_eq!(QosDuration::Finite(Duration::ZERO), QosDuration::Default);
        assert_eq!(
            QosDuration::from_rmw_time(1, 1_500_000_000),
            QosDuration::Finite(Duration::from_millis(2_500))
        );
        assert!(QosDuration::Finite(Duration::from_secs(1)) < QosDuration::Infinite);
        assert!(QosDuration::BestAvailable < QosDuration::Infinite);
    }

    #[test]
    fn displays_like_rclpy() {
        assert_eq!(QosDuration::Infinite.to_string(), "Infinite");
        assert_eq!(QosDuration::Default.to_string(), "0 nanoseconds");
        assert_eq!(
            QosDuration::Finite(Duration::from_secs(10)).to_string(),
            "10000000000 nanoseconds"
        );
        assert_eq!(
            QosDuration::BestAvailable.to_string(),
            "9223372036854775806 nanoseconds"
        );
    }
}
