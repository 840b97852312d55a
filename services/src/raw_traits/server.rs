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
use horus_ros_rmw::service::{ReplyRoute, Request};
use horus_ros_rmw::{Gid, RawReader, RawReaderWaker, RawWriter};

use super::{encapsulate_into, le_body, ServiceRequest, ServiceServerTrait, TransportError};
use crate::runtime::Runtime;
use crate::server_core::ServerEndpoints;
use crate::server_wire::{Serve, ServerWire};
use crate::{EndpointBuilder, EndpointOptions, SetupError};

/// Most requests received and not yet taken; beyond, the oldest is dropped.
const MAX_QUEUED: usize = 4096;
/// At most one warning about requests dropped at [`MAX_QUEUED`] per interval (the interval of
/// rmw's warnings about peers).
const OVERFLOW_WARNING_INTERVAL: Duration = Duration::from_secs(10);

/// Most requests taken and not yet answered; beyond, the oldest is forgotten (its
/// `send_reply` then fails with `UnknownRequest`).
const MAX_OUTSTANDING: usize = 4096;

/// Builds a [`DdsServiceServer`] ([`DdsServiceServer::builder`]). Node, name, QoS and wire
/// convention are set with the [`EndpointBuilder`] setters.
#[must_use = "a builder does nothing until .build() is called"]
pub struct DdsServiceServerBuilder<S: Service> {
    options: EndpointOptions,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> EndpointBuilder for DdsServiceServerBuilder<S> {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options
    }
}

impl<S: Service> DdsServiceServerBuilder<S> {
    /// Creates the request reader and reply writer and starts the request thread.
    pub fn build(self) -> Result<DdsServiceServer<S>, SetupError> {
        let ServerEndpoints {
            runtime,
            requests: reader,
            replies: writer,
            wire,
            ..
        } = ServerEndpoints::create::<S>(&self.options)?;
        let shared = Arc::new(Shared {
            request_reader: reader.gid(),
            reply_writer: writer.gid(),
            wire,
            _runtime: runtime,
            queue: Mutex::new(VecDeque::new()),
            waker: Mutex::new(None),
            writer: Mutex::new(writer),
            pump_waker: reader.waker(),
            stop: AtomicBool::new(false),
        });
        let pump = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name(format!("horus-rawsrv{}", shared.wire.service()))
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
/// - `send_reply` never blocks: if the client's reply reader is not matched yet, the reply is
///   parked (bounded per client) and sent by the background thread once it is, or dropped after
///   5 s.
/// - Requests taken but never answered are forgotten beyond 4096 outstanding (oldest first).
#[must_use = "a server's endpoints exist only while it is held"]
pub struct DdsServiceServer<S: Service> {
    shared: Arc<Shared>,
    pump: Option<JoinHandle<()>>,
    next_sequence: i64,
    outstanding: BTreeMap<i64, ReplyRoute>,
    _service: PhantomData<fn() -> S>,
}

impl<S: Service> std::fmt::Debug for DdsServiceServer<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DdsServiceServer")
            .field("name", self.shared.wire.service())
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
        DdsServiceServerBuilder {
            options: EndpointOptions::default(),
            _service: PhantomData,
        }
    }

    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        self.shared.wire.service()
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
        self.shared.pump_waker.wake();
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
        let Some(request) = self.shared.queue().pop_front() else {
            return Ok(None);
        };
        let len = match encapsulate_into(request.message(), request.big_endian, buf) {
            Ok(len) => len,
            Err(e) => {
                self.shared.queue().push_front(request);
                return Err(e);
            }
        };
        let sequence_number = self.next_sequence;
        self.next_sequence += 1;
        self.outstanding.insert(sequence_number, request.route);
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
        let Some(reply) = self.shared.wire.response(&route, Ok(body.into_owned())) else {
            return Ok(());
        };
        let writer = lock(&self.shared.writer);
        let result = self.shared.wire.send_response(&writer, reply);
        drop(writer);
        if self.shared.wire.parked() > 0 {
            // The request thread sends it once the client's reader is matched.
            self.shared.pump_waker.wake();
        }
        result.map_err(|e| TransportError::Send(e.to_string()))
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

/// The request thread's state between drains (see [`Shared::pump`]).
struct Pump<'a> {
    shared: &'a Shared,
    /// Requests dropped at the queue's bound since the last warning.
    overflowed: u64,
    /// When that warning was.
    warned_at: Option<Instant>,
    /// Whether a request arrived in this drain.
    arrived: bool,
}

impl Serve for Pump<'_> {
    fn request(&mut self, request: Request) {
        let mut queue = self.shared.queue();
        if queue.len() >= MAX_QUEUED {
            queue.pop_front();
            self.overflowed += 1;
        }
        queue.push_back(request);
        self.arrived = true;
    }

    fn drained(&mut self) -> Option<Instant> {
        // One warning per interval at most, with the count, however fast requests overflow.
        if self.overflowed > 0
            && self
                .warned_at
                .is_none_or(|at| at.elapsed() >= OVERFLOW_WARNING_INTERVAL)
        {
            self.shared.warn_overflowed(self.overflowed);
            (self.overflowed, self.warned_at) = (0, Some(Instant::now()));
        }
        if std::mem::take(&mut self.arrived) {
            let waker = self.shared.waker().take();
            if let Some(w) = waker {
                w.wake();
            }
        }
        // Parked replies whose client can hear them now go out; old ones are dropped.
        self.shared.wire.flush_parked(&lock(&self.shared.writer))
    }
}

struct Shared {
    /// Keeps the node alive.
    _runtime: Runtime,
    wire: ServerWire,
    request_reader: Gid,
    reply_writer: Gid,
    queue: Mutex<VecDeque<Request>>,
    waker: Mutex<Option<Waker>>,
    writer: Mutex<RawWriter>,
    /// Wakes the request thread.
    pump_waker: RawReaderWaker,
    stop: AtomicBool,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Shared {
    fn queue(&self) -> MutexGuard<'_, VecDeque<Request>> {
        lock(&self.queue)
    }

    fn waker(&self) -> MutexGuard<'_, Option<Waker>> {
        lock(&self.waker)
    }

    /// Warns that `dropped` requests were dropped at the queue's bound.
    fn warn_overflowed(&self, dropped: u64) {
        tracing::warn!(
            service = %self.wire.service(),
            "request queue full ({MAX_QUEUED}): dropped the {dropped} oldest request(s)"
        );
    }

    /// The request thread: queues requests, wakes the waker, sends deferred replies. Woken by
    /// requests, by drop, by `send_reply` parking a reply and by the graph changes a parked reply
    /// waits for; otherwise only a parked reply's expiry is due.
    fn pump(&self, mut reader: RawReader) {
        let mut pump = Pump {
            shared: self,
            overflowed: 0,
            warned_at: None,
            arrived: false,
        };
        self.wire.serve(&mut reader, &self.stop, &mut pump);
        // What overflowed since the last warning is told too.
        if pump.overflowed > 0 {
            self.warn_overflowed(pump.overflowed);
        }
    }
}
