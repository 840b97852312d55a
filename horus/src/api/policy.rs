//! What the scheduler does when a node misses its deadline ([`Miss`]) or fails
//! ([`FailurePolicy`]).

use std::time::Duration;

/// Deadline-miss policy, set with [`NodeBuilder::on_miss`](crate::NodeBuilder::on_miss).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Miss {
    /// Log a warning and go on (the default).
    #[default]
    Warn,
    /// Skip the node's next tick, resume the cycle after.
    Skip,
    /// Call `enter_safe_state()` (the node is isolated until `is_safe_state()` returns true).
    SafeMode,
    /// Stop the whole scheduler (every node's `shutdown` runs).
    Stop,
}

/// Error-recovery strategy, set with
/// [`NodeBuilder::failure_policy`](crate::NodeBuilder::failure_policy). It applies to a panic
/// in `tick` and to a failed (or panicking) `init`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FailurePolicy {
    /// The failure stops the scheduler at once (the default).
    #[default]
    Fatal,
    /// Re-initialize (`init` again) after `initial_backoff`, doubling the wait at each restart;
    /// a failure after `max_restarts` restarts is fatal.
    Restart {
        /// How many restarts are allowed.
        max_restarts: u32,
        /// The wait before the first restart (then 2×, 4×, …).
        initial_backoff: Duration,
    },
    /// Tolerate failures; after `max_failures` consecutive ones, skip the node until `cooldown`
    /// has passed, then try again. A node whose `init` fails is never ticked.
    Skip {
        /// Consecutive failures tolerated.
        max_failures: u32,
        /// How long the node is skipped after that.
        cooldown: Duration,
    },
    /// Log and go on: the node keeps ticking. A node whose `init` fails is never ticked.
    Ignore,
}

impl FailurePolicy {
    /// The wait before restart number `restart` (1-based): `initial_backoff × 2^(restart-1)`,
    /// saturating.
    pub fn restart_backoff(initial_backoff: Duration, restart: u32) -> Duration {
        let factor = 1u32
            .checked_shl(restart.saturating_sub(1))
            .unwrap_or(u32::MAX);
        initial_backoff.saturating_mul(factor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles() {
        let b = Duration::from_millis(10);
        assert_eq!(FailurePolicy::restart_backoff(b, 1), b);
        assert_eq!(FailurePolicy::restart_backoff(b, 2), b * 2);
        assert_eq!(FailurePolicy::restart_backoff(b, 4), b * 8);
        assert_eq!(
            FailurePolicy::restart_backoff(b, 40),
            b.saturating_mul(u32::MAX)
        );
    }
}
