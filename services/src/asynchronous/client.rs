//! Awaited calls: [`AsyncServiceClient::call`] ([`ServiceCall`]) and
//! [`AsyncServiceClient::wait_for_service_async`] ([`WaitForService`]).

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context as TaskContext, Poll};
use std::time::{Duration, Instant};

use horus_ros_msgs::Service;
use tokio::time::Sleep;

use super::graph_wake::GraphWake;
use crate::client::codec::Typed;
use crate::client::core::{ClientCore, ReadyServer, RequestKey};
use crate::{AsyncServiceClient, ServiceError, TransportError};

impl<S: Service> AsyncServiceClient<S> {
    /// Calls the service and gives a future of the reply, to `.await` on a tokio runtime (with
    /// its time driver on: `#[tokio::main]`, `#[tokio::test]` and `Builder::enable_all` have it).
    /// Takes `&self`: share the client (e.g. in an `Arc`) between tasks and calls.
    ///
    /// The same outcomes as the blocking [`ServiceClient::call`](crate::ServiceClient::call):
    /// `NoServer` if no server of this service and type appeared within `timeout`, `Timeout` if
    /// one was there but did not answer in time, `ServiceFailed` if its handler failed or
    /// panicked, `Transport(TransportError::ServerGone)` as soon as every server the request
    /// went to left. The future is
    /// woken by events only: the reply being routed to it, graph changes while it waits for a
    /// server, its own deadline.
    ///
    /// Cancel-safe: dropping the future (`tokio::time::timeout`, `select!`, an aborted task)
    /// withdraws the call; its reply, if one comes, is dropped, and
    /// [`pending_requests`](Self::pending_requests) counts it no more.
    ///
    /// ```no_run
    /// use horus_ros_services::prelude::*;
    ///
    /// #[tokio::main]
    /// async fn main() -> Result<()> {
    ///     let client = AsyncServiceClient::<AddTwoInts>::builder()
    ///         .name("/add_two_ints")
    ///         .build()?;
    ///     let reply = client
    ///         .call(AddTwoIntsRequest { a: 2, b: 3 }, Duration::from_secs(1))
    ///         .await?;
    ///     assert_eq!(reply.sum, 5);
    ///     Ok(())
    /// }
    /// ```
    pub fn call(&self, request: S::Request, timeout: Duration) -> ServiceCall<S> {
        let deadline = Instant::now() + timeout;
        ServiceCall {
            core: Arc::clone(self.core()),
            state: CallState::Unsent(Some(request)),
            wait: Waiting::new(deadline),
        }
    }

    /// A future that resolves to `true` as soon as a server can take a call (its endpoints are
    /// known and matched with ours: what a call waits for before sending), or `false` after
    /// `timeout` (rclcpp `wait_for_service`). Woken by graph changes, never polled; needs a tokio
    /// runtime with its time driver on, as [`call`](Self::call) does.
    ///
    /// ```no_run
    /// use horus_ros_services::prelude::*;
    ///
    /// #[tokio::main]
    /// async fn main() -> Result<()> {
    ///     let client = AsyncServiceClient::<AddTwoInts>::builder()
    ///         .name("/add_two_ints")
    ///         .build()?;
    ///     if client.wait_for_service_async(Duration::from_secs(5)).await {
    ///         println!("the server is there");
    ///     }
    ///     Ok(())
    /// }
    /// ```
    pub fn wait_for_service_async(&self, timeout: Duration) -> WaitForService<S> {
        WaitForService {
            core: Arc::clone(self.core()),
            wait: Waiting::new(Instant::now() + timeout),
        }
    }
}

/// What waiting for a usable server needs: the deadline, a watcher of the graph, and the timer
/// of an rmw_cyclonedds server still settling.
struct Waiting {
    deadline: Instant,
    /// The deadline as a tokio timer (created at the first poll that needs it).
    timer: Option<Pin<Box<Sleep>>>,
    /// Wakes the task at the next graph change (created when a server is waited for).
    graph: Option<Arc<GraphWake>>,
    /// When a matched server becomes ready without a graph change, and its timer.
    settle: Option<(Instant, Pin<Box<Sleep>>)>,
}

impl Waiting {
    fn new(deadline: Instant) -> Self {
        Self {
            deadline,
            timer: None,
            graph: None,
            settle: None,
        }
    }

    /// Whether the deadline passed; if not, the task is woken when it does.
    fn expired(&mut self, cx: &mut TaskContext<'_>) -> bool {
        if Instant::now() >= self.deadline {
            return true;
        }
        let deadline = tokio::time::Instant::from_std(self.deadline);
        let timer = self
            .timer
            .get_or_insert_with(|| Box::pin(tokio::time::sleep_until(deadline)));
        timer.as_mut().poll(cx).is_ready()
    }

    /// A usable server, an error that ends the wait (`Transport` when none can be called from
    /// this backend; `NoServer` or `Timeout` at the deadline), or `Pending` with the task woken by
    /// the next graph change, the settling of a server, or the deadline.
    fn poll_server<S: Service>(
        &mut self,
        core: &ClientCore<Typed<S>>,
        cx: &mut TaskContext<'_>,
    ) -> Poll<Result<ReadyServer, ServiceError>> {
        if let Some(server) = core.ready_server() {
            return Poll::Ready(Ok(server));
        }
        // Watch first, then look again: a change between the two wakes the task.
        self.graph
            .get_or_insert_with(|| GraphWake::watch(core.graph()))
            .set(cx.waker());
        for _ in 0..2 {
            if let Some(server) = core.ready_server() {
                return Poll::Ready(Ok(server));
            }
            if let Some(why) = core.unusable_servers() {
                return Poll::Ready(Err(ServiceError::Transport(why)));
            }
            if self.expired(cx) {
                return Poll::Ready(Err(core.not_ready_error()));
            }
            let Some(at) = core.settles_at() else {
                self.settle = None;
                return Poll::Pending;
            };
            let timer = match &mut self.settle {
                Some((when, timer)) if *when == at => timer,
                slot => {
                    let timer = Box::pin(tokio::time::sleep_until(at.into()));
                    &mut slot.insert((at, timer)).1
                }
            };
            if timer.as_mut().poll(cx).is_pending() {
                return Poll::Pending;
            }
            // Settled: look again (once).
            self.settle = None;
        }
        Poll::Pending
    }
}

enum CallState<S: Service> {
    /// Waiting for a usable server.
    Unsent(Option<S::Request>),
    /// Sent; waiting for the reply.
    Sent(RequestKey),
    /// The result was handed out.
    Done,
}

/// One call of [`AsyncServiceClient::call`]: a future of the reply (see there). Dropping it
/// withdraws the call.
#[must_use = "a call is sent when its future is polled (awaited), and withdrawn when dropped"]
pub struct ServiceCall<S: Service> {
    core: Arc<ClientCore<Typed<S>>>,
    state: CallState<S>,
    wait: Waiting,
}

impl<S: Service> std::fmt::Debug for ServiceCall<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let state = match self.state {
            CallState::Unsent(_) => "unsent",
            CallState::Sent(_) => "sent",
            CallState::Done => "done",
        };
        f.debug_struct("ServiceCall")
            .field("service", self.core.name())
            .field("state", &state)
            .finish()
    }
}

impl<S: Service> ServiceCall<S> {
    /// Whether the request has been sent (the call waits for its reply).
    pub fn is_sent(&self) -> bool {
        matches!(self.state, CallState::Sent(_))
    }
}

// Nothing in a ServiceCall is pinned in place: its timers are boxed.
impl<S: Service> Unpin for ServiceCall<S> {}

impl<S: Service> Future for ServiceCall<S> {
    type Output = Result<S::Response, ServiceError>;

    fn poll(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Self::Output> {
        let this = self.get_mut();
        if let CallState::Unsent(request) = &mut this.state {
            let sent = match this.wait.poll_server(&this.core, cx) {
                Poll::Pending => return Poll::Pending,
                Poll::Ready(Ok(server)) => match request.take() {
                    Some(request) => this.core.send(&request, server, this.wait.deadline, None),
                    None => Err(ServiceError::Transport(TransportError::CallCompleted)),
                },
                Poll::Ready(Err(e)) => Err(e),
            };
            match sent {
                Ok(key) => {
                    this.state = CallState::Sent(key);
                    // No more graph wake-ups: the client's watcher ends the call if its servers go.
                    this.wait.graph = None;
                    this.wait.settle = None;
                }
                Err(e) => {
                    this.state = CallState::Done;
                    return Poll::Ready(Err(e));
                }
            }
        }
        match this.state {
            CallState::Sent(key) => {
                // The waker first: a reply routed after it is stored wakes the task.
                this.core.set_waker(key, cx.waker());
                if let Some(result) = this.core.take_result(key) {
                    this.state = CallState::Done;
                    return Poll::Ready(result);
                }
                if this.wait.expired(cx) {
                    this.core.forget(key);
                    this.state = CallState::Done;
                    return Poll::Ready(Err(ServiceError::Timeout));
                }
                Poll::Pending
            }
            _ => Poll::Ready(Err(ServiceError::Transport(TransportError::CallCompleted))),
        }
    }
}

impl<S: Service> Drop for ServiceCall<S> {
    fn drop(&mut self) {
        if let CallState::Sent(key) = self.state {
            self.core.forget(key);
        }
    }
}

/// The future of [`AsyncServiceClient::wait_for_service_async`]: `true` once a server can take a
/// call, `false` at the timeout.
#[must_use = "futures do nothing unless awaited"]
pub struct WaitForService<S: Service> {
    core: Arc<ClientCore<Typed<S>>>,
    wait: Waiting,
}

impl<S: Service> std::fmt::Debug for WaitForService<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WaitForService")
            .field("service", self.core.name())
            .finish()
    }
}

impl<S: Service> Unpin for WaitForService<S> {}

impl<S: Service> Future for WaitForService<S> {
    type Output = bool;

    fn poll(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<bool> {
        let this = self.get_mut();
        match this.wait.poll_server(&this.core, cx) {
            Poll::Ready(Ok(_)) => Poll::Ready(true),
            // Unusable servers are waited for too: another may come.
            Poll::Ready(Err(ServiceError::Transport(_))) if !this.wait.expired(cx) => Poll::Pending,
            Poll::Ready(Err(_)) => Poll::Ready(false),
            Poll::Pending => Poll::Pending,
        }
    }
}
