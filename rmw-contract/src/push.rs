//! Waiting without polling for backends whose middleware pushes (calls back on threads of its
//! own, as Zenoh does, or an in-process bus): a [`Signal`] (a flag and a condition variable)
//! for a reader or a feed, raised from those threads; a [`WaitSet`] that collects the keys of
//! the attached readers that got data. Written once here for every such backend; the DDS
//! backends wait on their middleware's own primitives instead (mio for rustdds, a Cyclone DDS
//! waitset).

use std::collections::BTreeSet;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::{WaitSetBackend, Wake};

/// Locks a mutex whose data stays consistent even if a holder panicked.
pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Waits on `cv` until `done` holds, at most `timeout` (`None`: no limit); whether it held.
fn wait_on<'a, T>(
    cv: &Condvar,
    mut guard: MutexGuard<'a, T>,
    timeout: Option<Duration>,
    mut done: impl FnMut(&mut T) -> bool,
) -> (MutexGuard<'a, T>, bool) {
    // A timeout too long to represent waits without limit.
    let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
    loop {
        if done(&mut guard) {
            return (guard, true);
        }
        guard = match deadline {
            None => cv.wait(guard).unwrap_or_else(|p| p.into_inner()),
            Some(d) => match d.checked_duration_since(Instant::now()) {
                Some(left) if !left.is_zero() => {
                    cv.wait_timeout(guard, left)
                        .unwrap_or_else(|p| p.into_inner())
                        .0
                }
                _ => return (guard, false),
            },
        };
    }
}

/// A flag raised by [`Wake::wake`] and lowered by the wait that sees it (edge-triggered).
#[derive(Default)]
pub struct Signal {
    raised: Mutex<bool>,
    cv: Condvar,
}

impl Signal {
    /// Waits until raised (and lowers it), at most `timeout`; whether it was raised.
    pub fn wait(&self, timeout: Option<Duration>) -> bool {
        let guard = lock(&self.raised);
        let (_guard, raised) = wait_on(&self.cv, guard, timeout, std::mem::take);
        raised
    }
}

impl Wake for Signal {
    fn wake(&self) {
        *lock(&self.raised) = true;
        self.cv.notify_all();
    }
}

/// What a wait set shares with its readers: the keys ready, and whether its waker was woken.
#[derive(Default)]
pub struct SetState {
    ready: Mutex<(BTreeSet<usize>, bool)>,
    cv: Condvar,
}

impl SetState {
    /// Marks `key` ready (`None`: the set's own waker), waking the waiter.
    pub fn mark(&self, key: Option<usize>) {
        let mut ready = lock(&self.ready);
        match key {
            Some(key) => {
                ready.0.insert(key);
            }
            None => ready.1 = true,
        }
        self.cv.notify_all();
    }
}

impl Wake for SetState {
    fn wake(&self) {
        self.mark(None);
    }
}

/// Waits on many readers' data at once.
#[derive(Default)]
pub struct WaitSet {
    /// What the readers attached to it mark.
    pub shared: Arc<SetState>,
}

impl WaitSetBackend for WaitSet {
    fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool {
        let guard = lock(&self.shared.ready);
        let (mut guard, signalled) =
            wait_on(&self.shared.cv, guard, timeout, |r| !r.0.is_empty() || r.1);
        ready.extend(std::mem::take(&mut guard.0));
        guard.1 = false;
        signalled
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::clone(&self.shared) as Arc<dyn Wake>
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
