//! A context's shutdown, as rclcpp's (`rclcpp::Context::shutdown`, `rclcpp::ok`,
//! `Context::on_shutdown`, `Context::sleep_for` woken by it): once shut down — by the program or
//! by a signal (see [`signal_handler`](crate::signal_handler)) — a context stays so; waiters wake,
//! callbacks run once. The participant and everything on it keep working until dropped (as
//! rclcpp's `rmw_shutdown` leaves deleting the participant to `rmw_context_fini`), so that a
//! program can still say its last words (a HORUS node's `shutdown` may publish).

use std::future::Future;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::task::{Poll, Waker};
use std::time::{Duration, Instant};

use super::Context;
use crate::signal_handler::SignalHandlerOptions;

/// A callback run once when its context is shut down, given the reason.
type Callback = Box<dyn FnOnce(&str) + Send>;

/// The shutdown state of one context.
pub(crate) struct Shutdown {
    /// The signals that shut this context down.
    signals: SignalHandlerOptions,
    /// Whether the program looks at this context's shutdown (see [`Context::ok`]).
    watched: AtomicBool,
    state: Mutex<State>,
    changed: Condvar,
}

#[derive(Default)]
struct State {
    /// `Some` once shut down.
    reason: Option<String>,
    callbacks: Vec<Callback>,
    /// The wakers of pending [`ShutdownFuture`]s, by future.
    wakers: Vec<(u64, Waker)>,
    next_future: u64,
}

impl Shutdown {
    pub(crate) fn new(signals: SignalHandlerOptions) -> Self {
        Self {
            signals,
            watched: AtomicBool::new(false),
            state: Mutex::new(State::default()),
            changed: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub(crate) fn signals(&self) -> SignalHandlerOptions {
        self.signals
    }

    fn watch(&self) {
        self.watched.store(true, Ordering::SeqCst);
    }

    pub(crate) fn is_watched(&self) -> bool {
        self.watched.load(Ordering::SeqCst)
    }

    fn reason(&self) -> Option<String> {
        self.lock().reason.clone()
    }

    /// Shuts down: wakes every waiter, then runs the callbacks here (a panicking one is logged).
    /// `false` if already shut down.
    pub(crate) fn shutdown(&self, reason: &str) -> bool {
        let (callbacks, wakers) = {
            let mut state = self.lock();
            if state.reason.is_some() {
                return false;
            }
            state.reason = Some(reason.to_owned());
            (
                std::mem::take(&mut state.callbacks),
                std::mem::take(&mut state.wakers),
            )
        };
        tracing::debug!(reason, "context shut down");
        self.changed.notify_all();
        for (_, waker) in wakers {
            waker.wake();
        }
        for callback in callbacks {
            if catch_unwind(AssertUnwindSafe(|| callback(reason))).is_err() {
                tracing::error!("an on_shutdown callback panicked");
            }
        }
        true
    }

    /// Waits until shut down, at most `timeout` (`None`: no limit); whether it is.
    fn wait(&self, timeout: Option<Duration>) -> bool {
        let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
        let mut state = self.lock();
        while state.reason.is_none() {
            state = match deadline {
                None => self.changed.wait(state).unwrap_or_else(|p| p.into_inner()),
                Some(deadline) => {
                    let left = deadline.saturating_duration_since(Instant::now());
                    if left.is_zero() {
                        return false;
                    }
                    self.changed
                        .wait_timeout(state, left)
                        .unwrap_or_else(|p| p.into_inner())
                        .0
                }
            };
        }
        true
    }

    fn on_shutdown(&self, callback: Callback) {
        let mut state = self.lock();
        match state.reason.clone() {
            None => state.callbacks.push(callback),
            Some(reason) => {
                drop(state);
                if catch_unwind(AssertUnwindSafe(|| callback(&reason))).is_err() {
                    tracing::error!("an on_shutdown callback panicked");
                }
            }
        }
    }
}

impl Context {
    /// Whether the context is still up, i.e. not [shut down](Self::shutdown) (`rclcpp::ok`).
    ///
    /// Asking marks the context as watched: the program looks at its shutdown, so a SIGINT or
    /// SIGTERM only shuts it down and leaves the rest to the program (see
    /// [`signal_handler`](crate::signal_handler)), e.g. `while context.ok() { … }`.
    pub fn ok(&self) -> bool {
        let shutdown = &self.inner.shutdown;
        shutdown.watch();
        shutdown.lock().reason.is_none()
    }

    /// Shuts the context down (`rclcpp::shutdown`): [`ok`](Self::ok) turns false, waiters wake,
    /// [`on_shutdown`](Self::on_shutdown) callbacks run on this thread. Nodes and endpoints keep
    /// working until dropped; the participant leaves the graph when the context's last clone is
    /// dropped. `false` if it was already shut down.
    pub fn shutdown(&self, reason: &str) -> bool {
        self.inner.shutdown.shutdown(reason)
    }

    /// Why the context was shut down (e.g. `signal handler: SIGINT`), if it was.
    pub fn shutdown_reason(&self) -> Option<String> {
        self.inner.shutdown.reason()
    }

    /// Blocks until the context is shut down — by [`shutdown`](Self::shutdown), or by SIGINT or
    /// SIGTERM — at most `timeout` (`None`: no limit); whether it is shut down. What a program
    /// that serves until stopped blocks on (as an rclcpp program in `rclcpp::spin`). Marks the
    /// context as watched (see [`ok`](Self::ok)).
    pub fn wait_for_shutdown(&self, timeout: impl Into<Option<Duration>>) -> bool {
        let shutdown = &self.inner.shutdown;
        shutdown.watch();
        shutdown.wait(timeout.into())
    }

    /// A future that resolves when the context is shut down (runtime-agnostic: woken by the
    /// shutdown itself). Marks the context as watched from now on (see [`ok`](Self::ok)).
    pub fn wait_for_shutdown_async(&self) -> ShutdownFuture {
        let shutdown = Arc::clone(&self.inner.shutdown);
        shutdown.watch();
        let id = {
            let mut state = shutdown.lock();
            state.next_future += 1;
            state.next_future
        };
        ShutdownFuture { shutdown, id }
    }

    /// Runs `callback` once, with the reason, when the context is shut down (on the thread that
    /// shuts it down: the signal thread for a signal; keep it short), or right away if it is
    /// already. A panic in it is logged. Marks the context as watched (see [`ok`](Self::ok)).
    pub fn on_shutdown(&self, callback: impl FnOnce(&str) + Send + 'static) {
        let shutdown = &self.inner.shutdown;
        shutdown.watch();
        shutdown.on_shutdown(Box::new(callback));
    }

    /// The signals that shut this context down (see
    /// [`ContextBuilder::signal_handler`](crate::ContextBuilder::signal_handler)).
    pub fn signal_handler(&self) -> SignalHandlerOptions {
        self.inner.shutdown.signals()
    }
}

/// Resolves when its context is shut down (see [`Context::wait_for_shutdown_async`]). Does not
/// keep the context's participant alive.
#[must_use = "futures do nothing unless awaited"]
pub struct ShutdownFuture {
    shutdown: Arc<Shutdown>,
    id: u64,
}

impl std::fmt::Debug for ShutdownFuture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShutdownFuture")
            .field("id", &self.id)
            .finish()
    }
}

impl Future for ShutdownFuture {
    type Output = ();

    fn poll(self: Pin<&mut Self>, cx: &mut std::task::Context<'_>) -> Poll<()> {
        let mut state = self.shutdown.lock();
        if state.reason.is_some() {
            return Poll::Ready(());
        }
        let waker = cx.waker();
        match state.wakers.iter_mut().find(|(id, _)| *id == self.id) {
            Some((_, w)) => w.clone_from(waker),
            None => state.wakers.push((self.id, waker.clone())),
        }
        Poll::Pending
    }
}

impl Drop for ShutdownFuture {
    fn drop(&mut self) {
        self.shutdown.lock().wakers.retain(|(id, _)| *id != self.id);
    }
}
