//! [`RetryConfig`]: how `call_resilient` retries.

use std::time::Duration;

/// Retries for `call_resilient_with`: up to `max_retries` more attempts after the first, waiting
/// `initial_backoff`, then twice as long each time. Only transient errors are retried
/// ([`ServiceError::is_transient`](crate::ServiceError::is_transient): Timeout and Transport,
/// which includes [`TransportError::ServerGone`](crate::TransportError::ServerGone)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RetryConfig {
    /// Attempts after the first.
    pub max_retries: u32,
    /// Wait before the first retry.
    pub initial_backoff: Duration,
}

impl RetryConfig {
    /// `max_retries` retries with exponential backoff from `initial_backoff`.
    pub const fn new(max_retries: u32, initial_backoff: Duration) -> Self {
        Self {
            max_retries,
            initial_backoff,
        }
    }

    /// The wait before retry number `retry` (0-based): `initial_backoff * 2^retry`.
    pub fn backoff(&self, retry: u32) -> Duration {
        self.initial_backoff
            .saturating_mul(2u32.saturating_pow(retry))
    }
}

/// 3 retries, exponential backoff from 10 ms (`call_resilient`).
impl Default for RetryConfig {
    fn default() -> Self {
        Self::new(3, Duration::from_millis(10))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles() {
        let r = RetryConfig::default();
        assert_eq!(r.backoff(0), Duration::from_millis(10));
        assert_eq!(r.backoff(1), Duration::from_millis(20));
        assert_eq!(r.backoff(2), Duration::from_millis(40));
        assert_eq!(RetryConfig::new(1, Duration::MAX).backoff(5), Duration::MAX);
    }
}
