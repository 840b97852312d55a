//! The graph's changes as a [`futures_core::Stream`] (feature `tokio`): [`Graph::events`].

use std::pin::Pin;
use std::task::{Context as TaskContext, Poll};

pub use horus_ros_rmw::queue::Lagged;
use horus_ros_rmw::queue::QueueConsumer;

use crate::{Graph, GraphEvent};

/// How many events a [`GraphEvents`] stream buffers unless told otherwise.
pub const DEFAULT_EVENTS_CAPACITY: usize = 1024;

/// Every change of a [`Graph`] from the stream's creation on, as a [`futures_core::Stream`] of
/// `Result<GraphEvent, Lagged>`.
///
/// Bounded: at most its capacity of events are buffered; when the consumer falls behind, the
/// oldest are dropped and the consumer's next item is `Err(Lagged(n))` with their number, then
/// the newest events (see [`horus_ros_rmw::stream`]). Woken by the graph's thread as it applies
/// each change, never by polling. The stream ends when the graph is dropped. Its counters
/// (`len`, `lagged`, `received`, `peak`, …) come from [`QueueConsumer`], to which it derefs.
///
/// ```no_run
/// # async fn demo() -> Result<(), Box<dyn std::error::Error>> {
/// use horus_ros_graph::{Graph, GraphEvent};
/// use horus_ros_rmw::Context;
///
/// let context = Context::from_env()?;
/// let graph = Graph::of(&context)?;
/// let mut events = graph.events();
/// // With `futures::StreamExt`: `while let Some(event) = events.next().await`.
/// while let Some(event) = std::future::poll_fn(|cx| events.poll_next_event(cx)).await {
///     match event {
///         Ok(GraphEvent::NodeAdded { name, namespace }) => println!("node {namespace} {name}"),
///         Ok(other) => println!("{other:?}"),
///         Err(lagged) => println!("missed some: {lagged}"),
///     }
/// }
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct GraphEvents {
    queue: QueueConsumer<GraphEvent>,
}

impl GraphEvents {
    /// The next event or gap report, registering the task's waker (what `Stream::poll_next`
    /// does, usable without importing the trait).
    pub fn poll_next_event(
        &mut self,
        cx: &mut TaskContext<'_>,
    ) -> Poll<Option<Result<GraphEvent, Lagged>>> {
        self.queue.poll_next(cx)
    }

    /// The next event or gap report if one is buffered (never waits).
    pub fn try_next(&mut self) -> Option<Result<GraphEvent, Lagged>> {
        self.queue.try_next()
    }
}

/// The counters, each counting events: [`len`](QueueConsumer::len),
/// [`is_empty`](QueueConsumer::is_empty), [`capacity`](QueueConsumer::capacity),
/// [`lagged`](QueueConsumer::lagged), [`received`](QueueConsumer::received) and
/// [`peak`](QueueConsumer::peak).
impl std::ops::Deref for GraphEvents {
    type Target = QueueConsumer<GraphEvent>;

    fn deref(&self) -> &QueueConsumer<GraphEvent> {
        &self.queue
    }
}

impl futures_core::Stream for GraphEvents {
    type Item = Result<GraphEvent, Lagged>;

    fn poll_next(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Option<Self::Item>> {
        self.get_mut().queue.poll_next(cx)
    }
}

impl Graph {
    /// Every change from now on as a bounded stream of [`DEFAULT_EVENTS_CAPACITY`] events (see
    /// [`GraphEvents`]).
    pub fn events(&self) -> GraphEvents {
        self.events_with_capacity(DEFAULT_EVENTS_CAPACITY)
    }

    /// Every change from now on as a stream buffering at most `capacity` events (at least 1).
    pub fn events_with_capacity(&self, capacity: usize) -> GraphEvents {
        GraphEvents {
            queue: QueueConsumer::new(self.subscribers().add(capacity)),
        }
    }
}
