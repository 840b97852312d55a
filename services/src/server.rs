//! [`ServiceServerBuilder`] and [`ServiceServer`]: a ROS 2 service served from a background thread.

use std::marker::PhantomData;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_msgs::Service;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::service::Request;

use crate::cdr::decode;
use crate::introspection::IntrospectionState;
use crate::server_core::{server_handle_methods, ServerCore, ServerSettings};
use crate::server_wire::Serve;
use crate::{EndpointBuilder, EndpointOptions, SetupError};

type Handler<S> = Box<
    dyn FnMut(<S as Service>::Request) -> Result<<S as Service>::Response, String> + Send + 'static,
>;

/// Builds a [`ServiceServer`] ([`ServiceServer::builder`]; `ServiceServerBuilder::new()` is the
/// same builder, kept for the services guide). Node, name, QoS and wire convention are set with
/// the [`EndpointBuilder`] setters; setting errors are kept until [`build`](Self::build).
#[must_use = "a builder does nothing until .build() is called"]
pub struct ServiceServerBuilder<S: Service> {
    pub(crate) options: EndpointOptions,
    handler: Option<Handler<S>>,
    pub(crate) introspection: Option<(IntrospectionState, Qos)>,
}

impl<S: Service> Default for ServiceServerBuilder<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Service> EndpointBuilder for ServiceServerBuilder<S> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options
    }
}

impl<S: Service> ServiceServerBuilder<S> {
    /// A builder for the service `S` (the same as [`ServiceServer::builder`]): default node, name
    /// [`default_service_name`](crate::default_service_name), QoS `services_default`; the server
    /// thread wakes on events, never on a timer.
    pub fn new() -> Self {
        Self {
            options: EndpointOptions::default(),
            handler: None,
            introspection: None,
        }
    }

    /// Accepted for the API of poll-based servers, and ignored: the server thread never wakes
    /// on a timer. Requests, [`stop`](ServiceServer::stop), the graph changes a parked reply
    /// waits for and a parked reply's expiry wake it, each at once.
    pub fn poll_interval(self, _interval: Duration) -> Self {
        self
    }

    /// Publishes service introspection events from the start (rclcpp / rclpy
    /// `configure_introspection`): `state` METADATA or CONTENTS creates the
    /// `<service>/_service_event` publisher with `qos` (the Jazzy demos pass the system default
    /// profile). See [`ServiceServer::configure_introspection`].
    pub fn introspection(mut self, state: IntrospectionState, qos: Qos) -> Self {
        self.introspection = Some((state, qos));
        self
    }

    /// The request handler: `Ok(response)` is sent back; `Err(message)` reaches a horus-ros
    /// client as [`ServiceError::ServiceFailed`](crate::ServiceError::ServiceFailed) at once.
    /// ROS 2 services have no error reply, so a ROS client (rclcpp, rclpy) gets no reply and
    /// times out. A panic in the handler is caught and treated as `Err`.
    pub fn on_request<F>(mut self, handler: F) -> Self
    where
        F: FnMut(S::Request) -> Result<S::Response, String> + Send + 'static,
    {
        self.handler = Some(Box::new(handler));
        self
    }

    /// What the server is made from.
    pub(crate) fn settings(&self) -> ServerSettings<'_> {
        ServerSettings {
            options: &self.options,
            introspection: self.introspection.as_ref(),
        }
    }

    /// Creates the request reader and reply writer and starts serving.
    pub fn build(mut self) -> Result<ServiceServer<S>, SetupError> {
        let handler = self.handler.take().ok_or(SetupError::NoHandler)?;
        let (core, requests) = ServerCore::create::<S>(self.settings())?;
        let worker = ServerLoop::<S> {
            handler,
            core: Arc::clone(&core),
        };
        let thread = core.start("horus-srv", requests, worker)?;
        tracing::debug!(service = %core.name(), "service server started");
        Ok(ServiceServer {
            core,
            thread: Some(thread),
            _service: PhantomData,
        })
    }
}

/// A running service server; it serves until [`stop`](Self::stop)ped or dropped.
#[must_use = "a server serves only while it is held: dropping it stops serving"]
pub struct ServiceServer<S: Service> {
    core: Arc<ServerCore>,
    thread: Option<JoinHandle<()>>,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for ServiceServer<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServiceServer")
            .field("name", self.core.name())
            .field("type", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> ServiceServer<S> {
    /// A builder to choose node, name, QoS, wire convention, introspection and the handler.
    pub fn builder() -> ServiceServerBuilder<S> {
        ServiceServerBuilder::new()
    }

    server_handle_methods!();

    /// Stops serving; the endpoints leave the graph when the server is dropped.
    pub fn stop(&self) {
        self.core.stop();
    }
}

impl<S: Service> Drop for ServiceServer<S> {
    fn drop(&mut self) {
        self.stop();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The server thread: runs the handler on each request, in turn.
struct ServerLoop<S: Service> {
    handler: Handler<S>,
    core: Arc<ServerCore>,
}

impl<S: Service> Serve for ServerLoop<S> {
    fn request(&mut self, request: Request) {
        self.serve(request);
    }

    fn drained(&mut self) -> Option<Instant> {
        self.core.flush_parked()
    }
}

impl<S: Service> ServerLoop<S> {
    /// Decodes the request, runs the handler (catching panics) and answers.
    fn serve(&mut self, request: Request) {
        let outcome = match decode::<S::Request>(request.message(), request.big_endian) {
            Err(e) => Err(format!("malformed request: {e}")),
            Ok(decoded) => {
                self.core.received::<S>(&request, &decoded);
                match catch_unwind(AssertUnwindSafe(|| (self.handler)(decoded))) {
                    Ok(outcome) => outcome,
                    Err(panic) => Err(format!(
                        "the service handler panicked: {}",
                        panic_message(panic.as_ref())
                    )),
                }
            }
        };
        self.core.finish::<S>(
            &request.route,
            request.id.writer_guid,
            request.id.sequence_number,
            outcome,
        );
    }
}

/// The text of a panic payload.
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}
