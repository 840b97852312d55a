//! Servers with async handlers: [`AsyncServiceServer::builder`] (or
//! [`ServiceServerBuilder::on_request_async`]) → [`AsyncServiceServerBuilder`] →
//! [`AsyncServiceServer`].

use std::future::Future;
use std::marker::PhantomData;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::pin::Pin;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use futures_util::future::Either;
use futures_util::FutureExt;
use horus_ros_msgs::Service;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::service::Request;
use tokio::runtime::Handle;

use crate::cdr::decode;
use crate::introspection::IntrospectionState;
use crate::server::panic_message;
use crate::server_core::{server_handle_methods, ServerCore};
use crate::server_wire::Serve;
use crate::{EndpointBuilder, EndpointOptions, ServiceServerBuilder, SetupError};

/// How many requests one [`AsyncServiceServer`] handles at once unless told otherwise
/// ([`AsyncServiceServerBuilder::max_in_flight`]).
pub const DEFAULT_MAX_IN_FLIGHT: usize = 256;

type BoxedResponse<S> =
    Pin<Box<dyn Future<Output = Result<<S as Service>::Response, String>> + Send + 'static>>;
type AsyncHandler<S> =
    Arc<dyn Fn(<S as Service>::Request) -> BoxedResponse<S> + Send + Sync + 'static>;

impl<S: Service> ServiceServerBuilder<S> {
    /// Serves with an async handler instead: each request's future runs as a task of a tokio
    /// runtime (the one current at [`build`](AsyncServiceServerBuilder::build), or
    /// [`AsyncServiceServerBuilder::runtime`]), many at once (at most
    /// [`max_in_flight`](AsyncServiceServerBuilder::max_in_flight)). `Ok(response)` is sent
    /// back in the client's wire convention; `Err(message)` and panics reach a horus-ros client
    /// as [`ServiceError::ServiceFailed`](crate::ServiceError::ServiceFailed), as with
    /// [`on_request`](Self::on_request). The settings given so far (node, name, QoS, wire
    /// flavour, introspection) are kept.
    ///
    /// ```no_run
    /// use horus_ros_services::prelude::*;
    ///
    /// #[tokio::main]
    /// async fn main() -> Result<()> {
    ///     let server = ServiceServer::<AddTwoInts>::builder()
    ///         .name("/add_two_ints")
    ///         .on_request_async(|req| async move {
    ///             tokio::task::yield_now().await; // anything async: I/O, other calls, timers
    ///             Ok(AddTwoIntsResponse { sum: req.a + req.b })
    ///         })
    ///         .build()?;
    ///     // Serves until SIGINT or SIGTERM shuts the default node's context down.
    ///     horus_ros_services::default_node()?.context().wait_for_shutdown_async().await;
    ///     drop(server);
    ///     Ok(())
    /// }
    /// ```
    pub fn on_request_async<F, Fut>(self, handler: F) -> AsyncServiceServerBuilder<S>
    where
        F: Fn(S::Request) -> Fut + Send + Sync + 'static,
        Fut: Future<Output = Result<S::Response, String>> + Send + 'static,
    {
        AsyncServiceServerBuilder {
            base: self,
            handler: None,
            runtime: None,
            max_in_flight: DEFAULT_MAX_IN_FLIGHT,
        }
        .on_request(handler)
    }
}

/// Builds an [`AsyncServiceServer`] ([`AsyncServiceServer::builder`], or
/// [`ServiceServerBuilder::on_request_async`] from a server builder). Node, name, QoS and wire
/// convention are set with the [`EndpointBuilder`] setters.
#[must_use = "a builder does nothing until .build() is called"]
pub struct AsyncServiceServerBuilder<S: Service> {
    /// The settings a blocking server would have (endpoint options, introspection).
    base: ServiceServerBuilder<S>,
    handler: Option<AsyncHandler<S>>,
    runtime: Option<Handle>,
    max_in_flight: usize,
}

impl<S: Service> EndpointBuilder for AsyncServiceServerBuilder<S> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        self.base.options_mut()
    }
}

impl<S: Service> std::fmt::Debug for AsyncServiceServerBuilder<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AsyncServiceServerBuilder")
            .field("type", &S::TYPE_NAME)
            .field("max_in_flight", &self.max_in_flight)
            .finish()
    }
}

impl<S: Service> AsyncServiceServerBuilder<S> {
    /// The async request handler: each request's future runs as a task of the tokio runtime;
    /// `Ok(response)` is sent back, `Err(message)` and panics reach a horus-ros client as
    /// [`ServiceError::ServiceFailed`](crate::ServiceError::ServiceFailed) (see
    /// [`ServiceServerBuilder::on_request_async`]).
    pub fn on_request<F, Fut>(mut self, handler: F) -> Self
    where
        F: Fn(S::Request) -> Fut + Send + Sync + 'static,
        Fut: Future<Output = Result<S::Response, String>> + Send + 'static,
    {
        self.handler = Some(Arc::new(move |request| Box::pin(handler(request))));
        self
    }

    /// Publishes service introspection events from the start; see
    /// [`ServiceServerBuilder::introspection`].
    pub fn introspection(mut self, state: IntrospectionState, qos: Qos) -> Self {
        self.base = self.base.introspection(state, qos);
        self
    }

    /// Runs the handlers on this runtime instead of the one current at `build`.
    pub fn runtime(mut self, handle: Handle) -> Self {
        self.runtime = Some(handle);
        self
    }

    /// The most requests handled at once (default [`DEFAULT_MAX_IN_FLIGHT`], at least 1). Beyond
    /// it, requests wait in the DDS reader (whose history keeps at least 4,096 of them) and are
    /// taken as handlers finish; what that history cannot hold is dropped by the DDS layer, as for
    /// any busy server.
    pub fn max_in_flight(mut self, max: usize) -> Self {
        self.max_in_flight = max.max(1);
        self
    }

    /// Creates the request reader and reply writer and starts serving. Fails with
    /// [`SetupError::NoAsyncRuntime`] outside a tokio runtime when no
    /// [`runtime`](Self::runtime) was given.
    pub fn build(self) -> Result<AsyncServiceServer<S>, SetupError> {
        let handler = self.handler.ok_or(SetupError::NoHandler)?;
        let handle = match self.runtime {
            Some(handle) => handle,
            None => Handle::try_current().map_err(|e| SetupError::NoAsyncRuntime(e.to_string()))?,
        };
        let (core, requests) = ServerCore::create::<S>(self.base.settings())?;
        let shared = Arc::new(Shared {
            in_flight: AtomicUsize::new(0),
            peak_in_flight: AtomicUsize::new(0),
            cancel: tokio::sync::watch::Sender::new(false),
        });
        let worker = Dispatcher::<S> {
            work: Work {
                core: Arc::clone(&core),
                shared: Arc::clone(&shared),
            },
            handler,
            handle,
            max_in_flight: self.max_in_flight,
        };
        let thread = core.start("horus-asrv", requests, worker)?;
        tracing::debug!(service = %core.name(), "async service server started");
        Ok(AsyncServiceServer {
            core,
            shared,
            thread: Some(thread),
            max_in_flight: self.max_in_flight,
            _service: PhantomData,
        })
    }
}

/// What the server, its reader thread and its handler tasks share.
struct Shared {
    in_flight: AtomicUsize,
    peak_in_flight: AtomicUsize,
    /// Set when the server goes: the handlers still running are dropped.
    cancel: tokio::sync::watch::Sender<bool>,
}

/// A running server whose handler is async; it serves until [`stop`](Self::stop)ped or dropped.
/// Dropping it aborts the handlers still running (their clients get no reply).
///
/// ```no_run
/// use horus_ros_services::prelude::*;
///
/// fn main() -> Result<()> {
///     // A runtime of its own, passed explicitly (no need to be inside it).
///     let runtime =
///         tokio::runtime::Runtime::new().map_err(horus_ros_services::SetupError::from)?;
///     let server = AsyncServiceServer::<AddTwoInts>::builder()
///         .name("/add_two_ints")
///         .on_request(|req| async move { Ok(AddTwoIntsResponse { sum: req.a + req.b }) })
///         .runtime(runtime.handle().clone())
///         .max_in_flight(32)
///         .build()?;
///     println!("{} handlers running, at most {}", server.in_flight(), server.max_in_flight());
///     Ok(())
/// }
/// ```
#[must_use = "a server serves only while it is held: dropping it stops serving"]
pub struct AsyncServiceServer<S: Service> {
    core: Arc<ServerCore>,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    max_in_flight: usize,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for AsyncServiceServer<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AsyncServiceServer")
            .field("name", self.core.name())
            .field("type", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> AsyncServiceServer<S> {
    /// A builder to choose node, name, QoS, wire convention, introspection, runtime, the most
    /// requests handled at once and the async handler
    /// ([`on_request`](AsyncServiceServerBuilder::on_request)).
    pub fn builder() -> AsyncServiceServerBuilder<S> {
        AsyncServiceServerBuilder {
            base: ServiceServerBuilder::new(),
            handler: None,
            runtime: None,
            max_in_flight: DEFAULT_MAX_IN_FLIGHT,
        }
    }

    server_handle_methods!();

    /// Handlers running now.
    pub fn in_flight(&self) -> usize {
        self.shared.in_flight.load(Ordering::SeqCst)
    }

    /// The most handlers that ever ran at once (never above [`max_in_flight`](Self::max_in_flight)).
    pub fn peak_in_flight(&self) -> usize {
        self.shared.peak_in_flight.load(Ordering::SeqCst)
    }

    /// The most handlers run at once.
    pub fn max_in_flight(&self) -> usize {
        self.max_in_flight
    }

    /// Stops taking requests (handlers running finish); the endpoints leave the graph when the
    /// server is dropped.
    pub fn stop(&self) {
        self.core.stop();
    }
}

impl<S: Service> Drop for AsyncServiceServer<S> {
    fn drop(&mut self) {
        self.stop();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
        self.shared.cancel.send_replace(true);
    }
}

/// What a handler's task needs to answer: shared with the reader thread.
#[derive(Clone)]
struct Work {
    core: Arc<ServerCore>,
    shared: Arc<Shared>,
}

/// The server's reader thread: takes requests while fewer than the bound are in flight and
/// hands each to the runtime; flushes parked replies.
struct Dispatcher<S: Service> {
    work: Work,
    handler: AsyncHandler<S>,
    handle: Handle,
    max_in_flight: usize,
}

/// Counts one handler in flight; dropped when its task ends (finished, aborted, or dropped by a
/// runtime shutting down), it frees the place and wakes the reader thread.
struct InFlight {
    work: Work,
}

impl Drop for InFlight {
    fn drop(&mut self) {
        self.work.shared.in_flight.fetch_sub(1, Ordering::SeqCst);
        self.work.core.wake();
    }
}

impl<S: Service> Serve for Dispatcher<S> {
    /// At the bound, requests stay in the reader: a finishing handler wakes the thread.
    fn has_room(&self) -> bool {
        self.work.shared.in_flight.load(Ordering::SeqCst) < self.max_in_flight
    }

    fn request(&mut self, request: Request) {
        self.dispatch(request);
    }

    fn drained(&mut self) -> Option<Instant> {
        self.work.core.flush_parked()
    }
}

impl<S: Service> Dispatcher<S> {
    /// Decodes one request and starts its handler as a task (a malformed one is answered, or
    /// dropped, here).
    fn dispatch(&mut self, request: Request) {
        let (route, client_gid, sequence) = (
            request.route,
            request.id.writer_guid,
            request.id.sequence_number,
        );
        let decoded = match decode::<S::Request>(request.message(), request.big_endian) {
            Ok(decoded) => decoded,
            Err(e) => {
                self.work.core.finish::<S>(
                    &route,
                    client_gid,
                    sequence,
                    Err(format!("malformed request: {e}")),
                );
                return;
            }
        };
        self.work.core.received::<S>(&request, &decoded);
        let shared = &self.work.shared;
        let now = shared.in_flight.fetch_add(1, Ordering::SeqCst) + 1;
        shared.peak_in_flight.fetch_max(now, Ordering::SeqCst);
        let guard = InFlight {
            work: self.work.clone(),
        };
        let mut cancelled = shared.cancel.subscribe();
        // Making the future runs user code too: a panic there fails this request only.
        let future = catch_unwind(AssertUnwindSafe(|| (self.handler)(decoded)));
        let work = self.work.clone();
        // A runtime shutting down drops the task, and with it the guard.
        self.handle.spawn(async move {
            let _guard = guard;
            let handled = async move {
                match future {
                    Ok(future) => AssertUnwindSafe(future).catch_unwind().await,
                    Err(panic) => Err(panic),
                }
            };
            let gone = async move {
                let _ = cancelled.wait_for(|gone| *gone).await;
            };
            // The server's drop ends the handlers still running (their clients get no reply).
            let Either::Left((outcome, _)) =
                futures_util::future::select(std::pin::pin!(handled), std::pin::pin!(gone)).await
            else {
                return;
            };
            let outcome = outcome.unwrap_or_else(|panic| {
                Err(format!(
                    "the service handler panicked: {}",
                    panic_message(panic.as_ref())
                ))
            });
            work.core.finish::<S>(&route, client_gid, sequence, outcome);
        });
    }
}
