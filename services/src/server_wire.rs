//! What both servers ([`ServiceServer`](crate::ServiceServer) and
//! [`DdsServiceServer`](crate::DdsServiceServer)) share: reading a request in its client's wire
//! convention, and answering it in that convention once the client can hear the reply.

use std::collections::HashSet;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::{Backend, Gid, PublishError, RawSample, RawWriter, SampleId};

use crate::wire::{
    encode, is_horus_client_id, is_reader, peer_vendor, CycloneHeader, WireFlavour,
    HORUS_CLIENT_MARKER,
};

/// How long a reply waits for the client's reply reader to be matched before it is sent anyway
/// (rmw_fastrtps and rmw_cyclonedds wait too, so that a fresh client's first reply is not lost).
const REPLY_MATCH_WAIT: Duration = Duration::from_millis(500);

/// Longest single wait of [`ServerWire::wait_until_sendable`] between checks.
const MATCH_CHECK_INTERVAL: Duration = Duration::from_millis(10);

/// What a reply to one request needs, in the convention of the client that sent it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ReplyRoute {
    /// rmw_fastrtps (and horus-ros clients): reply with related_sample_identity =
    /// {reply_to, sequence_number}; a horus-ros client also takes error replies.
    FastRtps {
        reply_to: Gid,
        sequence_number: i64,
        horus_client: bool,
    },
    /// rmw_cyclonedds: echo the header; the client's reply reader is found from the participant
    /// of its request writer.
    CycloneDds {
        header: CycloneHeader,
        request_writer: Gid,
    },
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

/// A reply ready to write once its client can hear it (or at its deadline).
pub(crate) struct Reply {
    body: Vec<u8>,
    related: Option<SampleId>,
    recipient: Recipient,
    deadline: Instant,
}

/// Interprets requests and writes replies for one server, per client wire convention.
pub(crate) struct ServerWire {
    graph: Arc<Graph>,
    service: ServiceName,
    /// The DDS reply topic (`rr/…Reply`).
    reply_topic: String,
    reply_writer: Gid,
    flavour: Option<WireFlavour>,
    backend: Backend,
    /// Request writers already told about (once each) as unanswerable on this backend.
    refused: Mutex<HashSet<Gid>>,
}

impl ServerWire {
    /// The wire of the server of `service` replying with `reply_writer` on `reply_topic`; every
    /// client is taken to follow `flavour` if given, else the convention of its DDS vendor.
    pub(crate) fn new(
        graph: Arc<Graph>,
        service: ServiceName,
        reply_topic: String,
        reply_writer: Gid,
        flavour: Option<WireFlavour>,
        backend: Backend,
    ) -> Self {
        Self {
            graph,
            service,
            reply_topic,
            reply_writer,
            flavour,
            backend,
            refused: Mutex::new(HashSet::new()),
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
                let first = self
                    .refused
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .insert(sample.id.writer);
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
                    tracing::warn!(service = %self.service, "request shorter than rmw_cyclonedds' header; dropped");
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
                };
                (route, 0, *reply_to.as_bytes(), sample.id.sequence_number)
            }
        };
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
        let deadline = Instant::now() + REPLY_MATCH_WAIT;
        match *route {
            ReplyRoute::FastRtps {
                reply_to,
                sequence_number,
                horus_client,
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
                        tracing::warn!(service = %self.service, "handler failed; a ROS client gets no reply: {message}");
                        return None;
                    }
                };
                let recipient = if is_reader(reply_to) {
                    Recipient::Reader(reply_to)
                } else {
                    Recipient::Anyone
                };
                Some(Reply {
                    body,
                    related: Some(SampleId {
                        writer: reply_to,
                        sequence_number,
                    }),
                    recipient,
                    deadline,
                })
            }
            ReplyRoute::CycloneDds {
                header,
                request_writer,
            } => match outcome {
                Ok(body) => Some(Reply {
                    body: header.prepend(&body),
                    related: None,
                    recipient: Recipient::ParticipantOf(request_writer),
                    deadline,
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
                        recipient: Recipient::ParticipantOf(request_writer),
                        deadline,
                    })
                }
                Err(message) => {
                    tracing::warn!(
                        service = %self.service,
                        "handler failed for an rmw_cyclonedds client, which gets no reply: {message}"
                    );
                    None
                }
            },
        }
    }

    /// Whether `reply` can go now: its client's reply reader is matched with our writer, or it
    /// waited long enough.
    pub(crate) fn can_send(&self, reply: &Reply) -> bool {
        Instant::now() >= reply.deadline || self.recipient_matched(reply.recipient)
    }

    /// Waits until `reply` can go (at most until its deadline).
    pub(crate) fn wait_until_sendable(&self, reply: &Reply) {
        loop {
            let now = Instant::now();
            if now >= reply.deadline || self.recipient_matched(reply.recipient) {
                return;
            }
            // Matches being made are graph changes.
            self.graph
                .wait_for_graph_change((reply.deadline - now).min(MATCH_CHECK_INTERVAL));
        }
    }

    /// Writes `reply` with `writer` (to its one reader if that is matched, else to all: clients
    /// filter).
    pub(crate) fn write(&self, writer: &RawWriter, reply: Reply) -> Result<(), PublishError> {
        let only_to = match reply.recipient {
            Recipient::Reader(r) if self.graph.is_matched(self.reply_writer, r) => Some(r),
            _ => None,
        };
        writer
            .write(reply.body, reply.related, only_to)
            .map(|_id| ())
    }

    fn recipient_matched(&self, recipient: Recipient) -> bool {
        match recipient {
            Recipient::Reader(reader) => self.graph.is_matched(self.reply_writer, reader),
            Recipient::ParticipantOf(request_writer) => {
                // Readers of our reply topic in the requesting participant (its node may not be
                // known yet: look at the DDS topic, not at clients by node).
                let prefix = request_writer.prefix();
                self.graph
                    .read(|c| c.subscriptions_info_by_topic(&self.reply_topic, true))
                    .iter()
                    .filter(|r| r.endpoint_gid.prefix() == prefix)
                    .any(|r| self.graph.is_matched(self.reply_writer, r.endpoint_gid))
            }
            Recipient::Anyone => true,
        }
    }
}
