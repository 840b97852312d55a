//! Waiting on rustdds readers without polling: a mio 1 poll per reader (or one for a wait set)
//! and a waker that ends a wait from any thread. The Cyclone side is `horus_ros_rmw_cyclone`'s
//! `Signal`.
//!
//! rustdds' mio 1 sources are drained by take/try_recv, so edge-triggered waking works (its
//! mio 0.6 readiness fires only once: it is never drained).

use std::sync::{Arc, Mutex};
use std::time::Duration;

use rustdds::mio1 as mio;

/// Ends the current or next wait of the poll it was made for, from any thread.
#[derive(Clone)]
pub(crate) struct Waker(Arc<mio::Waker>);

impl Waker {
    /// A waker of `poll`, reported under `token`.
    pub(crate) fn new(poll: &mio::Poll, token: usize) -> std::io::Result<Self> {
        mio::Waker::new(poll.registry(), mio::Token(token)).map(|w| Self(Arc::new(w)))
    }

    /// Wakes the waiting thread (or makes its next wait return at once).
    pub(crate) fn wake(&self) -> std::io::Result<()> {
        self.0.wake()
    }
}

/// Waits on `poll` until it signals or `timeout` passes (no limit: `None`); returns whether it
/// signalled.
pub(crate) fn wait_on(poll: &mut mio::Poll, timeout: Option<Duration>) -> bool {
    let mut events = mio::Events::with_capacity(4);
    match poll.poll(&mut events, timeout) {
        Ok(()) => !events.is_empty(),
        Err(e) => {
            tracing::debug!("poll failed: {e}");
            false
        }
    }
}

/// One poll for many readers' data (the rustdds side of `WaitSet`); one thread waits at a time.
pub(crate) struct Waiter {
    poll: Mutex<(mio::Poll, mio::Events)>,
    /// Registers readers while another thread waits in `poll`.
    pub(crate) registry: mio::Registry,
    /// The token of the waiter's own waker.
    wake: usize,
}

impl Waiter {
    /// An empty waiter, and the waker that ends its waits (reported under `wake`, which
    /// [`wait`](Self::wait) leaves out of the ready keys).
    pub(crate) fn new(wake: usize) -> std::io::Result<(Self, Waker)> {
        let poll = mio::Poll::new()?;
        let registry = poll.registry().try_clone()?;
        let waker = Waker::new(&poll, wake)?;
        Ok((
            Self {
                poll: Mutex::new((poll, mio::Events::with_capacity(64))),
                registry,
                wake,
            },
            waker,
        ))
    }

    /// Waits at most `timeout` (`None`: no limit); puts the tokens of the readers that signalled
    /// in `ready` and returns whether anything (the waker included) did.
    pub(crate) fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool {
        let mut guard = self.poll.lock().unwrap_or_else(|p| p.into_inner());
        let (poll, events) = &mut *guard;
        if let Err(e) = poll.poll(events, timeout) {
            tracing::debug!("wait set: poll failed: {e}");
            return false;
        }
        let mut signalled = false;
        for event in events.iter() {
            signalled = true;
            if event.token().0 != self.wake {
                ready.push(event.token().0);
            }
        }
        signalled
    }
}
