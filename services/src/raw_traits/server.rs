//! [`DdsServiceServer`]: [`ServiceServerTrait`] over DDS, answering each client in its own wire
//! convention.

use std::collections::{BTreeMap, VecDeque};
use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::Waker;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use horus_ros_msgs::Service;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node, RawReader, RawSample, RawWriter, SampleId};

use super::{encapsulate_into, le_body, ServiceRequest, ServiceServerTrait, TransportError};
use crate::naming::{default_service_name, ServiceTopics};
use crate::runtime::Runtime;
use crate::wire::{is_reader, CycloneHeader, WireFlavour};
use crate::SetupError;

/// How long a reply waits for the client's reply reader to be matched before it is sent anyway
/// (as `ServiceServer`, rmw_fastrtps and rmw_cyclonedds do, so a fresh client's first reply is
/// not lost). The wait happens in the background: `send_reply` never blocks.
const REPLY_MATCH_WAIT: Duration = Duration::from_millis(500);

/// Longest sleep of the request thread (bounds drop time).
const TICK: Duration = Duration::from_millis(10);

/// Sleep of the request thread while replies wait for their client's reader to match.
const DEFERRED_TICK: Duration = Duration::from_millis(1);

/// Most requests received and not yet taken; beyond, the oldest is dropped.
const MAX_QUEUED: usize = 4096;

/// Most requests taken and not yet answered; beyond, the oldest is forgotten (its
/// `send_reply` then fails with `UnknownRequest`).
const MAX_OUTSTANDING: usize = 4096;

/// Most undecodable samples skipped in one drain before the thread checks whether to stop.
const MAX_ERRORS_PER_DRAIN: usize = 1000;

/// Builds a [`DdsServiceServer`].
#[must_use = "a builder does nothing until .build() is called"]
pub struct DdsServiceServerBuilder<S: Service> {
    node: Option<Node>,
    name: Option<String>,
    qos: Qos,
    flavour: Option<WireFlavour>,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> Default for DdsServiceServerBuilder<S> {
    fn default() -> Self {
        Self {
            node: None,
            name: None,
            qos: Qos::services_default(),
            flavour: None,
            _service: PhantomData,
        }
    }
}

impl<S: Service> DdsServiceServerBuilder<S> {
    /// Serves from `node` instead of the process's default node.
    pub fn node(mut self, node: &Node) -> Self {
        self.node = Some(node.clone());
        self
    }

    /// The service name (default: [`default_service_name`]).
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// The QoS of the request reader and reply writer (default: `services_default`).
    pub fn qos(mut self, qos: Qos) -> Self {
        self.qos = qos;
        self
    }

    /// Treats every client as following this wire convention instead of choosing per client
    /// from its DDS vendor.
    pub fn wire_flavour(mut self, flavour: WireFlavour) -> Self {
        self.flavour = Some(flavour);
        self
    }

    /// Creates the request reader and reply writer and starts the request thread.
    pub fn build(self) -> Result<DdsServiceServer<S>, SetupError> {
        let runtime = Runtime::for_service::<S>(self.node.as_ref())?;
        let name = self.name.unwrap_or_else(default_service_name::<S>);
        let topics = ServiceTopics::resolve::<S>(&runtime.node, &name, &self.qos)?;
        let reader = runtime.node.create_raw_reader(&topics.request)?;
        let writer = runtime.node.create_raw_writer(&topics.reply)?;
        let shared = Arc::new(Shared {
            request_reader: reader.gid(),
            reply_writer: writer.gid(),
            runtime,
            name: topics.name,
            flavour: self.flavour,
            queue: Mutex::new(VecDeque::new()),
            waker: Mutex::new(None),
            replies: Mutex::new(Replies {
                writer,
                deferred: VecDeque::new(),
            }),
            stop: AtomicBool::new(false),
        });
        let pump = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name(format!("horus-rawsrv{}", shared.name))
                .spawn(move || shared.pump(reader))?
        };
        Ok(DdsServiceServer {
            shared,
            pump: Some(pump),
            next_sequence: 1,
            outstanding: BTreeMap::new(),
            _service: PhantomData,
        })
    }
}

/// A [`ServiceServerTrait`] server over DDS: serves horus-ros, rmw_fastrtps_cpp and
/// rmw_cyclonedds_cpp clients at once, each in its own wire convention (from its DDS vendor).
///
/// - A background thread receives requests into a queue and wakes the
///   [registered](ServiceServerTrait::register_waker) waker; `has_request` looks at that queue.
/// - `try_recv_request` gives the request message (CDR with encapsulation header; an
///   rmw_cyclonedds request header is stripped) and a `sequence_number` local to this server
///   (1, 2, 3…): DDS sequence numbers are per client writer and would collide between clients.
///   The server keeps, per number, what the reply needs: the `related_sample_identity` of an
///   rmw_fastrtps-convention request, or the header of an rmw_cyclonedds one.
/// - `send_reply` never blocks: if the client's reply reader is not matched yet, the reply
///   waits (at most 500 ms, in the background) and is then sent.
/// - Requests taken but never answered are forgotten beyond 4096 outstanding (oldest first).
pub struct DdsServiceServer<S: Service> {
    shared: Arc<Shared>,
    pump: Option<JoinHandle<()>>,
    next_sequence: i64,
    outstanding: BTreeMap<i64, Route>,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for DdsServiceServer<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DdsServiceServer")
            .field("name", &self.shared.name)
            .field("type", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> DdsServiceServer<S> {
    /// A server of the service's default name on the default node.
    pub fn new() -> Result<Self, SetupError> {
        Self::builder().build()
    }

    /// A builder to choose node, name, QoS and wire convention.
    pub fn builder() -> DdsServiceServerBuilder<S> {
        DdsServiceServerBuilder::default()
    }

    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        &self.shared.name
    }

    /// The GIDs of the request reader and the reply writer.
    pub fn gids(&self) -> (Gid, Gid) {
        (self.shared.request_reader, self.shared.reply_writer)
    }

    /// Requests taken and not answered yet.
    pub fn outstanding_requests(&self) -> usize {
        self.outstanding.len()
    }
}

impl<S: Service> Drop for DdsServiceServer<S> {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        if let Some(pump) = self.pump.take() {
            let _ = pump.join();
        }
    }
}

impl<S: Service> ServiceServerTrait for DdsServiceServer<S> {
    type Error = TransportError;

    /// Takes the oldest request. If it does not fit `buf`, it stays queued and
    /// [`TransportError::BufferTooSmall`] says how much room it needs.
    fn try_recv_request<'a>(
        &mut self,
        buf: &'a mut [u8],
    ) -> Result<Option<ServiceRequest<'a>>, TransportError> {
        let Some(incoming) = self.shared.queue().pop_front() else {
            return Ok(None);
        };
        let message = incoming.body.get(incoming.offset..).unwrap_or_default();
        let len = match encapsulate_into(message, incoming.big_endian, buf) {
            Ok(len) => len,
            Err(e) => {
                self.shared.queue().push_front(incoming);
                return Err(e);
            }
        };
        let sequence_number = self.next_sequence;
        self.next_sequence += 1;
        self.outstanding.insert(sequence_number, incoming.route);
        while self.outstanding.len() > MAX_OUTSTANDING {
            self.outstanding.pop_first();
        }
        Ok(Some(ServiceRequest {
            sequence_number,
            data: &buf[..len],
        }))
    }

    /// Replies to request `sequence_number` in its client's convention; `UnknownRequest` if no
    /// such request is outstanding (a request is answered at most once).
    fn send_reply(&mut self, sequence_number: i64, data: &[u8]) -> Result<(), TransportError> {
        let route = *self
            .outstanding
            .get(&sequence_number)
            .ok_or(TransportError::UnknownRequest(sequence_number))?;
        let body = le_body::<S::Response>(data)?;
        self.outstanding.remove(&sequence_number);
        let deadline = Instant::now() + REPLY_MATCH_WAIT;
        let reply = match route {
            Route::FastRtps {
                reply_to,
                sequence_number,
            } => {
                let reader = is_reader(reply_to).then_some(reply_to);
                Deferred {
                    body: body.into_owned(),
                    related: Some(SampleId {
                        writer: reply_to,
                        sequence_number,
                    }),
                    reader,
                    wait_for: reader.into_iter().collect(),
                    deadline,
                }
            }
            Route::CycloneDds {
                header,
                request_writer,
            } => Deferred {
                body: header.prepend(&body),
                related: None,
                reader: None,
                wait_for: self.shared.client_readers_of(request_writer),
                deadline,
            },
        };
        let mut replies = self.shared.replies();
        if replies.deferred.is_empty() && self.shared.can_send(&reply) {
            self.shared.write(&replies.writer, reply)
        } else {
            replies.deferred.push_back(reply);
            Ok(())
        }
    }

    /// Whether a received request is waiting (non-destructive).
    fn has_request(&self) -> bool {
        !self.shared.queue().is_empty()
    }

    /// Wakes `waker` once, when the next request arrives; at once if one is waiting.
    fn register_waker(&self, waker: &Waker) {
        *self.shared.waker() = Some(waker.clone());
        if self.has_request() {
            if let Some(w) = self.shared.waker().take() {
                w.wake();
            }
        }
    }
}

/// What a reply to one request needs.
#[derive(Clone, Copy, Debug)]
enum Route {
    /// rmw_fastrtps: reply with related_sample_identity = {reply_to, sequence_number}.
    FastRtps { reply_to: Gid, sequence_number: i64 },
    /// rmw_cyclonedds: echo the header; the client's readers are found from its writer.
    CycloneDds {
        header: CycloneHeader,
        request_writer: Gid,
    },
}

/// A received request: its body (message from `offset` on) and how to answer it.
struct Incoming {
    route: Route,
    body: Vec<u8>,
    offset: usize,
    big_endian: bool,
}

/// A reply ready to write once its client's reply reader(s) are matched (or at `deadline`).
struct Deferred {
    body: Vec<u8>,
    related: Option<SampleId>,
    /// The one reader to send to, once matched (rmw_fastrtps convention).
    reader: Option<Gid>,
    wait_for: Vec<Gid>,
    deadline: Instant,
}

struct Replies {
    writer: RawWriter,
    deferred: VecDeque<Deferred>,
}

struct Shared {
    runtime: Runtime,
    name: ServiceName,
    request_reader: Gid,
    reply_writer: Gid,
    flavour: Option<WireFlavour>,
    queue: Mutex<VecDeque<Incoming>>,
    waker: Mutex<Option<Waker>>,
    replies: Mutex<Replies>,
    stop: AtomicBool,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Shared {
    fn queue(&self) -> MutexGuard<'_, VecDeque<Incoming>> {
        lock(&self.queue)
    }

    fn waker(&self) -> MutexGuard<'_, Option<Waker>> {
        lock(&self.waker)
    }

    fn replies(&self) -> MutexGuard<'_, Replies> {
        lock(&self.replies)
    }

    /// The request thread: queues requests, wakes the waker, sends deferred replies.
    fn pump(&self, mut reader: RawReader) {
        while !self.stop.load(Ordering::SeqCst) {
            let tick = if self.replies().deferred.is_empty() {
                TICK
            } else {
                DEFERRED_TICK
            };
            reader.wait(tick);
            let mut arrived = false;
            let mut errors = 0;
            loop {
                match reader.take() {
                    Ok(Some(sample)) => {
                        if let Some(incoming) = self.prepare(sample) {
                            let mut queue = self.queue();
                            if queue.len() >= MAX_QUEUED {
                                queue.pop_front();
                                tracing::warn!(service = %self.name, "request queue full: dropped the oldest request");
                            }
                            queue.push_back(incoming);
                            arrived = true;
                        }
                    }
                    Ok(None) => break,
                    Err(e) => {
                        tracing::warn!(service = %self.name, "dropped a request: {e}");
                        errors += 1;
                        if errors >= MAX_ERRORS_PER_DRAIN {
                            break;
                        }
                    }
                }
            }
            if arrived {
                let waker = self.waker().take();
                if let Some(w) = waker {
                    w.wake();
                }
            }
            self.flush();
        }
    }

    /// Reads the correlation data of a request in its client's convention.
    fn prepare(&self, sample: RawSample) -> Option<Incoming> {
        let flavour = self.flavour.unwrap_or_else(|| {
            WireFlavour::for_vendor(self.runtime.graph.participant_vendor(sample.id.writer))
        });
        let (route, offset) = match flavour {
            WireFlavour::CycloneDds => {
                let Some((header, message)) = CycloneHeader::split(&sample.body, sample.big_endian)
                else {
                    tracing::warn!(service = %self.name, "request shorter than rmw_cyclonedds' header; dropped");
                    return None;
                };
                // 16 header bytes: the message keeps its 8-byte alignment.
                let route = Route::CycloneDds {
                    header,
                    request_writer: sample.id.writer,
                };
                (route, sample.body.len() - message.len())
            }
            WireFlavour::FastRtps => {
                // rmw_fastrtps `__rmw_take_request`: the request id is the sample identity, with
                // the writer replaced by the related_sample_identity's GUID when given.
                let reply_to = match sample.related {
                    Some(r) if r.writer != Gid::default() => r.writer,
                    _ => sample.id.writer,
                };
                let route = Route::FastRtps {
                    reply_to,
                    sequence_number: sample.id.sequence_number,
                };
                (route, 0)
            }
        };
        Some(Incoming {
            route,
            body: sample.body,
            offset,
            big_endian: sample.big_endian,
        })
    }

    /// The reply readers of the participant of an rmw_cyclonedds client's request writer, as far
    /// as the graph shows them (its header carries no GUID).
    fn client_readers_of(&self, request_writer: Gid) -> Vec<Gid> {
        let prefix = request_writer.prefix();
        self.runtime
            .graph
            .read(|c| c.clients_info_by_service(self.name.as_str(), false))
            .unwrap_or_default()
            .into_iter()
            .filter_map(|client| client.endpoint_gids.first().copied())
            .filter(|gid| gid.prefix() == prefix)
            .collect()
    }

    /// Whether a reply can go now: its client's readers are matched, or it waited long enough.
    fn can_send(&self, reply: &Deferred) -> bool {
        Instant::now() >= reply.deadline
            || reply
                .wait_for
                .iter()
                .all(|r| self.runtime.graph.is_matched(self.reply_writer, *r))
    }

    /// Writes a reply (to its one reader if that is matched, else to all: clients filter).
    fn write(&self, writer: &RawWriter, reply: Deferred) -> Result<(), TransportError> {
        let only_to = reply
            .reader
            .filter(|r| self.runtime.graph.is_matched(self.reply_writer, *r));
        writer
            .write(reply.body, reply.related, only_to)
            .map(|_id| ())
            .map_err(|e| TransportError::Transport(e.to_string()))
    }

    /// Sends the deferred replies that can go now.
    fn flush(&self) {
        let mut replies = self.replies();
        if replies.deferred.is_empty() {
            return;
        }
        let waiting = std::mem::take(&mut replies.deferred);
        for reply in waiting {
            if self.can_send(&reply) {
                if let Err(e) = self.write(&replies.writer, reply) {
                    tracing::warn!(service = %self.name, "could not send a reply: {e}");
                }
            } else {
                replies.deferred.push_back(reply);
            }
        }
    }
}
