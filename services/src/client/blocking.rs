//! [`ServiceClient`]: blocking calls, with retries and an optional-server variant.

use std::sync::Arc;
use std::time::Duration;

use horus_ros_msgs::Service;
use horus_ros_rmw::qos::Qos;

use super::codec::Typed;
use super::core::{client_handle_methods, ClientCore, ClientOptions};
use super::pending::AsyncServiceClient;
use super::responses::Membership;
use crate::{
    EndpointBuilder, EndpointOptions, IntrospectionState, RetryConfig, ServiceError, SetupError,
};

/// Builds a client `C` of service `S`: `build()` gives the client the builder came from
/// ([`ServiceClient::builder`] a [`ServiceClient`], [`AsyncServiceClient::builder`] an
/// [`AsyncServiceClient`]). Node, name, QoS and wire convention are set with the
/// [`EndpointBuilder`] setters; the other setters are the same for both clients.
#[must_use = "a builder does nothing until .build() is called"]
pub struct ServiceClientBuilder<S: Service, C = ServiceClient<S>> {
    options: ClientOptions,
    _client: std::marker::PhantomData<fn() -> (S, C)>,
}

impl<S: Service, C> EndpointBuilder for ServiceClientBuilder<S, C> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options.endpoint
    }
}

impl<S: Service, C> ServiceClientBuilder<S, C> {
    /// A builder of defaults (through [`ServiceClient::builder`] and
    /// [`AsyncServiceClient::builder`]).
    pub(crate) fn new() -> Self {
        Self {
            options: ClientOptions::default(),
            _client: std::marker::PhantomData,
        }
    }

    /// Accepted for the API of poll-based clients, and ignored: a waiting call never wakes on
    /// a timer (replies, a server appearing and the end of its servers wake it at once).
    pub fn poll_interval(self, _interval: Duration) -> Self {
        self
    }

    /// Publishes service introspection events from the start (rclcpp / rclpy
    /// `configure_introspection`); see [`ServiceClient::configure_introspection`].
    pub fn introspection(mut self, state: IntrospectionState, qos: Qos) -> Self {
        self.options.introspection = Some((state, qos));
        self
    }
}

impl<S: Service> ServiceClientBuilder<S, ServiceClient<S>> {
    /// The blocking client.
    pub fn build(self) -> Result<ServiceClient<S>, SetupError> {
        let (core, responses) = ClientCore::new(self.options)?.join_responses()?;
        Ok(ServiceClient { core, responses })
    }
}

impl<S: Service> ServiceClientBuilder<S, AsyncServiceClient<S>> {
    /// The non-blocking client.
    pub fn build(self) -> Result<AsyncServiceClient<S>, SetupError> {
        AsyncServiceClient::from_core(ClientCore::new(self.options)?)
    }
}

/// Calls a service and waits for the reply.
#[must_use = "a client's endpoints exist only while it is held"]
pub struct ServiceClient<S: Service> {
    core: Arc<ClientCore<Typed<S>>>,
    /// Where its calls wait for their replies (see `client::responses`).
    responses: Membership,
}

impl<S: Service> std::fmt::Debug for ServiceClient<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServiceClient")
            .field("name", self.core.name())
            .field("type", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> ServiceClient<S> {
    /// A client of the service's default name on the default node.
    pub fn new() -> Result<Self, SetupError> {
        Self::builder().build()
    }

    /// Like [`new`](Self::new); `interval` is ignored (see
    /// [`ServiceClientBuilder::poll_interval`]).
    pub fn with_poll_interval(interval: Duration) -> Result<Self, SetupError> {
        Self::builder().poll_interval(interval).build()
    }

    /// A builder to choose node, name, QoS, wire convention and introspection; `build()` gives
    /// this client.
    pub fn builder() -> ServiceClientBuilder<S> {
        ServiceClientBuilder::new()
    }

    client_handle_methods!(discovery);

    /// Calls once: waits (within `timeout`) for a server, sends, waits for the reply.
    ///
    /// `NoServer` if no server of this service and type appeared within `timeout`; `Timeout` if
    /// one was there but did not answer in time; `ServiceFailed` if its handler returned `Err`;
    /// `Transport(TransportError::ServerGone)` as soon as every server the request went to has
    /// left the graph; other `Transport` errors if the communication failed.
    pub fn call(
        &mut self,
        request: S::Request,
        timeout: Duration,
    ) -> Result<S::Response, ServiceError> {
        self.core.call_blocking(&self.responses, &request, timeout)
    }

    /// Calls with retries on transient errors ([`ServiceError::is_transient`]: Timeout and
    /// Transport, which includes `TransportError::ServerGone`): 3 retries, backoff 10, 20,
    /// 40 ms; each attempt has the whole `timeout`.
    pub fn call_resilient(
        &mut self,
        request: S::Request,
        timeout: Duration,
    ) -> Result<S::Response, ServiceError> {
        self.call_resilient_with(request, timeout, RetryConfig::default())
    }

    /// Calls with the given retry policy (only transient errors are retried:
    /// [`ServiceError::is_transient`]).
    pub fn call_resilient_with(
        &mut self,
        request: S::Request,
        timeout: Duration,
        retry: RetryConfig,
    ) -> Result<S::Response, ServiceError> {
        let mut attempt = 0;
        loop {
            match self.call(request.clone(), timeout) {
                Err(e) if e.is_transient() && attempt < retry.max_retries => {
                    tracing::debug!(service = %self.name(), attempt, "retrying after: {e}");
                    std::thread::sleep(retry.backoff(attempt));
                    attempt += 1;
                }
                result => return result,
            }
        }
    }

    /// Like [`call`](Self::call), but `Ok(None)` when no server exists.
    pub fn call_optional(
        &mut self,
        request: S::Request,
        timeout: Duration,
    ) -> Result<Option<S::Response>, ServiceError> {
        match self.call(request, timeout) {
            Err(ServiceError::NoServer) => Ok(None),
            result => result.map(Some),
        }
    }

    client_handle_methods!(introspection);

    /// Requests sent whose replies are still awaited (0 between calls: nothing leaks).
    pub fn pending_requests(&self) -> usize {
        self.core.pending_count()
    }
}
