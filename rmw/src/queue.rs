//! [`DropOldestQueue`]: the bounded buffer behind every stream of items from the network (a
//! subscription's messages, the graph's events), for blocking and async consumers alike.
//!
//! Overflow policy: the buffer holds at most its capacity; when an item arrives while it is
//! full, the **oldest** buffered item is dropped (as a KEEP_LAST history does) and counted. The
//! consumer learns of the gap in order: the next item it gets is `Err(Lagged(n))`, `n` being the
//! items dropped since the previous one it got (tokio's `broadcast` reports `Lagged` the same
//! way), and then the newest items. A consumer slower than its producer therefore never holds
//! more than the capacity in memory, and always gets the most recent items.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::{Context as TaskContext, Poll, Waker};

/// Items dropped from a bounded stream's buffer because its consumer was slower than its
/// producer: the oldest ones, `0` of them since the item the consumer got before.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the consumer lagged: {0} items were dropped (the oldest ones)")]
pub struct Lagged(pub u64);

/// A bounded buffer between one producer (a thread, a callback) and one consumer task: `push`
/// never blocks and drops the oldest item when full; `poll_next` gives `Err(Lagged(n))` first
/// when items were dropped, then the buffered items in order, and `None` once closed and empty.
///
/// ```
/// use horus_ros_rmw::queue::{DropOldestQueue, Lagged};
///
/// let queue = DropOldestQueue::new(2);
/// queue.push_all([1, 2, 3, 4]); // a producer faster than its consumer
/// assert_eq!(queue.len(), 2);
/// assert_eq!(queue.try_next(), Some(Err(Lagged(2)))); // 1 and 2 were dropped
/// assert_eq!(queue.try_next(), Some(Ok(3)));
/// assert_eq!(queue.try_next(), Some(Ok(4)));
/// assert_eq!(queue.try_next(), None);
/// ```
#[derive(Debug)]
pub struct DropOldestQueue<T> {
    inner: Mutex<Inner<T>>,
}

#[derive(Debug)]
struct Inner<T> {
    items: VecDeque<T>,
    capacity: usize,
    /// Dropped since the consumer last got something.
    skipped: u64,
    /// Dropped in all.
    lagged: u64,
    /// Pushed in all.
    pushed: u64,
    /// The most items ever buffered at once.
    peak: usize,
    closed: bool,
    waker: Option<Waker>,
}

impl<T> DropOldestQueue<T> {
    /// An empty queue holding at most `capacity` items (at least 1).
    pub fn new(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Self {
            inner: Mutex::new(Inner {
                items: VecDeque::with_capacity(capacity.min(1024)),
                capacity,
                skipped: 0,
                lagged: 0,
                pushed: 0,
                peak: 0,
                closed: false,
                waker: None,
            }),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Inner<T>> {
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Adds `item`, dropping the oldest buffered item if the queue is full, and wakes the
    /// consumer. Ignored once the queue is closed.
    pub fn push(&self, item: T) {
        self.push_all(std::iter::once(item));
    }

    /// Adds every item in order (one lock, one wake-up), as [`push`](Self::push) does.
    pub fn push_all(&self, items: impl IntoIterator<Item = T>) {
        if let Some(waker) = self.push_all_deferred(items) {
            waker.wake();
        }
    }

    /// Adds every item as [`push_all`](Self::push_all) does, but gives the consumer's waker
    /// (if it waits) to the caller to wake, e.g. once the caller's own locks are released.
    #[must_use = "the consumer waits until the returned waker is woken"]
    pub fn push_all_deferred(&self, items: impl IntoIterator<Item = T>) -> Option<Waker> {
        let mut inner = self.lock();
        if inner.closed {
            return None;
        }
        let mut any = false;
        for item in items {
            if inner.items.len() >= inner.capacity {
                inner.items.pop_front();
                inner.skipped += 1;
                inner.lagged += 1;
            }
            inner.items.push_back(item);
            inner.pushed += 1;
            inner.peak = inner.peak.max(inner.items.len());
            any = true;
        }
        if any {
            inner.waker.take()
        } else {
            None
        }
    }

    /// Ends the stream: the consumer gets what is buffered, then `None`.
    pub fn close(&self) {
        let mut inner = self.lock();
        inner.closed = true;
        let waker = inner.waker.take();
        drop(inner);
        if let Some(waker) = waker {
            waker.wake();
        }
    }

    /// The next item without waiting: `Some(Err(Lagged))` if items were dropped since the last
    /// one taken, `Some(Ok(item))`, or `None` when nothing is buffered.
    pub fn try_next(&self) -> Option<Result<T, Lagged>> {
        Self::take(&mut self.lock())
    }

    fn take(inner: &mut Inner<T>) -> Option<Result<T, Lagged>> {
        if inner.skipped > 0 {
            let skipped = std::mem::take(&mut inner.skipped);
            return Some(Err(Lagged(skipped)));
        }
        inner.items.pop_front().map(Ok)
    }

    /// The next item, registering the task's waker when there is none yet (for a `Stream`
    /// implementation): `Ready(None)` once closed and drained.
    pub fn poll_next(&self, cx: &mut TaskContext<'_>) -> Poll<Option<Result<T, Lagged>>> {
        let mut inner = self.lock();
        if let Some(next) = Self::take(&mut inner) {
            return Poll::Ready(Some(next));
        }
        if inner.closed {
            return Poll::Ready(None);
        }
        match &mut inner.waker {
            Some(w) if w.will_wake(cx.waker()) => {}
            slot => *slot = Some(cx.waker().clone()),
        }
        Poll::Pending
    }

    /// Items buffered now (never more than [`capacity`](Self::capacity)).
    pub fn len(&self) -> usize {
        self.lock().items.len()
    }

    /// Whether nothing is buffered now.
    pub fn is_empty(&self) -> bool {
        self.lock().items.is_empty()
    }

    /// The most items the buffer holds.
    pub fn capacity(&self) -> usize {
        self.lock().capacity
    }

    /// Items dropped so far because the buffer was full (the sum of every `Lagged(n)` reported
    /// and still to be reported).
    pub fn lagged(&self) -> u64 {
        self.lock().lagged
    }

    /// Items pushed so far (delivered, buffered or dropped).
    pub fn pushed(&self) -> u64 {
        self.lock().pushed
    }

    /// The most items ever buffered at once (at most [`capacity`](Self::capacity)).
    pub fn peak(&self) -> usize {
        self.lock().peak
    }

    /// Whether the producer closed the queue.
    pub fn is_closed(&self) -> bool {
        self.lock().closed
    }
}

/// The consumer's side of a [`DropOldestQueue`] shared with its producer: the items and the
/// counters, without `push` or `close`. The bounded streams (feature `tokio`: a subscription's
/// `SubscriptionStream`, the graph's `GraphEvents`) deref to it for their counters; an item is
/// a message or an event there.
///
/// ```
/// use std::sync::Arc;
/// use horus_ros_rmw::queue::{DropOldestQueue, Lagged, QueueConsumer};
///
/// let queue = Arc::new(DropOldestQueue::new(2));
/// let consumer = QueueConsumer::new(Arc::clone(&queue));
/// queue.push_all([1, 2, 3]);
/// assert_eq!((consumer.len(), consumer.lagged(), consumer.received()), (2, 1, 3));
/// assert_eq!(consumer.try_next(), Some(Err(Lagged(1))));
/// ```
#[derive(Debug)]
pub struct QueueConsumer<T> {
    queue: Arc<DropOldestQueue<T>>,
}

impl<T> QueueConsumer<T> {
    /// The consumer of `queue`, whose producer keeps another handle to it.
    pub fn new(queue: Arc<DropOldestQueue<T>>) -> Self {
        Self { queue }
    }

    /// The next item or gap report, registering the task's waker (what `Stream::poll_next`
    /// does); `Ready(None)` once the producer closed the queue and it is drained.
    pub fn poll_next(&self, cx: &mut TaskContext<'_>) -> Poll<Option<Result<T, Lagged>>> {
        self.queue.poll_next(cx)
    }

    /// The next item or gap report if one is buffered (never waits).
    pub fn try_next(&self) -> Option<Result<T, Lagged>> {
        self.queue.try_next()
    }

    /// Items buffered now (at most [`capacity`](Self::capacity)).
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    /// Whether no item is buffered now.
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// The most items buffered.
    pub fn capacity(&self) -> usize {
        self.queue.capacity()
    }

    /// Items dropped so far because the consumer was behind (oldest first).
    pub fn lagged(&self) -> u64 {
        self.queue.lagged()
    }

    /// Items received so far (delivered, buffered or dropped).
    pub fn received(&self) -> u64 {
        self.queue.pushed()
    }

    /// The most items ever buffered at once (at most [`capacity`](Self::capacity)).
    pub fn peak(&self) -> usize {
        self.queue.peak()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};

    #[test]
    fn a_full_queue_drops_the_oldest_and_reports_the_gap_first() {
        let queue = DropOldestQueue::new(4);
        queue.push_all(0..10);
        assert_eq!(queue.len(), 4);
        assert_eq!(queue.peak(), 4);
        assert_eq!(queue.lagged(), 6);
        assert_eq!(queue.pushed(), 10);
        assert_eq!(queue.try_next(), Some(Err(Lagged(6))));
        let rest: Vec<_> = std::iter::from_fn(|| queue.try_next()).collect();
        assert_eq!(rest, vec![Ok(6), Ok(7), Ok(8), Ok(9)]);
        queue.push(10);
        assert_eq!(
            queue.try_next(),
            Some(Ok(10)),
            "no gap: nothing dropped since"
        );
        assert_eq!(queue.lagged(), 6);
    }

    #[test]
    fn closing_ends_the_stream_after_the_buffered_items() {
        let queue = DropOldestQueue::new(2);
        queue.push(1);
        queue.close();
        queue.push(2);
        let waker = futures_waker();
        let mut cx = TaskContext::from_waker(&waker);
        assert_eq!(queue.poll_next(&mut cx), Poll::Ready(Some(Ok(1))));
        assert_eq!(queue.poll_next(&mut cx), Poll::Ready(None));
    }

    #[test]
    fn a_push_wakes_the_waiting_consumer() {
        struct Flag(AtomicBool);
        impl std::task::Wake for Flag {
            fn wake(self: Arc<Self>) {
                self.0.store(true, Ordering::SeqCst);
            }
        }
        let flag = Arc::new(Flag(AtomicBool::new(false)));
        let waker = Waker::from(Arc::clone(&flag));
        let mut cx = TaskContext::from_waker(&waker);
        let queue = DropOldestQueue::new(2);
        assert_eq!(queue.poll_next(&mut cx), Poll::Pending);
        assert!(!flag.0.load(Ordering::SeqCst));
        queue.push(7);
        assert!(flag.0.load(Ordering::SeqCst));
        assert_eq!(queue.poll_next(&mut cx), Poll::Ready(Some(Ok(7))));
    }

    fn futures_waker() -> Waker {
        struct Nothing;
        impl std::task::Wake for Nothing {
            fn wake(self: Arc<Self>) {}
        }
        Waker::from(Arc::new(Nothing))
    }
}
