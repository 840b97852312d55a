//! [`ServiceServerBuilder`] and [`ServiceServer`]: a ROS 2 service served from a background thread.

use std::marker::PhantomData;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_msgs::description::EVENT_SUFFIX;
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_msgs::{dds_type_name, Service};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::service::{Request, TakenRequest};
use horus_ros_rmw::{Gid, Node, RawReader, RawReaderWaker, RawWriter};

use crate::cdr::{decode, encode};
use crate::introspection::{encode_event, EventType, Introspection, IntrospectionState};
use crate::naming::{default_service_name, ServiceTopics};
use crate::runtime::Runtime;
use crate::server_wire::ServerWire;
use crate::SetupError;
use crate::WireFlavour;

/// Most samples dropped (undecodable, or no request to answer) in one drain before the thread
/// checks whether to stop.
pub(crate) const MAX_ERRORS_PER_DRAIN: usize = 1000;

type Handler<S> = Box<
    dyn FnMut(<S as Service>::Request) -> Result<<S as Service>::Response, String> + Send + 'static,
>;

/// Builds a [`ServiceServer`]. Setting errors are kept until [`build`](Self::build).
#[must_use = "a builder does nothing until .build() is called"]
pub struct ServiceServerBuilder<S: Service> {
    pub(crate) node: Option<Node>,
    pub(crate) name: Option<String>,
    pub(crate) qos: Qos,
    pub(crate) flavour: Option<WireFlavour>,
    handler: Option<Handler<S>>,
    pub(crate) introspection: Option<(IntrospectionState, Qos)>,
}

impl<S: Service> Default for ServiceServerBuilder<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Service> ServiceServerBuilder<S> {
    /// A builder for the service `S`: default node, name [`default_service_name`], QoS
    /// `services_default`; the server thread wakes on events, never on a timer.
    pub fn new() -> Self {
        Self {
            node: None,
            name: None,
            qos: Qos::services_default(),
            flavour: None,
            handler: None,
            introspection: None,
        }
    }

    /// Serves from `node` instead of the process's default node.
    pub fn node(mut self, node: &Node) -> Self {
        self.node = Some(node.clone());
        self
    }

    /// The service name (relative names, `~` and substitutions expand as in rcl).
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// The QoS of the request reader and reply writer (default: `services_default`).
    pub fn qos(mut self, qos: Qos) -> Self {
        self.qos = qos;
        self
    }

    /// Accepted for the API of poll-based servers, and ignored: the server thread never wakes
    /// on a timer. Requests, [`stop`](ServiceServer::stop), the graph changes a parked reply
    /// waits for and a parked reply's expiry wake it, each at once.
    pub fn poll_interval(self, _interval: Duration) -> Self {
        self
    }

    /// Answers every client with this wire convention instead of choosing per client.
    pub fn wire_flavour(mut self, flavour: WireFlavour) -> Self {
        self.flavour = Some(flavour);
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

    /// Creates the request reader and reply writer and starts serving.
    pub fn build(self) -> Result<ServiceServer<S>, SetupError> {
        let handler = self.handler.ok_or(SetupError::NoHandler)?;
        let runtime = Runtime::for_service::<S>(self.node.as_ref())?;
        let name = self.name.unwrap_or_else(default_service_name::<S>);
        let topics = ServiceTopics::resolve::<S>(
            &runtime.node,
            &name,
            &self.qos,
            horus_ros_rmw::ServiceEndpointRole::Server,
        )?;
        let requests = runtime.node.create_raw_reader(&topics.request)?;
        let replies = runtime.node.create_raw_writer(&topics.reply)?;
        let shared = Arc::new(ServerShared::default());
        let waker = requests.waker();
        let request_reader = requests.gid();
        let reply_writer = replies.gid();
        let introspection = Introspection::new(
            runtime.node.clone(),
            topics.name.clone(),
            Some(EventType {
                dds_type_name: dds_type_name(&format!("{}{EVENT_SUFFIX}", S::TYPE_NAME)),
                type_hash: S::event_type_hash(),
            }),
        );
        if let Some((state, qos)) = &self.introspection {
            introspection.configure(*state, qos)?;
        }
        // Parked replies go out when their client's reader is matched: the graph wakes us.
        let wire = ServerWire::new(
            &runtime,
            topics.name.clone(),
            reply_writer,
            self.flavour,
            waker.clone(),
        );
        let worker = ServerLoop::<S> {
            requests,
            replies,
            wire,
            handler,
            shared: Arc::clone(&shared),
            introspection: Arc::clone(&introspection),
        };
        let thread = std::thread::Builder::new()
            .name(format!("horus-srv{}", topics.name))
            .spawn(move || worker.run())?;
        tracing::debug!(service = %topics.name, "service server started");
        Ok(ServiceServer {
            shared,
            waker,
            thread: Some(thread),
            name: topics.name,
            request_reader,
            reply_writer,
            introspection,
            _node: runtime.node,
            _service: PhantomData,
        })
    }
}

#[derive(Default)]
struct ServerShared {
    stop: AtomicBool,
    served: AtomicU64,
    failed: AtomicU64,
}

/// A running service server; it serves until [`stop`](Self::stop)ped or dropped.
#[must_use = "a server serves only while it is held: dropping it stops serving"]
pub struct ServiceServer<S: Service> {
    shared: Arc<ServerShared>,
    /// Wakes the server thread (to stop it).
    waker: RawReaderWaker,
    thread: Option<JoinHandle<()>>,
    name: ServiceName,
    request_reader: Gid,
    reply_writer: Gid,
    introspection: Arc<Introspection>,
    _node: Node,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for ServiceServer<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServiceServer")
            .field("name", &self.name)
            .field("type", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> ServiceServer<S> {
    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        &self.name
    }

    /// The GIDs of the request reader and the reply writer (as `service info -v` lists them).
    pub fn gids(&self) -> (Gid, Gid) {
        (self.request_reader, self.reply_writer)
    }

    /// Requests answered with a response so far.
    pub fn served_count(&self) -> u64 {
        self.shared.served.load(Ordering::Relaxed)
    }

    /// Requests whose handler failed (returned `Err` or panicked) so far.
    pub fn failed_count(&self) -> u64 {
        self.shared.failed.load(Ordering::Relaxed)
    }

    /// Turns service introspection on or off while serving (rclcpp / rclpy
    /// `configure_introspection`, rcl `rcl_service_configure_service_introspection`): OFF
    /// removes the `<service>/_service_event` publisher; METADATA publishes `REQUEST_RECEIVED` and
    /// `RESPONSE_SENT` events with their `ServiceEventInfo` only, CONTENTS with the request and
    /// the response. The publisher is created with `qos` when there is none; an existing one keeps
    /// its QoS. Events never hold up serving: they go through a bounded queue and are dropped
    /// when it is full.
    pub fn configure_introspection(
        &self,
        state: IntrospectionState,
        qos: &Qos,
    ) -> Result<(), SetupError> {
        self.introspection.configure(state, qos)
    }

    /// The introspection state in force.
    pub fn introspection_state(&self) -> IntrospectionState {
        self.introspection.state()
    }

    /// The GID of the `<service>/_service_event` publisher, while introspection is on.
    pub fn introspection_gid(&self) -> Option<Gid> {
        self.introspection.publisher_gid()
    }

    /// Stops serving; the endpoints leave the graph when the server is dropped.
    pub fn stop(&self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.waker.wake();
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

struct ServerLoop<S: Service> {
    requests: RawReader,
    replies: RawWriter,
    wire: ServerWire,
    handler: Handler<S>,
    shared: Arc<ServerShared>,
    introspection: Arc<Introspection>,
}

impl<S: Service> ServerLoop<S> {
    fn run(mut self) {
        while !self.shared.stop.load(Ordering::SeqCst) {
            let mut errors = 0;
            let drained = loop {
                match self.wire.take_request(&mut self.requests) {
                    TakenRequest::Request(request) => self.serve(request),
                    TakenRequest::Empty => break true,
                    TakenRequest::Dropped => {
                        errors += 1;
                        if errors >= MAX_ERRORS_PER_DRAIN {
                            break false;
                        }
                    }
                }
            };
            // Parked replies whose client can hear them now go out; old ones are dropped.
            let next_expiry = self.wire.flush_parked(&self.replies);
            if !drained {
                // Wake-ups are edge-triggered: what is left would not wake us.
                continue;
            }
            let wait = next_expiry.map(|t| t.saturating_duration_since(Instant::now()));
            // Woken at once by a request, by stop() and by graph changes while replies are
            // parked; with none parked, nothing else can change, so there is no time limit.
            self.requests.wait(wait);
        }
    }

    /// Answers one request in its client's convention: at once if the client's reply reader is
    /// matched, else parked until it is (never waiting here).
    fn serve(&mut self, request: Request) {
        let (outcome, response) = self.handle(&request);
        let Some(mut reply) = self.wire.response(&request.route, outcome) else {
            return;
        };
        // rcl `rcl_send_response`: RESPONSE_SENT once the response is sent.
        if let Some(response) = response {
            if self.introspection.state() != IntrospectionState::Off {
                let introspection = Arc::clone(&self.introspection);
                let (client_gid, sequence_number) =
                    (request.id.writer_guid, request.id.sequence_number);
                reply = reply.on_sent(Box::new(move || {
                    introspection.emit(
                        ServiceEventInfo::RESPONSE_SENT,
                        client_gid,
                        sequence_number,
                        |info, contents| {
                            encode_event::<S::Request, S::Response>(
                                info,
                                contents,
                                None,
                                Some(&response),
                            )
                        },
                    );
                }));
            }
        }
        if let Err(e) = self.wire.send_response(&self.replies, reply) {
            tracing::warn!(service = %self.wire.service(), "could not send a reply: {e}");
        }
    }

    /// Decodes the request, runs the handler (catching panics) and encodes the response; gives
    /// the response too when there is one.
    fn handle(&mut self, request: &Request) -> (Result<Vec<u8>, String>, Option<S::Response>) {
        let decoded = decode::<S::Request>(request.message(), request.big_endian)
            .map_err(|e| format!("malformed request: {e}"));
        let (result, response) = match decoded {
            Err(e) => (Err(e), None),
            Ok(decoded) => {
                // rcl `rcl_take_request_with_info`: REQUEST_RECEIVED once the request is taken.
                self.introspection.emit(
                    ServiceEventInfo::REQUEST_RECEIVED,
                    request.id.writer_guid,
                    request.id.sequence_number,
                    |info, contents| {
                        encode_event::<S::Request, S::Response>(
                            info,
                            contents,
                            Some(&decoded),
                            None,
                        )
                    },
                );
                match catch_unwind(AssertUnwindSafe(|| (self.handler)(decoded))) {
                    Ok(Ok(response)) => match encode(&response) {
                        Ok(body) => (Ok(body), Some(response)),
                        Err(e) => (Err(e.to_string()), None),
                    },
                    Ok(Err(message)) => (Err(message), None),
                    Err(panic) => (
                        Err(format!(
                            "the service handler panicked: {}",
                            panic_message(panic.as_ref())
                        )),
                        None,
                    ),
                }
            }
        };
        let counter = if result.is_ok() {
            &self.shared.served
        } else {
            &self.shared.failed
        };
        counter.fetch_add(1, Ordering::Relaxed);
        (result, response)
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
