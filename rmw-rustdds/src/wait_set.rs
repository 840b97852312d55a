//! Waiting on rustdds readers without polling: a mio 1 poll per reader (or one for a wait set)
//! and a waker that ends a wait from any thread. The Cyclone side is `cyclone/wait_set.rs`.
//!
//! rustdds' mio 1 sources are drained by take/try_recv, so edge-triggered waking works (its
//! mio 0.6 readiness fires only once: it is never drained).

use std::sync::{Arc, Mutex};
use std::time::Duration;

use rustdds::mio1 as mio;

use crate::contract::{WaitSetBackend, Wake};

/// The token of a wait set's own waker (the context's wait set refuses it as a reader key).
const WAKE: usize = usize::MAX;

/// Ends the current or next wait of the poll it was made for, from any thread.
#[derive(Clone)]
pub(crate) struct Waker(Arc<mio::Waker>);

impl Waker {
    /// A waker of `poll`, reported under `token`.
    pub(crate) fn new(poll: &mio::Poll, token: usize) -> std::io::Result<Self> {
        mio::Waker::new(poll.registry(), mio::Token(token)).map(|w| Self(Arc::new(w)))
    }
}

impl Wake for Waker {
    fn wake(&self) {
        if let Err(e) = self.0.wake() {
            tracing::debug!("could not wake a poll: {e}");
        }
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

/// One poll for many readers' data (the rustdds wait set); one thread waits at a time.
pub(crate) struct WaitSet {
    poll: Mutex<(mio::Poll, mio::Events)>,
    /// Registers readers while another thread waits in `poll`.
    pub(crate) registry: mio::Registry,
    waker: Waker,
}

impl WaitSet {
    /// An empty set, with the waker that ends its waits.
    pub(crate) fn new() -> std::io::Result<Self> {
        let poll = mio::Poll::new()?;
        let registry = poll.registry().try_clone()?;
        let waker = Waker::new(&poll, WAKE)?;
        Ok(Self {
            poll: Mutex::new((poll, mio::Events::with_capacity(64))),
            registry,
            waker,
        })
    }
}

impl WaitSetBackend for WaitSet {
    fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool {
        let mut guard = self.poll.lock().unwrap_or_else(|p| p.into_inner());
        let (poll, events) = &mut *guard;
        if let Err(e) = poll.poll(events, timeout) {
            tracing::debug!("wait set: poll failed: {e}");
            return false;
        }
        let mut signalled = false;
        for event in events.iter() {
            signalled = true;
            if event.token().0 != WAKE {
                ready.push(event.token().0);
            }
        }
        signalled
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::new(self.waker.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
