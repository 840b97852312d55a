//! [`Server`]: the rmw side of one service server — reading each request in its client's wire
//! convention (rmw `rmw_take_request`) and answering it in that convention once the client can
//! hear the reply (rmw `rmw_send_response`), never waiting for that on the serving thread: a reply
//! whose client's reader is not matched yet is parked (see `reply_park`).

use std::collections::HashSet;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

use super::convention::is_reader;
use super::reply_park::{Park, PeerWarnings, WarningKind, MAX_AGE};
use super::{
    is_horus_client_id, CycloneHeader, Peers, RequestId, WireFlavour, HORUS_CLIENT_MARKER,
};
use crate::names::ServiceName;
use crate::{Backend, Gid, PublishError, RawReader, RawSample, RawWriter, SampleId};

/// Most clients remembered as refused (whose convention this backend cannot answer).
const MAX_REFUSED: usize = 1024;

/// What a reply to one request needs, in the convention of the client that sent it (the
/// server-side half of rmw's request id: pass it back to [`Server::response`]).
#[derive(Clone, Copy, Debug)]
pub struct ReplyRoute(Route);

#[derive(Clone, Copy, Debug)]
enum Route {
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
        match self.0 {
            Route::FastRtps { request_writer, .. } | Route::CycloneDds { request_writer, .. } => {
                request_writer
            }
        }
    }

    /// Whose reply reader the reply waits for.
    fn recipient(&self) -> Recipient {
        match self.0 {
            Route::FastRtps { reply_to, .. } if is_reader(reply_to) => Recipient::Reader(reply_to),
            Route::FastRtps { .. } => Recipient::Anyone,
            Route::CycloneDds { request_writer, .. } => Recipient::ParticipantOf(request_writer),
        }
    }
}

/// A request taken by [`Server::take_request`]: its message (after any rmw_cyclonedds header),
/// its id, and how to answer it.
#[derive(Debug)]
pub struct Request {
    /// How to answer it (for [`Server::response`]).
    pub route: ReplyRoute,
    /// rmw's request id: the client's GUID in its RMW's convention and the request's sequence
    /// number (what rcl puts in a server's introspection events).
    pub id: RequestId,
    /// Whether the message is big-endian CDR.
    pub big_endian: bool,
    body: Vec<u8>,
    offset: usize,
}

impl Request {
    /// The CDR body of the request message.
    pub fn message(&self) -> &[u8] {
        self.body.get(self.offset..).unwrap_or_default()
    }
}

/// What [`Server::take_request`] found.
#[derive(Debug)]
pub enum TakenRequest {
    /// A request to answer.
    Request(Request),
    /// A sample that is no request this server can answer (malformed, from a client whose
    /// convention this backend cannot speak, or over its client's bound): dropped, with a
    /// warning limited in rate.
    Dropped,
    /// Nothing left to take.
    Empty,
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

/// Run once a response is written (e.g. to publish a `RESPONSE_SENT` introspection event).
pub type OnSent = Box<dyn FnOnce() + Send>;

/// A response ready to write once its client can hear it (from [`Server::response`]).
pub struct Response {
    body: Vec<u8>,
    related: Option<SampleId>,
    recipient: Recipient,
    client: Gid,
    on_sent: Option<OnSent>,
}

impl std::fmt::Debug for Response {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Response")
            .field("len", &self.body.len())
            .field("client", &self.client)
            .finish_non_exhaustive()
    }
}

impl Response {
    /// Runs `f` once the response is written (never if it is dropped).
    #[must_use]
    pub fn on_sent(mut self, f: OnSent) -> Self {
        self.on_sent = Some(f);
        self
    }
}

/// The rmw side of one service server: reads requests and writes responses in each client's
/// wire convention.
pub struct Server {
    peers: std::sync::Arc<dyn Peers>,
    service: ServiceName,
    reply_writer: Gid,
    flavour: Option<WireFlavour>,
    backend: Backend,
    /// Request writers already told about (once each) as unanswerable on this backend.
    refused: Mutex<HashSet<Gid>>,
    /// Responses waiting for their client's reply reader to be matched.
    park: Mutex<Park<Response>>,
    /// How many responses are parked (read without the park's lock).
    parked: AtomicUsize,
    /// Which warnings about peers are logged.
    warnings: Mutex<PeerWarnings>,
}

impl std::fmt::Debug for Server {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Server")
            .field("service", &self.service)
            .field("reply_writer", &self.reply_writer)
            .field("parked", &self.parked())
            .finish_non_exhaustive()
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Server {
    /// The server of `service` replying with `reply_writer`, learning of its clients from
    /// `peers`; every client is taken to follow `flavour` if given, else the convention of its
    /// DDS vendor. Whoever serves must call [`flush_parked`](Self::flush_parked) when `peers`
    /// reports new matches while [`parked`](Self::parked) is not zero.
    pub fn new(
        peers: std::sync::Arc<dyn Peers>,
        service: ServiceName,
        reply_writer: Gid,
        flavour: Option<WireFlavour>,
        backend: Backend,
    ) -> Self {
        Self {
            peers,
            service,
            reply_writer,
            flavour,
            backend,
            refused: Mutex::new(HashSet::new()),
            park: Mutex::new(Park::default()),
            parked: AtomicUsize::new(0),
            warnings: Mutex::new(PeerWarnings::default()),
        }
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

    /// Logs that a `what` (request or reply) of `client` was dropped because its parked
    /// replies are at their bound.
    fn warn_overflow(&self, client: Gid, what: &str) {
        self.warn_peer(
            client,
            WarningKind::Overflow,
            format_args!(
                "{what} dropped: the replies parked for this client (its reply reader is not \
                 matched) are at their bound"
            ),
        );
    }

    /// The fully-qualified service name.
    pub fn service(&self) -> &ServiceName {
        &self.service
    }

    /// rmw `rmw_take_request`: takes the next sample from `reader` and reads it as a request in
    /// its client's convention.
    pub fn take_request(&self, reader: &mut RawReader) -> TakenRequest {
        match reader.take() {
            Ok(Some(sample)) => match self.request_from(sample) {
                Some(request) => TakenRequest::Request(request),
                None => TakenRequest::Dropped,
            },
            Ok(None) => TakenRequest::Empty,
            Err(e) => {
                // The sender is not known: one warning for all such samples.
                self.warn_peer(
                    Gid::default(),
                    WarningKind::Malformed,
                    format_args!("dropped a request: {e}"),
                );
                TakenRequest::Dropped
            }
        }
    }

    /// Reads a request's correlation data in its client's convention; `None` (logged) if it is
    /// malformed or cannot be answered.
    fn request_from(&self, sample: RawSample) -> Option<Request> {
        let vendor = self.peers.vendor_of(sample.id.writer);
        let flavour = match WireFlavour::choose(self.backend, vendor, self.flavour) {
            Ok(flavour) => flavour,
            Err(why) => {
                let first = {
                    let mut refused = lock(&self.refused);
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
                let route = Route::CycloneDds {
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
                let route = Route::FastRtps {
                    reply_to,
                    sequence_number: sample.id.sequence_number,
                    horus_client,
                    request_writer: sample.id.writer,
                };
                (route, 0, *reply_to.as_bytes(), sample.id.sequence_number)
            }
        };
        let route = ReplyRoute(route);
        // A client whose replies are parked up to their bound gets no more work done for it
        // until its reader is matched or they age out.
        let client = route.client();
        if lock(&self.park).holds(client)
            && !lock(&self.park).admits(client)
            && !self.recipient_matched(route.recipient())
        {
            self.warn_overflow(client, "request");
            return None;
        }
        Some(Request {
            route,
            id: RequestId {
                writer_guid,
                sequence_number,
            },
            body: sample.body,
            offset,
            big_endian: sample.big_endian,
        })
    }

    /// The response to the request routed by `route`: the handler's response (a CDR_LE body),
    /// or for a failed handler the error reply a horus-ros client gets — negated sequence number,
    /// the message as a CDR string. `None` (logged) when there is nothing to send: ROS services
    /// have no error reply.
    pub fn response(
        &self,
        route: &ReplyRoute,
        outcome: Result<Vec<u8>, String>,
    ) -> Option<Response> {
        let (recipient, client) = (route.recipient(), route.client());
        let error_body = |message: &String| match horus_ros_msgs::cdr::to_cdr_body(message) {
            Ok(body) => Some(body),
            Err(e) => {
                tracing::warn!(service = %self.service, "could not encode an error reply: {e}");
                None
            }
        };
        let (body, related) = match route.0 {
            Route::FastRtps {
                reply_to,
                sequence_number,
                horus_client,
                ..
            } => {
                let (body, sequence_number) = match outcome {
                    Ok(body) => (body, sequence_number),
                    Err(message) if horus_client => (error_body(&message)?, -sequence_number),
                    Err(message) => {
                        self.warn_peer(
                            client,
                            WarningKind::Malformed,
                            format_args!("handler failed; a ROS client gets no reply: {message}"),
                        );
                        return None;
                    }
                };
                let related = SampleId {
                    writer: reply_to,
                    sequence_number,
                };
                (body, Some(related))
            }
            Route::CycloneDds { header, .. } => match outcome {
                Ok(body) => (header.prepend(&body), None),
                Err(message) if is_horus_client_id(header.guid) => {
                    let header = CycloneHeader {
                        seq: header.seq.saturating_neg(),
                        ..header
                    };
                    (header.prepend(&error_body(&message)?), None)
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
                    return None;
                }
            },
        };
        Some(Response {
            body,
            related,
            recipient,
            client,
            on_sent: None,
        })
    }

    /// rmw `rmw_send_response`: sends `response` now if its client's reply reader is matched
    /// with our writer (after any responses parked for that client), else parks it (bounded per
    /// client: count, bytes, age; beyond, it is dropped with a warning limited in rate). Never
    /// waits. Errs only if a write of this response failed.
    pub fn send_response(
        &self,
        writer: &RawWriter,
        response: Response,
    ) -> Result<(), PublishError> {
        let mut park = lock(&self.park);
        let mut result = Ok(());
        if self.recipient_matched(response.recipient) {
            for earlier in park.take_client(response.client) {
                self.write_logged(writer, earlier);
            }
            result = self.write_now(writer, response);
        } else {
            let (client, bytes) = (response.client, response.body.len());
            if park.park(client, response, bytes).is_err() {
                self.warn_overflow(client, "reply");
            }
        }
        self.parked.store(park.len(), Ordering::SeqCst);
        result
    }

    /// Sends the parked responses whose clients' readers are matched now, drops those older
    /// than their age limit (debug log); returns when the next parked response reaches it.
    pub fn flush_parked(&self, writer: &RawWriter) -> Option<Instant> {
        let mut park = lock(&self.park);
        if park.len() == 0 {
            return None;
        }
        for client in park.clients() {
            if park
                .first(client)
                .is_some_and(|r| self.recipient_matched(r.recipient))
            {
                for response in park.take_client(client) {
                    self.write_logged(writer, response);
                }
            }
        }
        for (client, _response) in park.expire(Instant::now(), MAX_AGE) {
            tracing::debug!(
                service = %self.service,
                %client,
                "reply dropped: the client's reply reader was not matched within {MAX_AGE:?}"
            );
        }
        self.parked.store(park.len(), Ordering::SeqCst);
        park.next_expiry(MAX_AGE)
    }

    /// Responses parked now.
    pub fn parked(&self) -> usize {
        self.parked.load(Ordering::SeqCst)
    }

    /// Writes `response` with `writer` (to its one reader if that is matched, else to all:
    /// clients filter), then runs its `on_sent`.
    fn write_now(&self, writer: &RawWriter, response: Response) -> Result<(), PublishError> {
        let only_to = match response.recipient {
            Recipient::Reader(r) if self.peers.is_matched(self.reply_writer, r) => Some(r),
            _ => None,
        };
        writer.write(response.body, response.related, only_to)?;
        if let Some(on_sent) = response.on_sent {
            on_sent();
        }
        Ok(())
    }

    /// [`write_now`](Self::write_now), logging a failure.
    fn write_logged(&self, writer: &RawWriter, response: Response) {
        if let Err(e) = self.write_now(writer, response) {
            tracing::warn!(service = %self.service, "could not send a reply: {e}");
        }
    }

    /// Whether the client of `recipient` can hear a response now.
    fn recipient_matched(&self, recipient: Recipient) -> bool {
        match recipient {
            Recipient::Reader(reader) => self.peers.is_matched(self.reply_writer, reader),
            Recipient::ParticipantOf(request_writer) => {
                // A reader of our reply topic in the requesting participant: our writer's matches
                // (reported by the DDS layer) say it, even before discovery lists the reader.
                self.peers
                    .matched_in_participant(self.reply_writer, request_writer)
            }
            Recipient::Anyone => true,
        }
    }
}
