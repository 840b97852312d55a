//! The graph's changes as bounded queues, one per consumer: [`GraphSubscription`] for a
//! blocking consumer, and (feature `tokio`) [`GraphEvents`](crate::GraphEvents) for a task —
//! both over a [`DropOldestQueue`] fed by the graph's thread through one [`Subscribers`] list.
//!
//! Overflow policy ([`horus_ros_rmw::queue`]): a subscriber that falls more than its capacity
//! behind loses the oldest events; its next receive reports how many
//! ([`RecvError::Lagged`]), then goes on with the oldest events still held. The graph's thread
//! never waits for a subscriber, and a slow one never holds more than its capacity.

use std::sync::{Arc, Condvar, Mutex, MutexGuard, Weak};
use std::task::{Context as TaskContext, Poll, Wake, Waker};
use std::time::{Duration, Instant};

use horus_ros_rmw::queue::{DropOldestQueue, Lagged};

use crate::GraphEvent;

/// Most events a [`GraphSubscription`] holds before it drops the oldest.
pub const SUBSCRIPTION_CAPACITY: usize = 4096;

/// The queues of the live subscribers of one graph (each held weakly: a dropped subscriber is
/// forgotten at the next change).
#[derive(Default)]
pub(crate) struct Subscribers {
    queues: Mutex<Vec<Weak<DropOldestQueue<GraphEvent>>>>,
    /// The consumers to wake for what was delivered, once the graph's lock is released.
    to_wake: Mutex<Vec<Waker>>,
}

impl Subscribers {
    fn lock(&self) -> MutexGuard<'_, Vec<Weak<DropOldestQueue<GraphEvent>>>> {
        self.queues.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// A new subscriber's queue, holding at most `capacity` events.
    pub(crate) fn add(&self, capacity: usize) -> Arc<DropOldestQueue<GraphEvent>> {
        let queue = Arc::new(DropOldestQueue::new(capacity));
        self.lock().push(Arc::downgrade(&queue));
        queue
    }

    /// Gives `events` to every live subscriber (called by the graph's thread while the change
    /// is applied, so that whoever sees the change in the graph finds its events queued);
    /// their consumers are woken by [`wake`](Self::wake).
    pub(crate) fn deliver(&self, events: &[GraphEvent]) {
        if events.is_empty() {
            return;
        }
        let mut queues = self.lock();
        queues.retain(|q| q.strong_count() > 0);
        let wakers: Vec<Waker> = queues
            .iter()
            .filter_map(Weak::upgrade)
            .filter_map(|queue| queue.push_all_deferred(events.iter().cloned()))
            .collect();
        drop(queues);
        self.to_wake
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .extend(wakers);
    }

    /// Wakes the consumers of what [`deliver`](Self::deliver) gave (called by the graph's
    /// thread with no lock of the graph held: a waker may run anything).
    pub(crate) fn wake(&self) {
        let wakers = std::mem::take(&mut *self.to_wake.lock().unwrap_or_else(|p| p.into_inner()));
        for waker in wakers {
            waker.wake();
        }
    }

    /// Ends every subscription (the graph is going away).
    pub(crate) fn close_all(&self) {
        for queue in self.lock().drain(..).filter_map(|q| q.upgrade()) {
            queue.close();
        }
    }
}

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

/// Wakes a thread blocked in [`GraphSubscription::recv`] (the queue's consumer waker).
#[derive(Default)]
struct Notify {
    woken: Mutex<bool>,
    ready: Condvar,
}

impl Wake for Notify {
    fn wake(self: Arc<Self>) {
        self.wake_by_ref();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        *self.woken.lock().unwrap_or_else(|p| p.into_inner()) = true;
        self.ready.notify_all();
    }
}

impl Notify {
    /// Waits until woken (clearing it), at most until `deadline`; whether it was woken.
    fn wait(&self, deadline: Option<Instant>) -> bool {
        let mut woken = self.woken.lock().unwrap_or_else(|p| p.into_inner());
        while !*woken {
            woken = match deadline {
                None => self.ready.wait(woken).unwrap_or_else(|p| p.into_inner()),
                Some(deadline) => {
                    let now = Instant::now();
                    if now >= deadline {
                        return false;
                    }
                    self.ready
                        .wait_timeout(woken, deadline - now)
                        .map(|(guard, _)| guard)
                        .unwrap_or_else(|p| p.into_inner().0)
                }
            };
        }
        *woken = false;
        true
    }
}

/// Every change of a [`Graph`](crate::Graph) from the moment of
/// [`subscribe`](crate::Graph::subscribe), in order, in a bounded queue (see the module's
/// overflow policy). Dropping it unsubscribes.
#[must_use = "a subscription does nothing unless its events are received"]
pub struct GraphSubscription {
    queue: Arc<DropOldestQueue<GraphEvent>>,
    notify: Arc<Notify>,
}

impl std::fmt::Debug for GraphSubscription {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GraphSubscription")
            .field("held", &self.queue.len())
            .finish()
    }
}

impl GraphSubscription {
    pub(crate) fn new(queue: Arc<DropOldestQueue<GraphEvent>>) -> Self {
        Self {
            queue,
            notify: Arc::default(),
        }
    }

    /// The next event, waiting for it at most `timeout` (`None`: until one comes or the
    /// subscription is closed).
    pub fn recv(&self, timeout: Option<Duration>) -> Result<GraphEvent, RecvError> {
        let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
        let waker = Waker::from(Arc::clone(&self.notify));
        let mut cx = TaskContext::from_waker(&waker);
        loop {
            // Registers the waker under the queue's lock when nothing is held: a later push
            // wakes `notify`.
            match self.queue.poll_next(&mut cx) {
                Poll::Ready(next) => return Self::received(next),
                Poll::Pending => {
                    if !self.notify.wait(deadline) {
                        return Err(RecvError::Timeout);
                    }
                }
            }
        }
    }

    /// The next event if one is held (never waits): `Err(Timeout)` when none is.
    pub fn try_recv(&self) -> Result<GraphEvent, RecvError> {
        match self.queue.try_next() {
            Some(next) => Self::received(Some(next)),
            None if self.queue.is_closed() => Err(RecvError::Closed),
            None => Err(RecvError::Timeout),
        }
    }

    fn received(next: Option<Result<GraphEvent, Lagged>>) -> Result<GraphEvent, RecvError> {
        match next {
            Some(Ok(event)) => Ok(event),
            Some(Err(Lagged(missed))) => Err(RecvError::Lagged(missed)),
            None => Err(RecvError::Closed),
        }
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
        self.queue.len()
    }

    /// Whether no event is held.
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// A handle that closes this subscription from another thread (e.g. a Ctrl+C handler), so
    /// that a waiting [`recv`](Self::recv) returns.
    pub fn interrupter(&self) -> SubscriptionInterrupter {
        SubscriptionInterrupter {
            queue: Arc::downgrade(&self.queue),
        }
    }
}

/// Closes a [`GraphSubscription`] from any thread (see
/// [`GraphSubscription::interrupter`]).
#[derive(Clone, Debug)]
pub struct SubscriptionInterrupter {
    queue: Weak<DropOldestQueue<GraphEvent>>,
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
        let queue = Arc::new(DropOldestQueue::new(SUBSCRIPTION_CAPACITY));
        let sub = GraphSubscription::new(Arc::clone(&queue));
        let events: Vec<_> = (0..SUBSCRIPTION_CAPACITY + 10).map(event).collect();
        queue.push_all(events[..100].iter().cloned());
        queue.push_all(events[100..].iter().cloned());
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
        let queue = Arc::new(DropOldestQueue::new(SUBSCRIPTION_CAPACITY));
        let sub = GraphSubscription::new(Arc::clone(&queue));
        assert_eq!(
            sub.recv(Some(Duration::from_millis(1))),
            Err(RecvError::Timeout)
        );
        let pusher = std::thread::spawn(move || queue.push(event(1)));
        assert_eq!(sub.recv(None), Ok(event(1)));
        pusher.join().expect("pusher");
    }

    #[test]
    fn an_interrupted_subscription_gives_what_it_holds_then_closed() {
        let queue = Arc::new(DropOldestQueue::new(SUBSCRIPTION_CAPACITY));
        let sub = GraphSubscription::new(Arc::clone(&queue));
        queue.push(event(1));
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
        queue.push(event(2));
    }
}
