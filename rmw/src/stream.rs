//! Bounded streams (feature `tokio`): a [`Subscription`] as a [`futures_core::Stream`] of its
//! messages ([`SubscriptionStream`]), buffered in a [`DropOldestQueue`] (see [`crate::queue`]
//! for the overflow policy).
//!
//! Runtime-agnostic: wake-ups go to the consumer task's [`Waker`](std::task::Waker), registered when it polls; any
//! executor (tokio included) can drive these streams.

use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::task::{Context as TaskContext, Poll};
use std::thread::JoinHandle;

use horus_ros_msgs::Message;

pub use crate::queue::{DropOldestQueue, Lagged, QueueConsumer};
use crate::{RawReaderWaker, Subscription};

/// How many items a [`SubscriptionStream`] buffers unless told otherwise.
pub const DEFAULT_STREAM_CAPACITY: usize = 256;

/// A [`Subscription`]'s messages as a [`futures_core::Stream`] of `Result<M, Lagged>` (see the
/// [module](self) for the overflow policy): a background thread blocks on the subscription's
/// reader (woken by arriving data, never polling) and moves every message into a bounded
/// buffer, waking the consumer task. Dropping the stream stops the thread and drops the
/// subscription (it leaves the graph). Its counters (`len`, `lagged`, `received`, `peak`, …)
/// come from [`QueueConsumer`], to which it derefs.
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
    queue: QueueConsumer<M>,
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
            queue: QueueConsumer::new(queue),
            stop,
            waker,
            thread: Some(thread),
            gid,
            topic,
        })
    }
}

/// The stream's thread: takes every message that has arrived into the queue (in pushes of at
/// most the queue's capacity, so a burst larger than the capacity keeps its newest part and a
/// publisher faster than the taking never grows the batch), then waits for more.
fn pump<M: Message>(
    mut subscription: Subscription<M>,
    queue: &DropOldestQueue<M>,
    stop: &AtomicBool,
) {
    let capacity = queue.capacity();
    let mut batch = Vec::new();
    while !stop.load(Ordering::SeqCst) {
        loop {
            match subscription.try_take() {
                Ok(Some(message)) => {
                    batch.push(message);
                    if batch.len() >= capacity {
                        queue.push_all(batch.drain(..));
                        // A publisher faster than the taking must not keep drop() waiting.
                        if stop.load(Ordering::SeqCst) {
                            break;
                        }
                    }
                }
                Ok(None) => break,
                Err(e) => tracing::debug!("dropped a sample: {e}"),
            }
        }
        if !batch.is_empty() {
            queue.push_all(batch.drain(..));
        }
        // Arriving data and the stream's drop (its waker) end the wait.
        subscription.wait(None);
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

    /// The reader's GID.
    pub fn gid(&self) -> crate::Gid {
        self.gid
    }

    /// The fully-qualified topic name.
    pub fn topic_name(&self) -> &str {
        &self.topic
    }
}

/// The counters, each counting messages: [`len`](QueueConsumer::len),
/// [`is_empty`](QueueConsumer::is_empty), [`capacity`](QueueConsumer::capacity),
/// [`lagged`](QueueConsumer::lagged), [`received`](QueueConsumer::received) and
/// [`peak`](QueueConsumer::peak).
impl<M: Message> std::ops::Deref for SubscriptionStream<M> {
    type Target = QueueConsumer<M>;

    fn deref(&self) -> &QueueConsumer<M> {
        &self.queue
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
