//! [`Signal`]: waiting for readers' data without a Cyclone waitset.
//!
//! A Cyclone waitset is woken by a read condition from inside the reader history cache's
//! lock, with a condition-variable broadcast under the waitset's own lock
//! (`dds_rhc_default.c`: `update_conditions_locked` → `dds_entity_status_signal` →
//! `dds_waitset_observer`). On one CPU the woken thread preempts the writer and blocks at once
//! on each of those locks in turn: three thread switches per hand-over instead of one
//! (`perf record -e sched:sched_switch` on the `service_roundtrip` bench). A [`Reader`]'s
//! DATA_AVAILABLE listener runs after the cache's lock is released (`dds_reader_data_available_cb`)
//! and raises the signals the reader is attached to: one push under our own lock, released
//! before the waiting thread is notified.
//!
//! [`Reader`]: crate::Reader

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, Weak};
use std::time::{Duration, Instant};

use crate::sys::lock;

/// Wakes the waiting thread when a reader attached to it may have data, or when
/// [`wake`](Self::wake) is called. Edge-triggered: a reader is reported once per arrival (or
/// burst of arrivals) after the previous report; take from it until it is empty. One thread
/// waits at a time: a second caller of [`wait`](Self::wait) blocks until the first returns.
#[derive(Debug, Default)]
pub struct Signal {
    /// Held for the whole of a wait.
    waiting: Mutex<()>,
    state: Mutex<State>,
    cond: Condvar,
}

#[derive(Debug, Default)]
struct State {
    /// The attachments raised since the last wait, each at most once (see `Notice::queued`).
    ready: Vec<Arc<Notice>>,
    woken: bool,
}

/// One reader attached to one signal under a token.
#[derive(Debug)]
pub(crate) struct Notice {
    /// Weak: the signal's `ready` list holds notices, which must not keep it alive.
    signal: Weak<Signal>,
    token: usize,
    /// Set while the notice is in the signal's `ready` list: so the list holds each attached
    /// reader once at most, and a burst of samples costs one push.
    queued: AtomicBool,
}

impl Notice {
    pub(crate) fn new(signal: &Arc<Signal>, token: usize) -> Arc<Self> {
        Arc::new(Self {
            signal: Arc::downgrade(signal),
            token,
            queued: AtomicBool::new(false),
        })
    }

    /// Reports the reader to its signal (a no-op while an earlier report is not yet taken).
    /// Called from Cyclone's threads: never blocks for long, never panics.
    pub(crate) fn raise(self: &Arc<Self>) {
        // AcqRel: the waiter's swap back to false reads this write, so what the raising thread
        // did before (storing the sample) happens before the waiter's take.
        if self.queued.swap(true, Ordering::AcqRel) {
            return;
        }
        let Some(signal) = self.signal.upgrade() else {
            return; // nobody waits any more
        };
        lock(&signal.state).ready.push(Arc::clone(self));
        signal.cond.notify_one();
    }
}

impl Signal {
    /// A new signal with nothing attached.
    pub fn new() -> Arc<Self> {
        Arc::default()
    }

    /// Makes the current or next [`wait`](Self::wait) return, from any thread.
    pub fn wake(&self) {
        lock(&self.state).woken = true;
        self.cond.notify_one();
    }

    /// Blocks until an attached reader may have data or [`wake`](Self::wake) was called, at
    /// most `timeout` (`None`: no limit). Puts the tokens of the readers that may have data in
    /// `ready` (cleared first); returns whether anything was signalled (a wake or a reader).
    pub fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool {
        ready.clear();
        let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
        let _waiting = lock(&self.waiting);
        let mut state = lock(&self.state);
        while state.ready.is_empty() && !state.woken {
            state = match (timeout, deadline) {
                (None, _) | (Some(_), None) => {
                    self.cond.wait(state).unwrap_or_else(|p| p.into_inner())
                }
                (Some(_), Some(deadline)) => {
                    let left = deadline.saturating_duration_since(Instant::now());
                    if left.is_zero() {
                        break;
                    }
                    self.cond
                        .wait_timeout(state, left)
                        .unwrap_or_else(|p| p.into_inner())
                        .0
                }
            };
        }
        let woken = std::mem::take(&mut state.woken);
        for notice in state.ready.drain(..) {
            // Cleared before the caller takes: a sample stored after this raises it again.
            notice.queued.swap(false, Ordering::AcqRel);
            ready.push(notice.token);
        }
        woken || !ready.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_raised_notice_is_reported_once_until_taken_then_again() {
        let signal = Signal::new();
        let a = Notice::new(&signal, 7);
        let b = Notice::new(&signal, 9);
        a.raise();
        a.raise();
        b.raise();
        let mut ready = Vec::new();
        assert!(signal.wait(Some(Duration::ZERO), &mut ready));
        assert_eq!(ready, [7, 9]);
        assert!(!signal.wait(Some(Duration::ZERO), &mut ready));
        assert!(ready.is_empty());
        a.raise();
        assert!(signal.wait(None, &mut ready));
        assert_eq!(ready, [7]);
    }

    #[test]
    fn wake_ends_a_wait_in_another_thread_with_nothing_ready() {
        let signal = Signal::new();
        let waiting = {
            let signal = Arc::clone(&signal);
            std::thread::spawn(move || {
                let mut ready = vec![1];
                let signalled = signal.wait(None, &mut ready);
                (signalled, ready)
            })
        };
        signal.wake();
        let (signalled, ready) = waiting.join().expect("waiter");
        assert!(signalled);
        assert!(ready.is_empty());
    }

    #[test]
    fn a_raise_from_another_thread_ends_a_wait_without_limit() {
        let signal = Signal::new();
        let notice = Notice::new(&signal, 3);
        let raiser = std::thread::spawn(move || notice.raise());
        let mut ready = Vec::new();
        assert!(signal.wait(None, &mut ready));
        assert_eq!(ready, [3]);
        raiser.join().expect("raiser");
    }
}
