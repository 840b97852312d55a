//! [`DdsServiceClient`]: [`ServiceClientTrait`] over DDS, in the server's wire convention.

use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::{Wake, Waker};
use std::thread::{JoinHandle, Thread};
use std::time::{Duration, Instant};

use horus_ros_msgs::Service;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::Gid;

use super::{
    deserialize, encapsulate_into, le_body, serialize_into, RosService, ServiceClientTrait,
    TransportError,
};
use crate::client::codec::{Raw, RawResponse};
use crate::client::core::{ClientCore, ClientOptions, Readiness, RequestKey};
use crate::{EndpointBuilder, EndpointOptions, SetupError};

/// The default [`send_timeout`](DdsServiceClientBuilder::send_timeout).
const DEFAULT_SEND_TIMEOUT: Duration = Duration::from_secs(10);

/// Builds a [`DdsServiceClient`] ([`DdsServiceClient::builder`]). Node, name, QoS and wire
/// convention are set with the [`EndpointBuilder`] setters.
#[must_use = "a builder does nothing until .build() is called"]
pub struct DdsServiceClientBuilder<S: Service> {
    options: ClientOptions,
    send_timeout: Duration,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> EndpointBuilder for DdsServiceClientBuilder<S> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options.endpoint
    }
}

impl<S: Service> DdsServiceClientBuilder<S> {
    /// How long a request queued by `send_request_raw` may wait for a ready server before it is
    /// dropped and `try_recv_reply_raw` reports [`TransportError::NoServer`] (default 10 s).
    pub fn send_timeout(mut self, timeout: Duration) -> Self {
        self.send_timeout = timeout;
        self
    }

    /// Creates the request writer and reply reader and starts the reply thread.
    pub fn build(self) -> Result<DdsServiceClient<S>, SetupError> {
        // Raw payloads are re-encoded as CDR_LE bodies before they reach the core.
        let codec = Raw {
            service_type: S::TYPE_NAME.to_owned(),
        };
        let shared = Arc::new(Shared {
            core: ClientCore::for_service::<S>(codec, &self.options)?,
            send_timeout: self.send_timeout,
            state: Mutex::new(State {
                unsent: None,
                current: None,
                reply: None,
                waker: None,
            }),
            stop: AtomicBool::new(false),
        });
        let pump = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name(format!("horus-rawcli{}", shared.core.name()))
                .spawn(move || shared.pump())?
        };
        Ok(DdsServiceClient {
            shared,
            pump: Some(pump),
            discovery_deadline: None,
            _service: PhantomData,
        })
    }
}

/// A [`ServiceClientTrait`] client over DDS: talks to any server of the service (horus-ros,
/// rmw_fastrtps_cpp or rmw_cyclonedds_cpp), in that server's wire convention.
///
/// - `send_request_raw` never blocks: the request is sent at once if a server is ready (its
///   endpoints known and matched with ours), else queued and sent as soon as one is (by the next
///   `try_recv_reply_raw` or the background reply thread). A queued request not sent within the
///   [send timeout](DdsServiceClientBuilder::send_timeout) is dropped and reported as
///   [`TransportError::NoServer`]. Sending again replaces an unsent request.
/// - `try_recv_reply_raw` gives the reply to the most recently sent request only: replies to
///   earlier requests (and duplicates) are dropped. A reply that does not fit the buffer is kept
///   ([`TransportError::BufferTooSmall`]).
/// - A background thread receives replies and wakes the [registered](ServiceClientTrait::register_waker)
///   waker.
#[must_use = "a client's endpoints exist only while it is held"]
pub struct DdsServiceClient<S: Service> {
    shared: Arc<Shared>,
    pump: Option<JoinHandle<()>>,
    discovery_deadline: Option<Instant>,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for DdsServiceClient<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DdsServiceClient")
            .field("name", self.shared.core.name())
            .field("type", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> DdsServiceClient<S> {
    /// A client of the service's default name on the default node.
    pub fn new() -> Result<Self, SetupError> {
        Self::builder().build()
    }

    /// A builder to choose node, name, QoS, wire convention and send timeout.
    pub fn builder() -> DdsServiceClientBuilder<S> {
        DdsServiceClientBuilder {
            options: ClientOptions::default(),
            send_timeout: DEFAULT_SEND_TIMEOUT,
            _service: PhantomData,
        }
    }

    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        self.shared.core.name()
    }

    /// The GIDs of the request writer and the reply reader.
    pub fn gids(&self) -> (Gid, Gid) {
        self.shared.core.gids()
    }
}

impl<S: Service> Drop for DdsServiceClient<S> {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.shared.core.wake();
        if let Some(pump) = self.pump.take() {
            let _ = pump.join();
        }
    }
}

impl<S: Service> ServiceClientTrait for DdsServiceClient<S> {
    type Error = TransportError;

    /// Queues `request` (CDR with encapsulation header) and sends it now if a server is ready;
    /// forgets any earlier request and its reply. Errors only if the payload is not CDR or the
    /// DDS write fails.
    fn send_request_raw(&mut self, request: &[u8]) -> Result<(), TransportError> {
        let body = le_body::<S::Request>(request)?.into_owned();
        let mut state = self.shared.state();
        if let Some(key) = state.current.take() {
            // Its reply, if it still comes, is dropped.
            self.shared.core.forget(key);
        }
        state.reply = None;
        state.unsent = Some(Unsent {
            body,
            queued: Instant::now(),
        });
        let sent = self.shared.try_send(&mut state)?;
        if !sent && state.unsent.is_some() {
            // The reply thread sends it when a server is ready, or ends it at the send timeout.
            drop(state);
            self.shared.core.wake();
        }
        Ok(())
    }

    fn try_recv_reply_raw(
        &mut self,
        reply_buf: &mut [u8],
    ) -> Result<Option<usize>, TransportError> {
        let mut state = self.shared.state();
        if let Err(e) = self.shared.try_send(&mut state) {
            state.reply = Some(Err(e));
        }
        self.shared.collect(&mut state);
        match state.reply.take() {
            None => Ok(None),
            Some(Err(e)) => Err(e),
            Some(Ok(reply)) => match encapsulate_into(&reply.body, reply.big_endian, reply_buf) {
                Ok(len) => Ok(Some(len)),
                Err(e) => {
                    // Kept: the caller may retry with a larger buffer.
                    state.reply = Some(Ok(reply));
                    Err(e)
                }
            },
        }
    }

    /// Wakes `waker` once, when the next reply (or error) is ready; at once if one already is.
    fn register_waker(&self, waker: &Waker) {
        let mut state = self.shared.state();
        self.shared.collect(&mut state);
        if state.reply.is_some() {
            drop(state);
            waker.wake_by_ref();
        } else {
            state.waker = Some(waker.clone());
        }
    }

    /// Starts a query that ends after `timeout_ms` or when a server is ready.
    fn start_server_discovery(&mut self, timeout_ms: u32) -> Result<(), TransportError> {
        self.discovery_deadline =
            Some(Instant::now() + Duration::from_millis(u64::from(timeout_ms)));
        Ok(())
    }

    /// `Some(true)` once a server is ready (endpoints known and matched, see
    /// [`is_server_ready`](Self::is_server_ready)); `Some(false)` when the query's timeout passed
    /// without one; `None` meanwhile. Without a query in flight, answers at once.
    fn poll_server_discovery(&mut self) -> Result<Option<bool>, TransportError> {
        if self.shared.core.ready_server().is_some() {
            self.discovery_deadline = None;
            return Ok(Some(true));
        }
        match self.discovery_deadline {
            Some(deadline) if Instant::now() < deadline => Ok(None),
            _ => {
                self.discovery_deadline = None;
                Ok(Some(false))
            }
        }
    }

    /// Sends `request` and waits for its reply (blocking), unlike the trait's default, which
    /// answers `Timeout` at once. The whole call is bounded by the client's
    /// [send timeout](DdsServiceClientBuilder::send_timeout): `NoServer` if no server was ready
    /// in time, `Timeout` if one was and its reply did not come. Woken by the reply, never polled.
    fn call_raw(&mut self, request: &[u8], reply_buf: &mut [u8]) -> Result<usize, TransportError> {
        let deadline = Instant::now() + self.shared.send_timeout;
        self.send_request_raw(request)?;
        let waker = Waker::from(Arc::new(Unpark(std::thread::current())));
        loop {
            if let Some(len) = self.try_recv_reply_raw(reply_buf)? {
                return Ok(len);
            }
            // A reply that came after the look above wakes the waker at once.
            self.register_waker(&waker);
            let now = Instant::now();
            if now >= deadline {
                // An outcome that came after the look above (the reply, or the send timeout's
                // NoServer) is the answer; only then is the call given up.
                if let Some(len) = self.try_recv_reply_raw(reply_buf)? {
                    return Ok(len);
                }
                return Err(self.shared.abandon());
            }
            std::thread::park_timeout(deadline - now);
        }
    }

    /// The typed form of [`call_raw`](Self::call_raw) (blocking, bounded the same way).
    fn call<R: RosService>(
        &mut self,
        request: &R::Request,
        req_buf: &mut [u8],
        reply_buf: &mut [u8],
    ) -> Result<R::Reply, TransportError> {
        let len = serialize_into(request, req_buf)?;
        #[allow(deprecated)]
        let reply_len = self.call_raw(&req_buf[..len], reply_buf)?;
        deserialize(&reply_buf[..reply_len])
    }

    /// Whether a server is ready (see [the readiness words](crate#readiness)).
    fn is_server_ready(&self) -> bool {
        self.shared.core.is_server_ready()
    }

    /// Whether a server is known (see [the readiness words](crate#readiness)); this backend
    /// always knows, so never `Err`.
    fn server_available(&self) -> Result<bool, TransportError> {
        Ok(self.shared.core.server_available())
    }
}

/// A request waiting for a ready server.
struct Unsent {
    /// The CDR_LE body (no encapsulation header, no rmw_cyclonedds header).
    body: Vec<u8>,
    queued: Instant,
}

struct State {
    unsent: Option<Unsent>,
    /// The request sent last, until its reply is in.
    current: Option<RequestKey>,
    /// The reply to `current` (or the error that ended it), until taken.
    reply: Option<Result<RawResponse, TransportError>>,
    waker: Option<Waker>,
}

struct Shared {
    /// Finds servers, sends in their convention and routes replies (as for `ServiceClient`).
    core: ClientCore<Raw>,
    send_timeout: Duration,
    state: Mutex<State>,
    stop: AtomicBool,
}

/// Wakes a thread parked in [`DdsServiceClient::call_raw`].
struct Unpark(Thread);

impl Wake for Unpark {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

impl Shared {
    fn state(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Sends the unsent request if a server is ready; drops it past the send timeout (then the
    /// reply slot holds `NoServer`). Returns whether it was sent; errors if the write failed.
    fn try_send(&self, state: &mut State) -> Result<bool, TransportError> {
        let Some(unsent) = &state.unsent else {
            return Ok(false);
        };
        let Some(server) = self.core.ready_server() else {
            if unsent.queued.elapsed() >= self.send_timeout {
                state.unsent = None;
                self.complete(state, Err(TransportError::NoServer));
            }
            return Ok(false);
        };
        let Some(unsent) = state.unsent.take() else {
            return Ok(false);
        };
        // No reply deadline: the request is current until replaced (the core's deadline only
        // serves async clients' wake-ups).
        let key = self
            .core
            .send(&unsent.body, server, Instant::now(), None)
            .map_err(TransportError::from)?;
        state.current = Some(key);
        Ok(true)
    }

    /// Moves the current request's reply, once the core routed it, into the reply slot.
    fn collect(&self, state: &mut State) {
        if let Some(result) = state.current.and_then(|key| self.core.take_result(key)) {
            self.complete(state, result.map_err(TransportError::from));
        }
    }

    /// Ends a blocking call at its deadline: `NoServer` if its request was never sent, else
    /// `Timeout` (a reply that still comes is dropped).
    fn abandon(&self) -> TransportError {
        let mut state = self.state();
        state.waker = None;
        if state.unsent.take().is_some() {
            return TransportError::NoServer;
        }
        if let Some(key) = state.current.take() {
            self.core.forget(key);
        }
        TransportError::Timeout
    }

    /// Ends the current request with `outcome` and wakes the waker.
    fn complete(&self, state: &mut State, outcome: Result<RawResponse, TransportError>) {
        if let Some(key) = state.current.take() {
            self.core.forget(key);
        }
        state.reply = Some(outcome);
        if let Some(waker) = state.waker.take() {
            waker.wake();
        }
    }

    /// The reply thread: receives replies, sends queued requests when a server becomes ready,
    /// enforces the send timeout. Woken by replies, by drop, by a request queued with no server
    /// ready and (while one is) by graph changes; otherwise only the send timeout or a server's
    /// settling instant is due.
    fn pump(&self) {
        while !self.stop.load(Ordering::SeqCst) {
            self.core.drain_replies();
            let mut state = self.state();
            self.collect(&mut state);
            if state.unsent.is_some() {
                // Set before looking, so a server appearing after the look wakes us.
                self.core.set_wake_on_graph_change(true);
                if let Err(e) = self.try_send(&mut state) {
                    self.complete(&mut state, Err(e));
                }
            }
            let next = match &state.unsent {
                Some(unsent) => {
                    let timeout_at = unsent.queued + self.send_timeout;
                    Some(match self.core.readiness() {
                        Readiness::NotYet(Some(settles_at)) => settles_at.min(timeout_at),
                        _ => timeout_at,
                    })
                }
                None => {
                    self.core.set_wake_on_graph_change(false);
                    None
                }
            };
            drop(state);
            self.core
                .wait_for_replies(next.map(|t| t.saturating_duration_since(Instant::now())));
        }
    }
}
