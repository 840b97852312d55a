//! What both servers ([`ServiceServer`](crate::ServiceServer) and
//! [`DdsServiceServer`](crate::DdsServiceServer)) share: reading a request in its client's wire
//! convention, and answering it in that convention once the client can hear the reply (never
//! waiting for that: see `reply_park`).

use std::collections::HashSet;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Instant;

use horus_ros_graph::{Graph, GraphView, GraphWatcher};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::{Backend, Gid, PublishError, RawReaderWaker, RawSample, RawWriter, SampleId};

use crate::reply_park::{Park, PeerWarnings, WarningKind, MAX_AGE};
use crate::wire::{
    encode, is_horus_client_id, is_reader, peer_vendor, CycloneHeader, WireFlavour,
    HORUS_CLIENT_MARKER,
};

/// Most clients remembered as refused (whose convention this backend cannot answer).
const MAX_REFUSED: usize = 1024;

/// What a reply to one request needs, in the convention of the client that sent it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ReplyRoute {
    /// rmw_fastrtps (and horus-ros clients): reply with related_sample_identity =
    /// {reply_to, sequence_number}; a horus-ros client also takes error replies.
    FastRtps {
        reply_to: Gid,
        sequence_number: i64,
        horus_client: bool,
        request_writer: Gid,
    },
    /// rmw_cyclonedds: echo the header; the client's reply reader is found from the participant
    /// of its request writer.
    CycloneDds {
        header: CycloneHeader,
        request_writer: Gid,
    },
}

impl ReplyRoute {
    /// The client: the request writer (whose parked replies are bounded together).
    fn client(&self) -> Gid {
        match *self {
            Self::FastRtps { request_writer, .. } | Self::CycloneDds { request_writer, .. } => {
                request_writer
            }
        }
    }

    /// Whose reply reader the reply waits for.
    fn recipient(&self) -> Recipient {
        match *self {
            Self::FastRtps { reply_to, .. } if is_reader(reply_to) => Recipient::Reader(reply_to),
            Self::FastRtps { .. } => Recipient::Anyone,
            Self::CycloneDds { request_writer, .. } => Recipient::ParticipantOf(request_writer),
        }
    }
}

/// A received request: its message (after any rmw_cyclonedds header) and how to answer it.
pub(crate) struct Request {
    pub(crate) route: ReplyRoute,
    /// The request header's `writer_guid`, as the client's RMW convention makes it (what rcl puts
    /// in a server's introspection events as `client_gid`).
    pub(crate) writer_guid: [u8; 16],
    /// The request header's `sequence_number`.
    pub(crate) sequence_number: i64,
    body: Vec<u8>,
    offset: usize,
    pub(crate) big_endian: bool,
}

impl Request {
    /// The CDR body of the request message.
    pub(crate) fn message(&self) -> &[u8] {
        self.body.get(self.offset..).unwrap_or_default()
    }
}

/// rmw_cyclonedds (jazzy `rmw_node.cpp` `rmw_take_response_request`) fills a request's
/// `writer_guid` with the header's 64-bit client id followed by the sample's
/// `publication_handle` (both copied in memory order: little-endian here). RustDDS has no instance
/// handles: there the last 8 bytes of the request writer's GUID stand in for it.
fn cyclone_writer_guid(header: CycloneHeader, sample: &RawSample) -> [u8; 16] {
    let mut guid = [0u8; 16];
    guid[..8].copy_from_slice(&header.guid.to_le_bytes());
    match sample.publication_handle {
        Some(handle) => guid[8..].copy_from_slice(&handle.to_le_bytes()),
        None => guid[8..].copy_from_slice(&sample.id.writer.as_bytes()[8..]),
    }
    guid
}

/// Whose reply reader a reply waits for.
#[derive(Clone, Copy, Debug)]
enum Recipient {
    /// The client's reply reader (rmw_fastrtps convention): the reply goes to it alone once
    /// matched.
    Reader(Gid),
    /// Any reader of our reply topic in the participant of this request writer (an
    /// rmw_cyclonedds client, identified by a header id rather than a GUID).
    ParticipantOf(Gid),
    /// Nobody known (the related GUID is not a reader): the reply goes to all at once.
    Anyone,
}

/// Run once a reply is written (e.g. to publish a `RESPONSE_SENT` introspection event).
pub(crate) type OnSent = Box<dyn FnOnce() + Send>;

/// A reply ready to write once its client can hear it.
pub(crate) struct Reply {
    body: Vec<u8>,
    related: Option<SampleId>,
    recipient: Recipient,
    client: Gid,
    on_sent: Option<OnSent>,
}

impl Reply {
    /// Runs `f` once the reply is written (never if it is dropped).
    pub(crate) fn on_sent(mut self, f: OnSent) -> Self {
        self.on_sent = Some(f);
        self
    }
}

/// Wakes a server's thread when the graph changes while replies are parked (their clients'
/// readers may have been matched).
struct ParkWatcher {
    parked: Arc<AtomicUsize>,
    waker: RawReaderWaker,
}

impl GraphWatcher for ParkWatcher {
    fn graph_changed(&self, _graph: &GraphView<'_>) {
        if self.parked.load(Ordering::SeqCst) > 0 {
            self.waker.wake();
        }
    }
}

/// Interprets requests and writes replies for one server, per client wire convention.
pub(crate) struct ServerWire {
    graph: Arc<Graph>,
    service: ServiceName,
    reply_writer: Gid,
    flavour: Option<WireFlavour>,
    backend: Backend,
    /// Request writers already told about (once each) as unanswerable on this backend.
    refused: Mutex<HashSet<Gid>>,
    /// Replies waiting for their client's reply reader to be matched.
    park: Mutex<Park<Reply>>,
    /// How many replies are parked (read by the watcher without the park's lock).
    parked: Arc<AtomicUsize>,
    /// Which warnings about peers are logged.
    warnings: Mutex<PeerWarnings>,
    /// Kept alive while the server is (the graph holds it weakly).
    watcher: Mutex<Option<Arc<ParkWatcher>>>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl ServerWire {
    /// The wire of the server of `service` replying with `reply_writer`; every
    /// client is taken to follow `flavour` if given, else the convention of its DDS vendor.
    pub(crate) fn new(
        graph: Arc<Graph>,
        service: ServiceName,
        reply_writer: Gid,
        flavour: Option<WireFlavour>,
        backend: Backend,
    ) -> Self {
        Self {
            graph,
            service,
            reply_writer,
            flavour,
            backend,
            refused: Mutex::new(HashSet::new()),
            park: Mutex::new(Park::default()),
            parked: Arc::new(AtomicUsize::new(0)),
            warnings: Mutex::new(PeerWarnings::default()),
            watcher: Mutex::new(None),
        }
    }

    /// Has `waker` woken whenever the graph changes while replies are parked: the thread it
    /// wakes then calls [`flush`](Self::flush).
    pub(crate) fn wake_on_graph_change(&self, waker: RawReaderWaker) {
        let watcher = Arc::new(ParkWatcher {
            parked: Arc::clone(&self.parked),
            waker,
        });
        let weak: std::sync::Weak<dyn GraphWatcher> = Arc::downgrade(&watcher) as _;
        self.graph.watch(weak);
        *lock(&self.watcher) = Some(watcher);
    }

    /// Logs a request that could not be taken (undecodable), limited in rate like the warnings
    /// about peers (the sender is not known).
    pub(crate) fn warn_unreadable(&self, e: &dyn std::fmt::Display) {
        self.warn_peer(
            Gid::default(),
            WarningKind::Malformed,
            format_args!("dropped a request: {e}"),
        );
    }

    /// Logs `message` about `peer`, limited to one per peer and kind every few seconds.
    fn warn_peer(&self, peer: Gid, kind: WarningKind, message: std::fmt::Arguments<'_>) {
        let allowed = lock(&self.warnings).allow(peer, kind, Instant::now());
        match allowed {
            Some(0) => tracing::warn!(service = %self.service, client = %peer, "{message}"),
            Some(held) => tracing::warn!(
                service = %self.service,
                client = %peer,
                "{message} ({held} more like it not logged)"
            ),
            None => {}
        }
    }

    /// The fully-qualified service name.
    pub(crate) fn service(&self) -> &ServiceName {
        &self.service
    }

    /// Reads a request's correlation data in its client's convention; `None` (logged) if it is
    /// malformed.
    pub(crate) fn interpret(&self, sample: RawSample) -> Option<Request> {
        let vendor = peer_vendor(&self.graph, sample.id.writer);
        let flavour = match WireFlavour::choose(self.backend, vendor, self.flavour) {
            Ok(flavour) => flavour,
            Err(why) => {
                let first = {
                    let mut refused = self.refused.lock().unwrap_or_else(|p| p.into_inner());
                    // Bounded: beyond, forgotten (each such client is warned of once more).
                    if refused.len() >= MAX_REFUSED {
                        refused.clear();
                    }
                    refused.insert(sample.id.writer)
                };
                if first {
                    tracing::warn!(
                        service = %self.service,
                        client = %sample.id.writer,
                        "requests from this client cannot be answered and are dropped: {why}"
                    );
                }
                return None;
            }
        };
        let (route, offset, writer_guid, sequence_number) = match flavour {
            WireFlavour::CycloneDds => {
                let Some((header, message)) = CycloneHeader::split(&sample.body, sample.big_endian)
                else {
                    self.warn_peer(
                        sample.id.writer,
                        WarningKind::Malformed,
                        format_args!("request shorter than rmw_cyclonedds' header; dropped"),
                    );
                    return None;
                };
                // 16 header bytes: the message keeps its 8-byte alignment.
                let route = ReplyRoute::CycloneDds {
                    header,
                    request_writer: sample.id.writer,
                };
                let writer_guid = cyclone_writer_guid(header, &sample);
                (
                    route,
                    sample.body.len() - message.len(),
                    writer_guid,
                    header.seq,
                )
            }
            WireFlavour::FastRtps => {
                // rmw_fastrtps `__rmw_take_request`: the request id is the sample identity, with
                // the writer replaced by the related_sample_identity's GUID when given.
                let reply_to = match sample.related {
                    Some(r) if r.writer != Gid::default() => r.writer,
                    _ => sample.id.writer,
                };
                let horus_client = sample
                    .related
                    .is_some_and(|r| r.sequence_number == HORUS_CLIENT_MARKER);
                let route = ReplyRoute::FastRtps {
                    reply_to,
                    sequence_number: sample.id.sequence_number,
                    horus_client,
                    request_writer: sample.id.writer,
                };
                (route, 0, *reply_to.as_bytes(), sample.id.sequence_number)
            }
        };
        // A client whose replies are parked up to their bound gets no more work done for it
        // until its reader is matched or they age out.
        let client = route.client();
        if lock(&self.park).holds(client)
            && !lock(&self.park).admits(client)
            && !self.recipient_matched(route.recipient())
        {
            self.warn_peer(
                client,
                WarningKind::Overflow,
                format_args!(
                    "request dropped: the replies parked for this client (its reply reader is \
                     not matched) are at their bound"
                ),
            );
            return None;
        }
        Some(Request {
            route,
            writer_guid,
            sequence_number,
            body: sample.body,
            offset,
            big_endian: sample.big_endian,
        })
    }

    /// The reply to the request routed by `route`: the response (a CDR_LE body), or for a failed
    /// handler the error reply a horus-ros client gets — negated sequence number, the message as a
    /// CDR string. `None` (logged) when there is nothing to send: ROS services have no error reply.
    pub(crate) fn reply(
        &self,
        route: &ReplyRoute,
        outcome: Result<Vec<u8>, String>,
    ) -> Option<Reply> {
        let (recipient, client) = (route.recipient(), route.client());
        match *route {
            ReplyRoute::FastRtps {
                reply_to,
                sequence_number,
                horus_client,
                ..
            } => {
                let (body, sequence_number) = match outcome {
                    Ok(body) => (body, sequence_number),
                    Err(message) if horus_client => match encode(&message) {
                        Ok(body) => (body, -sequence_number),
                        Err(e) => {
                            tracing::warn!(service = %self.service, "could not encode an error reply: {e}");
                            return None;
                        }
                    },
                    Err(message) => {
                        self.warn_peer(
                            client,
                            WarningKind::Malformed,
                            format_args!("handler failed; a ROS client gets no reply: {message}"),
                        );
                        return None;
                    }
                };
                Some(Reply {
                    body,
                    related: Some(SampleId {
                        writer: reply_to,
                        sequence_number,
                    }),
                    recipient,
                    client,
                    on_sent: None,
                })
            }
            ReplyRoute::CycloneDds { header, .. } => match outcome {
                Ok(body) => Some(Reply {
                    body: header.prepend(&body),
                    related: None,
                    recipient,
                    client,
                    on_sent: None,
                }),
                Err(message) if is_horus_client_id(header.guid) => {
                    let body = match encode(&message) {
                        Ok(body) => body,
                        Err(e) => {
                            tracing::warn!(service = %self.service, "could not encode an error reply: {e}");
                            return None;
                        }
                    };
                    let header = CycloneHeader {
                        seq: header.seq.saturating_neg(),
                        ..header
                    };
                    Some(Reply {
                        body: header.prepend(&body),
                        related: None,
                        recipient,
                        client,
                        on_sent: None,
                    })
                }
                Err(message) => {
                    self.warn_peer(
                        client,
                        WarningKind::Malformed,
                        format_args!(
                            "handler failed for an rmw_cyclonedds client, which gets no reply: \
                             {message}"
                        ),
                    );
                    None
                }
            },
        }
    }

    /// Sends `reply` now if its client's reply reader is matched with our writer (after any
    /// replies parked for that client), else parks it (bounded per client: count, bytes, age;
    /// beyond, it is dropped with a warning limited in rate). Never waits. Errs only if a write
    /// of this reply failed.
    pub(crate) fn send_or_park(
        &self,
        writer: &RawWriter,
        reply: Reply,
    ) -> Result<(), PublishError> {
        let mut park = lock(&self.park);
        let mut result = Ok(());
        if self.recipient_matched(reply.recipient) {
            for earlier in park.take_client(reply.client) {
                self.write_logged(writer, earlier);
            }
            result = self.write_now(writer, reply);
        } else {
            let (client, bytes) = (reply.client, reply.body.len());
            if park.park(client, reply, bytes).is_err() {
                self.warn_peer(
                    client,
                    WarningKind::Overflow,
                    format_args!(
                        "reply dropped: the replies parked for this client (its reply reader is \
                         not matched) are at their bound"
                    ),
                );
            }
        }
        self.parked.store(park.len(), Ordering::SeqCst);
        result
    }

    /// Sends the parked replies whose clients' readers are matched now, drops those older than
    /// their age limit (debug log); returns when the next parked reply reaches it.
    pub(crate) fn flush(&self, writer: &RawWriter) -> Option<Instant> {
        let mut park = lock(&self.park);
        if park.len() == 0 {
            return None;
        }
        for client in park.clients() {
            if park
                .first(client)
                .is_some_and(|r| self.recipient_matched(r.recipient))
            {
                for reply in park.take_client(client) {
                    self.write_logged(writer, reply);
                }
            }
        }
        for (client, _reply) in park.expire(Instant::now(), MAX_AGE) {
            tracing::debug!(
                service = %self.service,
                %client,
                "reply dropped: the client's reply reader was not matched within {MAX_AGE:?}"
            );
        }
        self.parked.store(park.len(), Ordering::SeqCst);
        park.next_expiry(MAX_AGE)
    }

    /// Replies parked now.
    pub(crate) fn parked(&self) -> usize {
        self.parked.load(Ordering::SeqCst)
    }

    /// Writes `reply` with `writer` (to its one reader if that is matched, else to all: clients
    /// filter), then runs its `on_sent`.
    fn write_now(&self, writer: &RawWriter, reply: Reply) -> Result<(), PublishError> {
        let only_to = match reply.recipient {
            Recipient::Reader(r) if self.graph.is_matched(self.reply_writer, r) => Some(r),
            _ => None,
        };
        writer.write(reply.body, reply.related, only_to)?;
        if let Some(on_sent) = reply.on_sent {
            on_sent();
        }
        Ok(())
    }

    /// [`write_now`](Self::write_now), logging a failure.
    fn write_logged(&self, writer: &RawWriter, reply: Reply) {
        if let Err(e) = self.write_now(writer, reply) {
            tracing::warn!(service = %self.service, "could not send a reply: {e}");
        }
    }

    /// Whether the client of `recipient` can hear a reply now.
    fn recipient_matched(&self, recipient: Recipient) -> bool {
        match recipient {
            Recipient::Reader(reader) => self.graph.is_matched(self.reply_writer, reader),
            Recipient::ParticipantOf(request_writer) => {
                // A reader of our reply topic in the requesting participant: our writer's matches
                // (reported by the DDS layer) say it, even before discovery lists the reader.
                self.graph
                    .matched_in_participant(self.reply_writer, request_writer)
                    .is_some()
            }
            Recipient::Anyone => true,
        }
    }
}
