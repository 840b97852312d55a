//! [`ServiceServerBuilder`] and [`ServiceServer`]: a ROS 2 service served from a background thread.

use std::marker::PhantomData;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_msgs::Service;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node, RawReader, RawSample, RawWriter, SampleId};

use crate::naming::{default_service_name, ServiceTopics};
use crate::runtime::Runtime;
use crate::wire::{decode, encode, is_reader, CycloneHeader, WireFlavour, HORUS_CLIENT_MARKER};
use crate::SetupError;

/// The default [`poll_interval`](ServiceServerBuilder::poll_interval).
pub const DEFAULT_POLL_INTERVAL: Duration = Duration::from_millis(5);

/// How long a reply waits for the client's reply reader to be matched before it is sent anyway
/// (rmw_fastrtps and rmw_cyclonedds wait too, so that a fresh client's first reply is not lost).
const REPLY_MATCH_WAIT: Duration = Duration::from_millis(500);

/// Most undecodable samples skipped in one drain before the thread checks whether to stop.
const MAX_ERRORS_PER_DRAIN: usize = 1000;

type Handler<S> = Box<
    dyn FnMut(<S as Service>::Request) -> Result<<S as Service>::Response, String> + Send + 'static,
>;

/// Builds a [`ServiceServer`]. Setting errors are kept until [`build`](Self::build).
#[must_use = "a builder does nothing until .build() is called"]
pub struct ServiceServerBuilder<S: Service> {
    node: Option<Node>,
    name: Option<String>,
    qos: Qos,
    poll_interval: Duration,
    flavour: Option<WireFlavour>,
    handler: Option<Handler<S>>,
}

impl<S: Service> Default for ServiceServerBuilder<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Service> ServiceServerBuilder<S> {
    /// A builder for the service `S`: default node, name [`default_service_name`], QoS
    /// `services_default`, poll interval 5 ms.
    pub fn new() -> Self {
        Self {
            node: None,
            name: None,
            qos: Qos::services_default(),
            poll_interval: DEFAULT_POLL_INTERVAL,
            flavour: None,
            handler: None,
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

    /// The longest the server thread sleeps between checks: requests wake it at once (no fixed
    /// polling delay); this bounds how long `stop()` and a missed wake-up can take.
    pub fn poll_interval(mut self, interval: Duration) -> Self {
        self.poll_interval = interval.max(Duration::from_micros(100));
        self
    }

    /// Answers every client with this wire convention instead of choosing per client.
    pub fn wire_flavour(mut self, flavour: WireFlavour) -> Self {
        self.flavour = Some(flavour);
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
        let topics = ServiceTopics::resolve::<S>(&runtime.node, &name, &self.qos)?;
        let requests = runtime.node.create_raw_reader(&topics.request)?;
        let replies = runtime.node.create_raw_writer(&topics.reply)?;
        let shared = Arc::new(ServerShared::default());
        let request_reader = requests.gid();
        let reply_writer = replies.gid();
        let worker = ServerLoop::<S> {
            requests,
            replies,
            graph: Arc::clone(&runtime.graph),
            service: topics.name.clone(),
            reply_topic: topics.reply.dds_topic_name.clone(),
            handler,
            flavour: self.flavour,
            poll_interval: self.poll_interval,
            shared: Arc::clone(&shared),
        };
        let thread = std::thread::Builder::new()
            .name(format!("horus-srv{}", topics.name))
            .spawn(move || worker.run())?;
        tracing::debug!(service = %topics.name, "service server started");
        Ok(ServiceServer {
            shared,
            thread: Some(thread),
            name: topics.name,
            request_reader,
            reply_writer,
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
pub struct ServiceServer<S: Service> {
    shared: Arc<ServerShared>,
    thread: Option<JoinHandle<()>>,
    name: ServiceName,
    request_reader: Gid,
    reply_writer: Gid,
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

    /// Stops serving; the endpoints leave the graph when the server is dropped.
    pub fn stop(&self) {
        self.shared.stop.store(true, Ordering::SeqCst);
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
    graph: Arc<Graph>,
    service: ServiceName,
    /// The DDS reply topic (`rr/…Reply`).
    reply_topic: String,
    handler: Handler<S>,
    flavour: Option<WireFlavour>,
    poll_interval: Duration,
    shared: Arc<ServerShared>,
}

impl<S: Service> ServerLoop<S> {
    fn run(mut self) {
        while !self.shared.stop.load(Ordering::SeqCst) {
            let mut errors = 0;
            loop {
                match self.requests.take() {
                    Ok(Some(sample)) => self.serve(sample),
                    Ok(None) => break,
                    Err(e) => {
                        tracing::warn!(service = %self.service, "dropped a request: {e}");
                        errors += 1;
                        if errors >= MAX_ERRORS_PER_DRAIN {
                            break;
                        }
                    }
                }
            }
            // Woken at once by a request; the interval only bounds stop() and missed wake-ups.
            self.requests.wait(self.poll_interval);
        }
    }

    fn serve(&mut self, sample: RawSample) {
        let flavour = self.flavour.unwrap_or_else(|| {
            WireFlavour::for_vendor(self.graph.participant_vendor(sample.id.writer))
        });
        match flavour {
            WireFlavour::CycloneDds => self.serve_cyclone(sample),
            WireFlavour::FastRtps => self.serve_fastrtps(sample),
        }
    }

    /// rmw_cyclonedds: echo the request header in front of the response.
    fn serve_cyclone(&mut self, sample: RawSample) {
        let Some((header, message)) = CycloneHeader::split(&sample.body, sample.big_endian) else {
            tracing::warn!(service = %self.service, "request shorter than rmw_cyclonedds' header; dropped");
            return;
        };
        match self.handle(message, sample.big_endian) {
            Ok(body) => {
                self.wait_for_client_reader_of(sample.id.writer);
                if let Err(e) = self.replies.write(header.prepend(&body), None, None) {
                    tracing::warn!(service = %self.service, "could not send a reply: {e}");
                }
            }
            Err(message) => tracing::warn!(
                service = %self.service,
                "handler failed for an rmw_cyclonedds client, which gets no reply: {message}"
            ),
        }
    }

    /// rmw_fastrtps (and horus-ros clients): reply with related_sample_identity = request id.
    fn serve_fastrtps(&mut self, sample: RawSample) {
        let reply_to = match sample.related {
            Some(r) if r.writer != Gid::default() => r.writer,
            _ => sample.id.writer,
        };
        let horus_client = sample
            .related
            .is_some_and(|r| r.sequence_number == HORUS_CLIENT_MARKER);
        let outcome = self.handle(&sample.body, sample.big_endian);
        let only_to = (is_reader(reply_to)
            && self
                .graph
                .wait_for_match(self.replies.gid(), reply_to, REPLY_MATCH_WAIT))
        .then_some(reply_to);
        let (body, sequence_number) = match outcome {
            Ok(body) => (body, sample.id.sequence_number),
            // The error reply: the request's sequence number negated, the message as a CDR string.
            Err(message) if horus_client => match encode(&message) {
                Ok(body) => (body, -sample.id.sequence_number),
                Err(e) => {
                    tracing::warn!(service = %self.service, "could not encode an error reply: {e}");
                    return;
                }
            },
            Err(message) => {
                tracing::warn!(service = %self.service, "handler failed; a ROS client gets no reply: {message}");
                return;
            }
        };
        let related = SampleId {
            writer: reply_to,
            sequence_number,
        };
        if let Err(e) = self.replies.write(body, Some(related), only_to) {
            tracing::warn!(service = %self.service, "could not send a reply: {e}");
        }
    }

    /// Decodes the request, runs the handler (catching panics) and encodes the response.
    fn handle(&mut self, body: &[u8], big_endian: bool) -> Result<Vec<u8>, String> {
        let result = decode::<S::Request>(body, big_endian)
            .map_err(|e| format!("malformed request: {e}"))
            .and_then(
                |request| match catch_unwind(AssertUnwindSafe(|| (self.handler)(request))) {
                    Ok(Ok(response)) => encode(&response).map_err(|e| e.to_string()),
                    Ok(Err(message)) => Err(message),
                    Err(panic) => Err(format!(
                        "the service handler panicked: {}",
                        panic_message(panic.as_ref())
                    )),
                },
            );
        let counter = if result.is_ok() {
            &self.shared.served
        } else {
            &self.shared.failed
        };
        counter.fetch_add(1, Ordering::Relaxed);
        result
    }

    /// rmw_cyclonedds clients are identified by a header id, not a GUID: wait for the reply
    /// reader(s) of the requesting participant on our reply topic, as far as the graph shows them.
    fn wait_for_client_reader_of(&mut self, request_writer: Gid) {
        let prefix = request_writer.prefix();
        let writer = self.replies.gid();
        let deadline = Instant::now() + REPLY_MATCH_WAIT;
        loop {
            // Readers of our reply topic in the requesting participant (its node may not be
            // known yet: look at the DDS topic, not at clients by node).
            let matched = self
                .graph
                .read(|c| c.subscriptions_info_by_topic(&self.reply_topic, true))
                .iter()
                .filter(|r| r.endpoint_gid.prefix() == prefix)
                .any(|r| self.graph.is_matched(writer, r.endpoint_gid));
            let now = Instant::now();
            if matched || now >= deadline {
                return;
            }
            self.graph
                .wait_for_graph_change((deadline - now).min(Duration::from_millis(10)));
        }
    }
}

/// The text of a panic payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}
