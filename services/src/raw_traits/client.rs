//! [`DdsServiceClient`]: [`ServiceClientTrait`] over DDS, in the server's wire convention.

use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, AtomicI64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::Waker;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_msgs::Service;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node, RawReader, RawSample, RawWriter, SampleId};

use super::{encapsulate_into, le_body, ServiceClientTrait, TransportError};
use crate::client::core::ClientOptions;
use crate::naming::{default_service_name, ServiceTopics};
use crate::runtime::Runtime;
use crate::wire::{client_id, decode, CycloneHeader, WireFlavour, HORUS_CLIENT_MARKER};
use crate::SetupError;

/// Request numbers of rmw_cyclonedds-convention requests (process-wide, like rmw_cyclonedds).
static NEXT_CYCLONE_SEQ: AtomicI64 = AtomicI64::new(1);

/// How long our reply reader must have been matched with an rmw_cyclonedds server's reply writer
/// before a request is sent (as `ServiceClient` does: such a server does not wait for us).
const CYCLONE_MATCH_SETTLE: Duration = Duration::from_millis(100);

/// The default [`send_timeout`](DdsServiceClientBuilder::send_timeout).
const DEFAULT_SEND_TIMEOUT: Duration = Duration::from_secs(10);

/// Longest sleep of the reply thread (bounds drop time and send-timeout detection).
const TICK: Duration = Duration::from_millis(10);

/// Sleep of the reply thread while a request waits for a server (servers appear as graph
/// changes, not reader events).
const UNSENT_TICK: Duration = Duration::from_millis(2);

/// Builds a [`DdsServiceClient`].
#[must_use = "a builder does nothing until .build() is called"]
pub struct DdsServiceClientBuilder<S: Service> {
    options: ClientOptions,
    send_timeout: Duration,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> Default for DdsServiceClientBuilder<S> {
    fn default() -> Self {
        Self {
            options: ClientOptions::default(),
            send_timeout: DEFAULT_SEND_TIMEOUT,
            _service: PhantomData,
        }
    }
}

impl<S: Service> DdsServiceClientBuilder<S> {
    /// Calls from `node` instead of the process's default node.
    pub fn node(mut self, node: &Node) -> Self {
        self.options.node = Some(node.clone());
        self
    }

    /// The service name (default: [`default_service_name`]).
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.options.name = Some(name.into());
        self
    }

    /// The QoS of the request writer and reply reader (default: `services_default`).
    pub fn qos(mut self, qos: Qos) -> Self {
        self.options.qos = qos;
        self
    }

    /// Uses this wire convention instead of the one of the server found.
    pub fn wire_flavour(mut self, flavour: WireFlavour) -> Self {
        self.options.flavour = Some(flavour);
        self
    }

    /// How long a request queued by `send_request_raw` may wait for a ready server before it is
    /// dropped and `try_recv_reply_raw` reports [`TransportError::NoServer`] (default 10 s).
    pub fn send_timeout(mut self, timeout: Duration) -> Self {
        self.send_timeout = timeout;
        self
    }

    /// Creates the request writer and reply reader and starts the reply thread.
    pub fn build(self) -> Result<DdsServiceClient<S>, SetupError> {
        let runtime = Runtime::for_service::<S>(self.options.node.as_ref())?;
        let name = self.options.name.unwrap_or_else(default_service_name::<S>);
        let topics = ServiceTopics::resolve::<S>(&runtime.node, &name, &self.options.qos)?;
        let writer = runtime.node.create_raw_writer(&topics.request)?;
        let reader = runtime.node.create_raw_reader(&topics.reply)?;
        let shared = Arc::new(Shared {
            request_writer: writer.gid(),
            reply_reader: reader.gid(),
            client_id: client_id(writer.gid()),
            runtime,
            name: topics.name,
            type_name: S::TYPE_NAME,
            flavour: self.options.flavour,
            send_timeout: self.send_timeout,
            state: Mutex::new(State {
                writer,
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
                .name(format!("horus-rawcli{}", shared.name))
                .spawn(move || shared.pump(reader))?
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
pub struct DdsServiceClient<S: Service> {
    shared: Arc<Shared>,
    pump: Option<JoinHandle<()>>,
    discovery_deadline: Option<Instant>,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for DdsServiceClient<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DdsServiceClient")
            .field("name", &self.shared.name)
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
        DdsServiceClientBuilder::default()
    }

    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        &self.shared.name
    }

    /// The GIDs of the request writer and the reply reader.
    pub fn gids(&self) -> (Gid, Gid) {
        (self.shared.request_writer, self.shared.reply_reader)
    }
}

impl<S: Service> Drop for DdsServiceClient<S> {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
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
        state.current = None;
        state.reply = None;
        state.unsent = Some(Unsent {
            body,
            queued: Instant::now(),
        });
        self.shared.try_send(&mut state).map(|_sent| ())
    }

    fn try_recv_reply_raw(
        &mut self,
        reply_buf: &mut [u8],
    ) -> Result<Option<usize>, TransportError> {
        let mut state = self.shared.state();
        if let Err(e) = self.shared.try_send(&mut state) {
            state.reply = Some(Err(e));
        }
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
        if self.shared.ready_server().is_some() {
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

    /// Whether a server can take a request now: its request reader and reply writer are known
    /// and matched with our writer and reader (rmw_fastrtps `service_is_ready`).
    fn is_server_ready(&self) -> bool {
        self.shared.ready_server().is_some()
    }

    /// Whether the graph knows a server of this service and type with both its endpoints
    /// (rcl `service_is_available`), matched with ours or not yet.
    fn server_available(&self) -> Result<bool, TransportError> {
        Ok(!self.shared.servers().is_empty())
    }
}

/// A request waiting for a ready server.
struct Unsent {
    /// The CDR_LE body (no encapsulation header, no rmw_cyclonedds header).
    body: Vec<u8>,
    queued: Instant,
}

/// A received reply body.
struct Reply {
    body: Vec<u8>,
    big_endian: bool,
}

/// Identifies the request whose reply is awaited.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct RequestKey {
    flavour: WireFlavour,
    sequence: i64,
}

struct State {
    writer: RawWriter,
    unsent: Option<Unsent>,
    /// The request sent last, until its reply is in.
    current: Option<RequestKey>,
    /// The reply to `current` (or the error that ended it), until taken.
    reply: Option<Result<Reply, TransportError>>,
    waker: Option<Waker>,
}

struct Shared {
    runtime: Runtime,
    name: ServiceName,
    type_name: &'static str,
    request_writer: Gid,
    reply_reader: Gid,
    client_id: u64,
    flavour: Option<WireFlavour>,
    send_timeout: Duration,
    state: Mutex<State>,
    stop: AtomicBool,
}

impl Shared {
    fn state(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// (request reader, reply writer) of each server of this service and type the graph knows
    /// with both endpoints.
    fn servers(&self) -> Vec<(Gid, Gid)> {
        self.runtime
            .graph
            .read(|c| c.servers_info_by_service(self.name.as_str(), false))
            .unwrap_or_default()
            .into_iter()
            .filter(|s| s.service_type == self.type_name && s.endpoint_gids.len() == 2)
            .map(|s| (s.endpoint_gids[0], s.endpoint_gids[1]))
            .collect()
    }

    /// The wire convention of a server usable now, if any (as `ServiceClient` decides it).
    fn ready_server(&self) -> Option<WireFlavour> {
        let graph = &self.runtime.graph;
        self.servers().into_iter().find_map(|(reader, writer)| {
            graph.matched_since(self.request_writer, reader)?;
            let reply_match = graph.matched_since(self.reply_reader, writer)?;
            let flavour = self
                .flavour
                .unwrap_or_else(|| WireFlavour::for_vendor(graph.participant_vendor(reader)));
            let settled =
                flavour != WireFlavour::CycloneDds || reply_match.elapsed() >= CYCLONE_MATCH_SETTLE;
            settled.then_some(flavour)
        })
    }

    /// Sends the unsent request if a server is ready; drops it past the send timeout (then the
    /// reply slot holds `NoServer`). Returns whether it was sent; errors if the write failed.
    fn try_send(&self, state: &mut State) -> Result<bool, TransportError> {
        let Some(unsent) = &state.unsent else {
            return Ok(false);
        };
        let Some(flavour) = self.ready_server() else {
            if unsent.queued.elapsed() >= self.send_timeout {
                state.unsent = None;
                self.complete(state, Err(TransportError::NoServer));
            }
            return Ok(false);
        };
        let Some(unsent) = state.unsent.take() else {
            return Ok(false);
        };
        let key = match flavour {
            WireFlavour::FastRtps => {
                // rmw_fastrtps: related_sample_identity = our reply reader; the marker asks a
                // horus-ros server for error replies.
                let related = SampleId {
                    writer: self.reply_reader,
                    sequence_number: HORUS_CLIENT_MARKER,
                };
                let id = state
                    .writer
                    .write(unsent.body, Some(related), None)
                    .map_err(|e| TransportError::Transport(e.to_string()))?;
                RequestKey {
                    flavour,
                    sequence: id.sequence_number,
                }
            }
            WireFlavour::CycloneDds => {
                let seq = NEXT_CYCLONE_SEQ.fetch_add(1, Ordering::Relaxed);
                let header = CycloneHeader {
                    guid: self.client_id,
                    seq,
                };
                state
                    .writer
                    .write(header.prepend(&unsent.body), None, None)
                    .map_err(|e| TransportError::Transport(e.to_string()))?;
                RequestKey {
                    flavour,
                    sequence: seq,
                }
            }
        };
        state.current = Some(key);
        Ok(true)
    }

    /// Ends the current request with `outcome` and wakes the waker.
    fn complete(&self, state: &mut State, outcome: Result<Reply, TransportError>) {
        state.current = None;
        state.reply = Some(outcome);
        if let Some(waker) = state.waker.take() {
            waker.wake();
        }
    }

    /// The reply thread: receives replies, sends queued requests when a server becomes ready,
    /// enforces the send timeout.
    fn pump(&self, mut reader: RawReader) {
        while !self.stop.load(Ordering::SeqCst) {
            let tick = if self.state().unsent.is_some() {
                UNSENT_TICK
            } else {
                TICK
            };
            reader.wait(tick);
            loop {
                match reader.take() {
                    Ok(Some(sample)) => self.route(sample),
                    Ok(None) => break,
                    Err(e) => tracing::debug!(service = %self.name, "dropped a reply: {e}"),
                }
            }
            let mut state = self.state();
            if state.unsent.is_some() {
                if let Err(e) = self.try_send(&mut state) {
                    self.complete(&mut state, Err(e));
                }
            }
        }
    }

    /// Stores a reply if it answers the current request; drops it otherwise.
    fn route(&self, sample: RawSample) {
        let (key, outcome) = match sample.related {
            Some(related) => {
                // rmw_fastrtps `__rmw_take_response`: ours iff the related GUID is our reader or writer.
                if related.writer != self.reply_reader && related.writer != self.request_writer {
                    return;
                }
                let flavour = WireFlavour::FastRtps;
                if related.sequence_number < 0 {
                    // A horus-ros server's error reply: the handler's message as a CDR string.
                    let message = decode::<String>(&sample.body, sample.big_endian)
                        .unwrap_or_else(|_| "the service handler failed".to_owned());
                    let sequence = related.sequence_number.saturating_neg();
                    (
                        RequestKey { flavour, sequence },
                        Err(TransportError::ServiceFailed(message)),
                    )
                } else {
                    let key = RequestKey {
                        flavour,
                        sequence: related.sequence_number,
                    };
                    let reply = Reply {
                        body: sample.body,
                        big_endian: sample.big_endian,
                    };
                    (key, Ok(reply))
                }
            }
            None => {
                // rmw_cyclonedds `rmw_take_response`: ours iff the header carries our id.
                let Some((header, message)) = CycloneHeader::split(&sample.body, sample.big_endian)
                else {
                    return;
                };
                if header.guid != self.client_id {
                    return;
                }
                let key = RequestKey {
                    flavour: WireFlavour::CycloneDds,
                    sequence: header.seq,
                };
                // The header is 16 bytes, so the message keeps its 8-byte alignment.
                let reply = Reply {
                    body: message.to_vec(),
                    big_endian: sample.big_endian,
                };
                (key, Ok(reply))
            }
        };
        let mut state = self.state();
        if state.current == Some(key) {
            self.complete(&mut state, outcome);
        }
    }
}
