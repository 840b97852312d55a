//! [`AsyncServiceClient`] and [`PendingResponse`]: calls that do not block the caller.

use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::task::{Context as TaskContext, Poll};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_msgs::Service;

use super::codec::Typed;
use super::core::{client_handle_methods, ClientCore, RequestKey};
use super::ServiceClientBuilder;
use crate::{ServiceError, SetupError, TransportError};

/// Calls a service without blocking: each call returns a [`PendingResponse`] to check, wait on,
/// or `.await`. A background thread receives the replies.
#[must_use = "a client's endpoints exist only while it is held"]
pub struct AsyncServiceClient<S: Service> {
    core: Arc<ClientCore<Typed<S>>>,
    stop: Arc<AtomicBool>,
    pump: Option<JoinHandle<()>>,
}

impl<S: Service> std::fmt::Debug for AsyncServiceClient<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AsyncServiceClient")
            .field("name", self.core.name())
            .finish()
    }
}

impl<S: Service> AsyncServiceClient<S> {
    /// A client of the service's default name on the default node.
    pub fn new() -> Result<Self, SetupError> {
        Self::builder().build()
    }

    /// A builder to choose node, name, QoS, wire convention and introspection; `build()` gives
    /// this client.
    pub fn builder() -> ServiceClientBuilder<S, Self> {
        ServiceClientBuilder::new()
    }

    pub(crate) fn from_core(core: ClientCore<Typed<S>>) -> Result<Self, SetupError> {
        let core = Arc::new(core);
        let stop = Arc::new(AtomicBool::new(false));
        let pump = {
            let (core, stop) = (Arc::clone(&core), Arc::clone(&stop));
            std::thread::Builder::new()
                .name(format!("horus-cli{}", core.name()))
                .spawn(move || {
                    // Woken by replies, by graph changes that end calls or (while futures wait
                    // for a server) may make one usable, by new futures and by drop; and at the
                    // earliest deadline of a waiting future.
                    while !stop.load(Ordering::SeqCst) {
                        core.drain_replies();
                        let next = core.wake_due();
                        core.wait_for_replies(
                            next.map(|t| t.saturating_duration_since(Instant::now())),
                        );
                    }
                })?
        };
        Ok(Self {
            core,
            stop,
            pump: Some(pump),
        })
    }

    client_handle_methods!(
        discovery,
        "",
        "It blocks the caller: in async code, `wait_for_service_async` (feature `tokio`) waits",
        "without blocking."
    );

    /// Requests sent whose replies are still awaited (0 once every call ended or was dropped:
    /// nothing leaks).
    pub fn pending_requests(&self) -> usize {
        self.core.pending_count()
    }

    /// The state shared with the reply thread (for the async layer).
    #[cfg(feature = "tokio")]
    pub(crate) fn core(&self) -> &Arc<ClientCore<Typed<S>>> {
        &self.core
    }

    client_handle_methods!(introspection);

    /// Starts a call (never blocks). If no server is usable yet, the request is sent as soon as
    /// one is, within `timeout`.
    pub fn call_async(&self, request: S::Request, timeout: Duration) -> PendingResponse<S> {
        let mut pending = PendingResponse {
            core: Arc::clone(&self.core),
            deadline: Instant::now() + timeout,
            state: State::Unsent(Some(request)),
        };
        pending.advance();
        pending
    }
}

impl<S: Service> Drop for AsyncServiceClient<S> {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        self.core.wake();
        if let Some(pump) = self.pump.take() {
            let _ = pump.join();
        }
    }
}

enum State<S: Service> {
    /// Waiting for a usable server.
    Unsent(Option<S::Request>),
    /// Sent; waiting for the reply.
    Sent(RequestKey),
    /// Finished; the result was handed out (or is about to be).
    Done(Option<Result<S::Response, ServiceError>>),
}

/// One call of an [`AsyncServiceClient`]: check it, wait for it, or `.await` it (any executor).
/// Dropping it abandons the call; a late reply is then dropped.
#[must_use = "dropping a pending response abandons its call"]
pub struct PendingResponse<S: Service> {
    core: Arc<ClientCore<Typed<S>>>,
    deadline: Instant,
    state: State<S>,
}

impl<S: Service> std::fmt::Debug for PendingResponse<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let state = match self.state {
            State::Unsent(_) => "unsent",
            State::Sent(_) => "sent",
            State::Done(_) => "done",
        };
        f.debug_struct("PendingResponse")
            .field("state", &state)
            .finish()
    }
}

impl<S: Service> PendingResponse<S> {
    /// Moves the call on as far as it can go without blocking.
    fn advance(&mut self) {
        if let State::Unsent(request) = &mut self.state {
            if let Some(server) = self.core.ready_server() {
                let outcome = match request.take() {
                    Some(req) => self.core.send(&req, server, self.deadline, None),
                    None => Err(ServiceError::Transport(TransportError::CallCompleted)),
                };
                self.state = match outcome {
                    Ok(key) => State::Sent(key),
                    Err(e) => State::Done(Some(Err(e))),
                };
            } else if Instant::now() >= self.deadline {
                self.state = State::Done(Some(Err(self.core.not_ready_error())));
            }
        }
        if let State::Sent(key) = self.state {
            if let Some(result) = self.core.take_result(key) {
                self.state = State::Done(Some(result));
            } else if Instant::now() >= self.deadline {
                self.core.forget(key);
                self.state = State::Done(Some(Err(ServiceError::Timeout)));
            }
        }
    }

    /// The response if it is in (non-blocking): `Ok(None)` while waiting. After it returned a
    /// response or an error, further calls return `Ok(None)`.
    pub fn check(&mut self) -> Result<Option<S::Response>, ServiceError> {
        self.advance();
        match &mut self.state {
            State::Done(result) => result.take().transpose(),
            _ => Ok(None),
        }
    }

    /// Whether the timeout has passed without a result.
    pub fn is_expired(&self) -> bool {
        !matches!(self.state, State::Done(_)) && Instant::now() >= self.deadline
    }

    /// Blocks until the response, an error, or the timeout.
    pub fn wait(mut self) -> Result<S::Response, ServiceError> {
        loop {
            self.advance();
            match &mut self.state {
                State::Done(result) => {
                    return result.take().unwrap_or(Err(ServiceError::Timeout));
                }
                State::Unsent(_) => self.core.wait_for_readiness_change(self.deadline),
                State::Sent(key) => self.core.wait_completion(*key, self.deadline),
            }
        }
    }
}

// Nothing in a PendingResponse is pinned in place (no self-references, no pin projections).
impl<S: Service> Unpin for PendingResponse<S> {}

impl<S: Service> Future for PendingResponse<S> {
    type Output = Result<S::Response, ServiceError>;

    fn poll(self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<Self::Output> {
        let this = self.get_mut();
        this.advance();
        match &mut this.state {
            State::Done(result) => Poll::Ready(result.take().unwrap_or(Err(ServiceError::Timeout))),
            State::Sent(key) => {
                this.core.set_waker(*key, cx.waker());
                // The reply may have been routed between advance() and set_waker().
                this.advance();
                match &mut this.state {
                    State::Done(result) => {
                        Poll::Ready(result.take().unwrap_or(Err(ServiceError::Timeout)))
                    }
                    _ => Poll::Pending,
                }
            }
            State::Unsent(_) => {
                this.core.park_unsent(cx.waker(), this.deadline);
                Poll::Pending
            }
        }
    }
}

impl<S: Service> Drop for PendingResponse<S> {
    fn drop(&mut self) {
        if let State::Sent(key) = self.state {
            self.core.forget(key);
        }
    }
}
