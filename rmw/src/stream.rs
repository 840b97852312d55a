//! Bounded streams (feature `tokio`): a [`Subscription`] as a [`futures_core::Stream`] of its
//! messages ([`SubscriptionStream`]), and the buffer behind it and behind the graph's event
//! stream ([`DropOldestQueue`]).
//!
//! Overflow policy: a stream's buffer holds at most its capacity; when an item arrives while it
//! is full, the **oldest** buffered item is dropped (as a KEEP_LAST history does) and counted.
//! The consumer learns of the gap in order: the next item it gets is `Err(Lagged(n))`, `n` being
//! the items dropped since the previous one it got (tokio's `broadcast` reports `Lagged` the
//! same way), and then the newest items. A consumer slower than its producer therefore never
//! holds more than the capacity in memory, and always gets the most recent items.
//!
//! Runtime-agnostic: wake-ups go to the consumer task's [`Waker`], registered when it polls; any
//! executor (tokio included) can drive these streams.

use std::collections::VecDeque;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::{Context as TaskContext, Poll, Waker};
use std::thread::JoinHandle;
use std::time::Duration;

use horus_ros_msgs::Message;

use crate::{RawReaderWaker, Subscription};

/// Items dropped from a bounded stream's buffer because its consumer was slower than its
/// producer: the oldest ones, `0` of them since the item the consumer got before.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the consumer lagged: {0} items were dropped (the oldest ones)")]
pub struct Lagged(pub u64);

/// How many items a [`SubscriptionStream`] buffers unless told otherwise.
pub const DEFAULT_STREAM_CAPACITY: usize = 256;

/// A bounded buffer between one producer (a thread, a callback) and one consumer task: `push`
/// never blocks and drops the oldest item when full; `poll_next` gives `Err(Lagged(n))` first
/// when items were dropped, then the buffered items in order, and `None` once closed and empty.
///
/// ```
/// use horus_ros_rmw::stream::{DropOldestQueue, Lagged};
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

/// A [`Subscription`]'s messages as a [`futures_core::Stream`] of `Result<M, Lagged>` (see the
/// [module](self) for the overflow policy): a background thread blocks on the subscription's
/// reader (woken by arriving data, never polling) and moves every message into a bounded
/// buffer, waking the consumer task. Dropping the stream stops the thread and drops the
/// subscription (it leaves the graph).
///
/// ```no_run
/// # async fn demo() -> Result<(), Box<dyn std::error::Error>> {
/// use horus_ros_msgs::std_msgs::msg::String as StringMsg;
/// use horus_ros_rmw::qos::Qos;
/// use horus_ros_rmw::Context;
///
/// let context = Context::from_env()?;
/// let node = context.create_node("listener", "/")?;
/// let subscription = node.create_subscription::<StringMsg>("chatter", &Qos::default_profile())?;
/// let mut stream = subscription.into_stream(64)?;
/// // With `futures::StreamExt` (or tokio-stream's): `while let Some(m) = stream.next().await`.
/// while let Some(message) = std::future::poll_fn(|cx| stream.poll_next_message(cx)).await {
///     match message {
///         Ok(m) => println!("I heard: [{}]", m.data),
///         Err(lagged) => println!("{lagged}"),
///     }
/// }
/// # Ok(()) }
/// ```
pub struct SubscriptionStream<M: Message> {
    queue: Arc<DropOldestQueue<M>>,
    stop: Arc<AtomicBool>,
    waker: RawReaderWaker,
    thread: Option<JoinHandle<()>>,
    gid: crate::Gid,
    topic: String,
}

impl<M: Message> std::fmt::Debug for SubscriptionStream<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SubscriptionStream")
            .field("topic", &self.topic)
            .field("buffered", &self.queue.len())
            .finish()
    }
}

/// Longest single wait of a stream's thread; arriving data and the stream's drop wake it at once.
const IDLE_WAIT: Duration = Duration::from_secs(3600);

impl<M: Message> Subscription<M> {
    /// This subscription's messages as a bounded stream holding at most `capacity` of them (at
    /// least 1); see [`SubscriptionStream`]. Fails only if its thread cannot be started.
    pub fn into_stream(self, capacity: usize) -> std::io::Result<SubscriptionStream<M>> {
        let queue = Arc::new(DropOldestQueue::new(capacity));
        let stop = Arc::new(AtomicBool::new(false));
        let waker = self.waker();
        let gid = self.gid();
        let topic = self.topic_name().to_string();
        let thread = {
            let (queue, stop) = (Arc::clone(&queue), Arc::clone(&stop));
            std::thread::Builder::new()
                .name(format!("horus-sub{topic}"))
                .spawn(move || pump(self, &queue, &stop))?
        };
        Ok(SubscriptionStream {
            queue,
            stop,
            waker,
            thread: Some(thread),
            gid,
            topic,
        })
    }
}

/// The stream's thread: takes every message that has arrived into the queue (in one push, so a
/// burst larger than the capacity keeps its newest part), then waits for more.
fn pump<M: Message>(
    mut subscription: Subscription<M>,
    queue: &DropOldestQueue<M>,
    stop: &AtomicBool,
) {
    let mut batch = Vec::new();
    while !stop.load(Ordering::SeqCst) {
        loop {
            match subscription.try_take() {
                Ok(Some(message)) => batch.push(message),
                Ok(None) => break,
                Err(e) => tracing::debug!("dropped a sample: {e}"),
            }
        }
        if !batch.is_empty() {
            queue.push_all(batch.drain(..));
        }
        subscription.wait(IDLE_WAIT);
    }
    queue.close();
}

impl<M: Message> SubscriptionStream<M> {
    /// The next message or gap report, registering the task's waker (what `Stream::poll_next`
    /// does, usable without importing the trait).
    pub fn poll_next_message(
        &mut self,
        cx: &mut TaskContext<'_>,
    ) -> Poll<Option<Result<M, Lagged>>> {
        self.queue.poll_next(cx)
    }

    /// The next message or gap report if one is buffered (never waits).
    pub fn try_next(&mut self) -> Option<Result<M, Lagged>> {
        self.queue.try_next()
    }

    /// Messages buffered now (at most [`capacity`](Self::capacity)).
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    /// Whether no message is buffered now.
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// The most messages buffered.
    pub fn capacity(&self) -> usize {
        self.queue.capacity()
    }

    /// Messages dropped so far because the consumer was behind (oldest first).
    pub fn lagged(&self) -> u64 {
        self.queue.lagged()
    }

    /// Messages received so far (delivered, buffered or dropped).
    pub fn received(&self) -> u64 {
        self.queue.pushed()
    }

    /// The most messages ever buffered at once (at most [`capacity`](Self::capacity)).
    pub fn peak(&self) -> usize {
        self.queue.peak()
    }

    /// The reader's GID.
    pub fn gid(&self) -> crate::Gid {
        self.gid
    }

    /// The fully-qualified topic name.
    pub fn topic_name(&self) -> &str {
        &self.topic
    }
}

impl<M: Message> futures_core::Stream for SubscriptionStream<M> {
    type Item = Result<M, Lagged>;

    fn poll_next(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Option<Self::Item>> {
        self.get_mut().queue.poll_next(cx)
    }
}

impl<M: Message> Drop for SubscriptionStream<M> {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        self.waker.wake();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
