//! [`GraphSubscription`]: the typed changes of a [`Graph`](crate::Graph) as a bounded queue.
//!
//! Overflow policy (as tokio's broadcast channel): a subscriber that falls more than
//! [`SUBSCRIPTION_CAPACITY`] events behind loses the oldest ones; its next receive reports how
//! many with [`RecvError::Lagged`], then goes on with the oldest events still held. The graph's
//! thread never waits for a subscriber, and a slow one never holds more than the capacity.

use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::GraphEvent;

/// Most events a [`GraphSubscription`] holds before it drops the oldest.
pub const SUBSCRIPTION_CAPACITY: usize = 4096;

/// Why [`GraphSubscription::recv`] returned no event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RecvError {
    /// The subscriber fell behind: this many events (the oldest) were dropped. Receiving goes on
    /// with the oldest event still held; re-read the graph to catch up on what was missed.
    #[error("fell behind the graph: {0} events were dropped")]
    Lagged(u64),
    /// No event came within the timeout.
    #[error("no graph event within the timeout")]
    Timeout,
    /// The graph was dropped or the subscription [`interrupt`](SubscriptionInterrupter::interrupt)ed,
    /// and every event held was received.
    #[error("the graph subscription is closed")]
    Closed,
}

#[derive(Default)]
struct Inner {
    events: VecDeque<GraphEvent>,
    lagged: u64,
    closed: bool,
}

/// The queue shared by a subscription and the graph (which holds it weakly).
#[derive(Default)]
pub(crate) struct EventQueue {
    inner: Mutex<Inner>,
    ready: Condvar,
}

impl EventQueue {
    fn lock(&self) -> MutexGuard<'_, Inner> {
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Appends `events`, dropping the oldest beyond the capacity, and wakes the receiver.
    pub(crate) fn push(&self, events: &[GraphEvent]) {
        let mut inner = self.lock();
        if inner.closed {
            return;
        }
        inner.events.extend(events.iter().cloned());
        let excess = inner.events.len().saturating_sub(SUBSCRIPTION_CAPACITY);
        if excess > 0 {
            inner.events.drain(..excess);
            inner.lagged += excess as u64;
        }
        drop(inner);
        self.ready.notify_all();
    }

    /// Ends the subscription: receiving returns what is held, then [`RecvError::Closed`].
    pub(crate) fn close(&self) {
        self.lock().closed = true;
        self.ready.notify_all();
    }
}

/// Every change of a [`Graph`](crate::Graph) from the moment of
/// [`subscribe`](crate::Graph::subscribe), in order, in a bounded queue (see the module's
/// overflow policy). Dropping it unsubscribes.
#[must_use = "a subscription does nothing unless its events are received"]
pub struct GraphSubscription {
    queue: Arc<EventQueue>,
}

impl std::fmt::Debug for GraphSubscription {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GraphSubscription")
            .field("held", &self.queue.lock().events.len())
            .finish()
    }
}

impl GraphSubscription {
    pub(crate) fn new() -> (Self, Arc<EventQueue>) {
        let queue = Arc::new(EventQueue::default());
        (
            Self {
                queue: Arc::clone(&queue),
            },
            queue,
        )
    }

    /// The next event, waiting for it at most `timeout` (`None`: until one comes or the
    /// subscription is closed).
    pub fn recv(&self, timeout: Option<Duration>) -> Result<GraphEvent, RecvError> {
        let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
        let mut inner = self.queue.lock();
        loop {
            if let Some(result) = Self::take(&mut inner) {
                return result;
            }
            inner = match deadline {
                None => self
                    .queue
                    .ready
                    .wait(inner)
                    .unwrap_or_else(|p| p.into_inner()),
                Some(deadline) => {
                    let now = Instant::now();
                    if now >= deadline {
                        return Err(RecvError::Timeout);
                    }
                    self.queue
                        .ready
                        .wait_timeout(inner, deadline - now)
                        .map(|(guard, _)| guard)
                        .unwrap_or_else(|p| p.into_inner().0)
                }
            };
        }
    }

    /// The next event if one is held (never waits): `Err(Timeout)` when none is.
    pub fn try_recv(&self) -> Result<GraphEvent, RecvError> {
        Self::take(&mut self.queue.lock()).unwrap_or(Err(RecvError::Timeout))
    }

    /// The events held now, oldest first, without waiting (a lag report is skipped: compare
    /// with [`len`](Self::len) or use [`try_recv`](Self::try_recv) to see it).
    pub fn try_iter(&self) -> impl Iterator<Item = GraphEvent> + '_ {
        std::iter::from_fn(move || loop {
            match self.try_recv() {
                Ok(event) => return Some(event),
                Err(RecvError::Lagged(_)) => continue,
                Err(_) => return None,
            }
        })
    }

    /// How many events are held, not yet received.
    pub fn len(&self) -> usize {
        self.queue.lock().events.len()
    }

    /// Whether no event is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A handle that closes this subscription from another thread (e.g. a Ctrl+C handler), so
    /// that a waiting [`recv`](Self::recv) returns.
    pub fn interrupter(&self) -> SubscriptionInterrupter {
        SubscriptionInterrupter {
            queue: Arc::downgrade(&self.queue),
        }
    }

    fn take(inner: &mut Inner) -> Option<Result<GraphEvent, RecvError>> {
        if inner.lagged > 0 {
            return Some(Err(RecvError::Lagged(std::mem::take(&mut inner.lagged))));
        }
        if let Some(event) = inner.events.pop_front() {
            return Some(Ok(event));
        }
        inner.closed.then_some(Err(RecvError::Closed))
    }
}

impl Drop for GraphSubscription {
    fn drop(&mut self) {
        self.queue.close();
    }
}

/// Closes a [`GraphSubscription`] from any thread (see
/// [`GraphSubscription::interrupter`]).
#[derive(Clone, Debug)]
pub struct SubscriptionInterrupter {
    queue: std::sync::Weak<EventQueue>,
}

impl SubscriptionInterrupter {
    /// Closes the subscription: its receiver gets what is held, then [`RecvError::Closed`].
    pub fn interrupt(&self) {
        if let Some(queue) = self.queue.upgrade() {
            queue.close();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn event(i: usize) -> GraphEvent {
        GraphEvent::NodeAdded {
            name: format!("n{i}"),
            namespace: "/".to_owned(),
        }
    }

    #[test]
    fn a_slow_subscriber_holds_at_most_the_capacity_and_learns_how_many_it_missed() {
        let (sub, queue) = GraphSubscription::new();
        let events: Vec<_> = (0..SUBSCRIPTION_CAPACITY + 10).map(event).collect();
        queue.push(&events[..100]);
        queue.push(&events[100..]);
        assert_eq!(sub.len(), SUBSCRIPTION_CAPACITY);
        assert_eq!(sub.try_recv(), Err(RecvError::Lagged(10)));
        assert_eq!(
            sub.try_recv(),
            Ok(event(10)),
            "the oldest still held comes next"
        );
        assert_eq!(sub.len(), SUBSCRIPTION_CAPACITY - 1);
    }

    #[test]
    fn recv_times_out_then_gets_what_another_thread_pushes() {
        let (sub, queue) = GraphSubscription::new();
        assert_eq!(
            sub.recv(Some(Duration::from_millis(1))),
            Err(RecvError::Timeout)
        );
        let pusher = std::thread::spawn(move || queue.push(&[event(1)]));
        assert_eq!(sub.recv(None), Ok(event(1)));
        pusher.join().expect("pusher");
    }

    #[test]
    fn an_interrupted_subscription_gives_what_it_holds_then_closed() {
        let (sub, queue) = GraphSubscription::new();
        queue.push(&[event(1)]);
        let interrupter = sub.interrupter();
        let waiter = std::thread::spawn(move || {
            let first = sub.recv(None);
            let second = sub.recv(None);
            (first, second)
        });
        interrupter.interrupt();
        let (first, second) = waiter.join().expect("waiter");
        assert_eq!(first, Ok(event(1)));
        assert_eq!(second, Err(RecvError::Closed));
        queue.push(&[event(2)]);
    }
}
