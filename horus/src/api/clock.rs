//! Time for the scheduler: a [`Clock`] (the system's monotonic clock, or a [`ManualClock`] that
//! tests move), and the [`StopHandle`] that ends `run`.

use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// The scheduler's time source. Times are offsets from an arbitrary origin.
pub trait Clock: Send + Sync {
    /// The current time.
    fn now(&self) -> Duration;

    /// Waits until `deadline` or until `stop` is stopped, whichever comes first.
    fn wait_until(&self, deadline: Duration, stop: &StopHandle);
}

/// The system's monotonic clock (`Instant`); waiting blocks on the stop handle's condition
/// variable, so `stop()` wakes it at once.
#[derive(Debug)]
pub struct SystemClock {
    origin: Instant,
}

impl SystemClock {
    /// A clock whose origin is now.
    pub fn new() -> Self {
        Self {
            origin: Instant::now(),
        }
    }
}

impl Default for SystemClock {
    fn default() -> Self {
        Self::new()
    }
}

impl Clock for SystemClock {
    fn now(&self) -> Duration {
        self.origin.elapsed()
    }

    fn wait_until(&self, deadline: Duration, stop: &StopHandle) {
        let now = self.now();
        if deadline > now {
            stop.wait_timeout(deadline - now);
        }
    }
}

/// A clock that moves only when told to (tests): [`advance`](Self::advance), or a scheduler
/// waiting on it, which jumps straight to the deadline.
#[derive(Debug, Default)]
pub struct ManualClock {
    now: Mutex<Duration>,
}

impl ManualClock {
    /// A clock at time zero.
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// Moves the clock forward by `by`.
    pub fn advance(&self, by: Duration) {
        let mut now = self.now.lock().unwrap_or_else(|p| p.into_inner());
        *now += by;
    }

    /// Sets the time (never backwards).
    pub fn set(&self, to: Duration) {
        let mut now = self.now.lock().unwrap_or_else(|p| p.into_inner());
        *now = (*now).max(to);
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Duration {
        *self.now.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn wait_until(&self, deadline: Duration, _stop: &StopHandle) {
        self.set(deadline);
    }
}

/// Stops a running scheduler from anywhere (another thread, a signal handler, a node).
#[derive(Clone, Debug, Default)]
pub struct StopHandle {
    inner: Arc<(Mutex<bool>, Condvar)>,
}

impl StopHandle {
    /// Asks the scheduler to stop: `run` returns after every node's `shutdown`.
    pub fn stop(&self) {
        let (flag, cv) = &*self.inner;
        *flag.lock().unwrap_or_else(|p| p.into_inner()) = true;
        cv.notify_all();
    }

    /// Whether a stop was asked for.
    pub fn is_stopped(&self) -> bool {
        *self.inner.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Blocks until stopped or `timeout` passed; returns whether stopped.
    pub fn wait_timeout(&self, timeout: Duration) -> bool {
        let (flag, cv) = &*self.inner;
        let guard = flag.lock().unwrap_or_else(|p| p.into_inner());
        let (guard, _) = cv
            .wait_timeout_while(guard, timeout, |stopped| !*stopped)
            .unwrap_or_else(|p| p.into_inner());
        *guard
    }

    pub(crate) fn downgrade(&self) -> std::sync::Weak<(Mutex<bool>, Condvar)> {
        Arc::downgrade(&self.inner)
    }

    pub(crate) fn from_inner(inner: Arc<(Mutex<bool>, Condvar)>) -> Self {
        Self { inner }
    }
}
