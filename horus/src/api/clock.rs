//! Time for the scheduler: a [`Clock`] (the system's monotonic clock, or a [`ManualClock`] that
//! tests move), and the [`StopHandle`] that ends `run`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

/// The scheduler's time source. Times are offsets from an arbitrary origin.
pub trait Clock: Send + Sync {
    /// The current time.
    fn now(&self) -> Duration;

    /// Waits until `deadline` or until `stop` is stopped, whichever comes first.
    fn wait_until(&self, deadline: Duration, stop: &StopHandle);
}

/// The system's monotonic clock; waiting blocks on the stop handle's condition variable, so
/// `stop()` wakes it at once.
///
/// Read through [`quanta`]: the CPU's time-stamp counter, calibrated against the OS monotonic
/// clock, where it is invariant and the kernel's own clock source (a few ns a read instead of a
/// `clock_gettime` call); the OS monotonic clock otherwise. The scheduler reads it once per
/// tick, so this is most of its per-tick cost.
#[derive(Debug)]
pub struct SystemClock {
    clock: quanta::Clock,
    origin: u64,
}

impl SystemClock {
    /// A clock whose origin is now.
    pub fn new() -> Self {
        let clock = quanta::Clock::new();
        let origin = clock.raw();
        Self { clock, origin }
    }
}

impl Default for SystemClock {
    fn default() -> Self {
        Self::new()
    }
}

impl Clock for SystemClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.clock.delta_as_nanos(self.origin, self.clock.raw()))
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
    inner: Arc<StopState>,
}

/// The state behind a [`StopHandle`]: the flag is read lock-free (the scheduler checks it every
/// cycle); the mutex and condition variable serve only waiters, which check the flag under the
/// lock, and `stop` notifies under it, so no wake-up is lost.
#[derive(Debug, Default)]
pub(crate) struct StopState {
    stopped: AtomicBool,
    lock: Mutex<()>,
    cv: Condvar,
}

impl StopHandle {
    /// Asks the scheduler to stop: `run` returns after every node's `shutdown`.
    pub fn stop(&self) {
        let s = &*self.inner;
        let _guard = s.lock.lock().unwrap_or_else(|p| p.into_inner());
        s.stopped.store(true, Ordering::Release);
        s.cv.notify_all();
    }

    /// Whether a stop was asked for.
    pub fn is_stopped(&self) -> bool {
        self.inner.stopped.load(Ordering::Acquire)
    }

    /// Blocks until stopped or `timeout` passed; returns whether stopped.
    pub fn wait_timeout(&self, timeout: Duration) -> bool {
        let s = &*self.inner;
        let guard = s.lock.lock().unwrap_or_else(|p| p.into_inner());
        let _guard =
            s.cv.wait_timeout_while(guard, timeout, |()| !s.stopped.load(Ordering::Acquire))
                .unwrap_or_else(|p| p.into_inner());
        self.is_stopped()
    }

    pub(crate) fn downgrade(&self) -> std::sync::Weak<StopState> {
        Arc::downgrade(&self.inner)
    }

    pub(crate) fn from_inner(inner: Arc<StopState>) -> Self {
        Self { inner }
    }
}

/// Nanoseconds since the Unix epoch on the system (wall-clock) time, as HORUS stamps messages
/// (`horus::timestamp_now()`); 0 before the epoch, `u64::MAX` past year 2554.
pub fn timestamp_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}
