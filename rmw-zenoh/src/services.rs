//! Services on Zenoh as rmw_zenoh_cpp 0.2.10 makes them (`src/detail/rmw_service_data.cpp`,
//! `src/detail/rmw_client_data.cpp`; wire facts §2–5).
//!
//! - A server declares a queryable on the service key `<domain>/<name>/<type>/<hash>` (the
//!   service's DDS type name `pkg::srv::dds_::Name_` and its RIHS01 hash) with `complete=true`,
//!   and an `SS` token. Each query (the CDR request with the 33-byte attachment of its client's
//!   sequence number, timestamp and GID) is queued for the request reader, and the query itself
//!   is held, keyed by (client GID, sequence number), until the reply writer answers it: one
//!   reply on the same key, the CDR reply with an attachment echoing the sequence number and
//!   the client's GID under a new timestamp. A reply whose query is gone is dropped.
//! - A client declares an `SC` token (its GID is the token's hash) and sends each request as a
//!   `get` on the service key (target `ALL_COMPLETE`, consolidation `NONE`) with the attachment
//!   of its own sequence number (from 1); the replies go to the reply reader's queue. The `get`
//!   goes through a querier (the same query on the wire) whose matching status says whether
//!   this session has a route to a queryable; a request made before there is one is held, at
//!   most [`MAX_PENDING_REQUESTS`], and sent when the route appears ([`route`](super::route)).
//!   A client that does not know its service type's hash queries the key with `*` for it
//!   (target `ALL`, as no queryable is complete for a wildcard: [`ServiceQuery`]).
//!
//! The contract's request/reply endpoints of one server or client (paired by their
//! [`ServiceEndpointId`](horus_ros_rmw_contract::ServiceEndpointId)) share one [`ServiceEntity`]; the
//! identities they carry are described at
//! [`Capabilities::service_queries`](horus_ros_rmw_contract::Capabilities::service_queries). A failed
//! handler's error reply (for our own clients) is Zenoh's error reply, which rmw_zenoh clients
//! drop.

use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, AtomicI64, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::time::Duration;

use zenoh::liveliness::LivelinessToken;
use zenoh::matching::{MatchingListener, MatchingStatus};
use zenoh::query::{ConsolidationMode, Querier, Query, Queryable, Reply};
use zenoh::Wait;

use super::attachment::{now_ns, Attachment};
use super::endpoints::{zenoh_error, Incoming, ReaderQueue, CDR_LE_HEADER};
use super::feed::Graph;
use super::keyexpr::ServiceQuery;
use super::route::RouteWait;
use horus_ros_rmw_contract::dds_error::DdsError;
use horus_ros_rmw_contract::push::lock;
use horus_ros_rmw_contract::Gid;
use horus_ros_rmw_contract::HORUS_CLIENT_MARKER;
use horus_ros_rmw_contract::{SampleId, WriterBackend};

/// Most queries a server holds unanswered; beyond, the oldest is let go (its client gets no
/// reply from this server).
pub(crate) const MAX_HELD_QUERIES: usize = 4096;

/// Most requests a client holds while its session has no route to a server.
pub(crate) const MAX_PENDING_REQUESTS: usize = 64;

/// The queries a server holds until they are answered, oldest first.
#[derive(Default)]
struct HeldQueries {
    queries: HashMap<(Gid, i64), Query>,
    order: VecDeque<(Gid, i64)>,
}

impl HeldQueries {
    fn hold(&mut self, id: (Gid, i64), query: Query) {
        if self.queries.insert(id, query).is_none() {
            self.order.push_back(id);
        }
        while self.queries.len() > MAX_HELD_QUERIES {
            let Some(oldest) = self.order.pop_front() else {
                break;
            };
            if self.queries.remove(&oldest).is_some() {
                tracing::debug!(client = %oldest.0, seq = oldest.1, "zenoh: a request left unanswered (too many held)");
            }
        }
    }

    fn take(&mut self, id: (Gid, i64)) -> Option<Query> {
        let query = self.queries.remove(&id)?;
        self.order.retain(|o| *o != id);
        Some(query)
    }
}

/// A server's or client's Zenoh side, shared by its two contract endpoints.
pub(crate) struct ServiceEntity {
    /// The GID of the token (the request reader's, or the request writer's).
    pub(crate) gid: Gid,
    /// The GID of the other endpoint (the reply writer's or reader's).
    pub(crate) reply_gid: Gid,
    /// Requests (server) or replies (client) for the reader.
    pub(crate) queue: Arc<ReaderQueue>,
    kind: EntityKind,
    _token: Option<LivelinessToken>,
}

enum EntityKind {
    Server {
        queries: Arc<Mutex<HeldQueries>>,
        _queryable: Queryable<()>,
    },
    Client {
        /// Before `sender`, so dropped first: a querier undeclared first undeclares its matching
        /// listeners (zenoh 1.8 `Querier::undeclare_impl`), and the listener's own undeclaration
        /// then finds none and logs an ERROR ("Unable to find MatchingListener":
        /// `Session::undeclare_matches_listener_inner`).
        _matching: MatchingListener<()>,
        sender: Arc<RequestSender>,
        sequence_number: AtomicI64,
    },
}

/// A request not sent yet: its sequence number, payload and attachment.
struct PendingRequest {
    sequence_number: i64,
    payload: Vec<u8>,
    attachment: Vec<u8>,
}

/// A client's querier and the requests that wait for its route.
struct RequestSender {
    /// Shared with each `get`'s callback, so that it is undeclared only once its last query
    /// ended (its ResponseFinal, its timeout or the session's close): zenoh 1.8 forgets an
    /// undeclared querier's queries (`Session::undeclare_querier_inner`), and their
    /// ResponseFinal, which follows the reply, is then logged as a WARN ("Received ResponseFinal
    /// for unknown Request": `<WeakSession as Primitives>::send_response_final`).
    querier: Arc<Querier<'static>>,
    queue: Arc<ReaderQueue>,
    client: Gid,
    pending: RouteWait<PendingRequest>,
}

impl RequestSender {
    /// Sends the request now if a server is routed to, else holds it (bounded).
    fn request(&self, request: PendingRequest) -> Result<(), DdsError> {
        self.pending
            .send_or_hold(request, || true, |request| self.send(request))
    }

    /// The `get` (rmw_client_data.cpp: target ALL_COMPLETE, consolidation NONE, the
    /// querier's), its replies queued.
    fn send(&self, request: PendingRequest) -> Result<(), DdsError> {
        let (queue, querier) = (Arc::clone(&self.queue), Arc::clone(&self.querier));
        let (client, sequence_number) = (self.client, request.sequence_number);
        self.querier
            .get()
            .payload(request.payload)
            .attachment(request.attachment)
            .callback(move |reply: Reply| {
                let _querier = &querier;
                on_reply(&queue, client, sequence_number, &reply)
            })
            .wait()
            .map_err(|e| zenoh_error(DdsError::Write, e))
    }
}

impl ServiceEntity {
    /// A server: the queryable (`complete=true`) on `key`, its requests going to `queue`; then
    /// its token (`declare_token`), so that a client that sees the token finds the queryable.
    pub(crate) fn server(
        session: &zenoh::Session,
        key: String,
        (gid, reply_gid): (Gid, Gid),
        declare_token: impl FnOnce() -> Option<LivelinessToken>,
        queue: Arc<ReaderQueue>,
    ) -> Result<Self, DdsError> {
        let key = zenoh::key_expr::KeyExpr::try_from(key)
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let queries = Arc::new(Mutex::new(HeldQueries::default()));
        let on_query = {
            let (queries, queue) = (Arc::clone(&queries), Arc::clone(&queue));
            // rmw_service_data.cpp: a query without an attachment is refused ("ServiceData
            // take_request attachment is empty").
            move |query: Query| {
                let Some(attachment) = queue.attachment_of(query.attachment(), query.key_expr())
                else {
                    return;
                };
                let payload = query.payload().cloned().unwrap_or_default();
                let client = attachment.gid;
                lock(&queries).hold((client, attachment.sequence_number), query);
                queue.deliver(Incoming {
                    payload,
                    attachment,
                    received: horus_ros_rmw_contract::unix_time_ns(),
                    related: Some(SampleId {
                        writer: client,
                        sequence_number: HORUS_CLIENT_MARKER,
                    }),
                });
            }
        };
        let queryable = session
            .declare_queryable(key)
            .complete(true)
            .callback(on_query)
            .wait()
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        Ok(Self {
            gid,
            reply_gid,
            queue,
            kind: EntityKind::Server {
                queries,
                _queryable: queryable,
            },
            _token: declare_token(),
        })
    }

    /// A client sending its requests as `query` says, its replies going to `queue`.
    pub(crate) fn client(
        session: &zenoh::Session,
        query: ServiceQuery,
        (gid, reply_gid): (Gid, Gid),
        declare_token: impl FnOnce() -> Option<LivelinessToken>,
        queue: Arc<ReaderQueue>,
    ) -> Result<Self, DdsError> {
        let key = zenoh::key_expr::KeyExpr::try_from(query.key)
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let querier = session
            .declare_querier(key)
            .target(query.target)
            .consolidation(ConsolidationMode::None)
            .wait()
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let sender = Arc::new(RequestSender {
            querier: Arc::new(querier),
            queue: Arc::clone(&queue),
            client: gid,
            pending: RouteWait::new(MAX_PENDING_REQUESTS, "request"),
        });
        // Declared with a route already there, it reports it at once.
        let weak: Weak<RequestSender> = Arc::downgrade(&sender);
        let matching = sender
            .querier
            .matching_listener()
            .callback(move |status: MatchingStatus| {
                if let Some(sender) = weak.upgrade() {
                    sender
                        .pending
                        .on_matching(status.matching(), |request| sender.send(request));
                }
            })
            .wait()
            .map_err(|e| zenoh_error(DdsError::Create, e))?;
        let token = declare_token();
        Ok(Self {
            gid,
            reply_gid,
            queue,
            kind: EntityKind::Client {
                _matching: matching,
                sender,
                sequence_number: AtomicI64::new(0),
            },
            _token: token,
        })
    }

    /// Whether it is a server.
    pub(crate) fn is_server(&self) -> bool {
        matches!(self.kind, EntityKind::Server { .. })
    }

    /// A client's request: a `get` with the next sequence number, its replies queued.
    fn request(&self, body: Vec<u8>) -> Result<SampleId, DdsError> {
        let EntityKind::Client {
            sender,
            sequence_number,
            ..
        } = &self.kind
        else {
            return Err(DdsError::RelatedSampleIdentityUnsupported);
        };
        let sequence_number = sequence_number.fetch_add(1, Ordering::Relaxed) + 1;
        let attachment = Attachment {
            sequence_number,
            source_timestamp: now_ns(),
            gid: self.gid,
        };
        sender.request(PendingRequest {
            sequence_number,
            payload: with_header(body),
            attachment: attachment.to_bytes().to_vec(),
        })?;
        Ok(SampleId {
            writer: self.gid,
            sequence_number,
        })
    }

    /// A server's reply to the request `related` (a negated sequence number: an error reply).
    fn reply(&self, body: Vec<u8>, related: SampleId) -> Result<SampleId, DdsError> {
        let EntityKind::Server { queries, .. } = &self.kind else {
            return Err(DdsError::RelatedSampleIdentityUnsupported);
        };
        let sequence_number = related.sequence_number.saturating_abs();
        let id = SampleId {
            writer: self.reply_gid,
            sequence_number,
        };
        let Some(query) = lock(queries).take((related.writer, sequence_number)) else {
            tracing::debug!(client = %related.writer, seq = sequence_number, "zenoh: reply dropped: its query is gone");
            return Ok(id);
        };
        let result = if related.sequence_number < 0 {
            query.reply_err(with_header(body)).wait()
        } else {
            let attachment = Attachment {
                sequence_number,
                source_timestamp: now_ns(),
                gid: related.writer,
            };
            query
                .reply(query.key_expr().clone(), with_header(body))
                .attachment(attachment.to_bytes().to_vec())
                .wait()
        };
        result.map_err(|e| zenoh_error(DdsError::Write, e))?;
        Ok(id)
    }
}

/// `body` after the CDR_LE encapsulation header.
fn with_header(body: Vec<u8>) -> Vec<u8> {
    let mut payload = Vec::with_capacity(4 + body.len());
    payload.extend_from_slice(&CDR_LE_HEADER);
    payload.extend_from_slice(&body);
    payload
}

/// A reply to request `sequence_number` of `client`: queued with the request's identity as
/// `related` (from the attachment, as rmw_zenoh's `take_response` reads it); an error reply
/// with the sequence number negated.
fn on_reply(queue: &ReaderQueue, client: Gid, sequence_number: i64, reply: &Reply) {
    let received = horus_ros_rmw_contract::unix_time_ns();
    let incoming = match reply.result() {
        Ok(sample) => {
            let Some(attachment) = queue.attachment_of(sample.attachment(), sample.key_expr())
            else {
                return;
            };
            Incoming {
                payload: sample.payload().clone(),
                related: Some(SampleId {
                    writer: attachment.gid,
                    sequence_number: attachment.sequence_number,
                }),
                attachment,
                received,
            }
        }
        Err(error) => Incoming {
            payload: error.payload().clone(),
            attachment: Attachment {
                sequence_number,
                source_timestamp: received,
                gid: client,
            },
            received,
            related: Some(SampleId {
                writer: client,
                sequence_number: -sequence_number,
            }),
        },
    };
    queue.deliver(incoming);
}

/// A server's reply writer or a client's request writer.
pub(crate) struct ServiceWriter {
    pub(crate) entity: Arc<ServiceEntity>,
    pub(crate) gid: Gid,
    pub(crate) graph: Arc<Graph>,
    pub(crate) deleted: Arc<AtomicBool>,
}

impl WriterBackend for ServiceWriter {
    /// A client's request (`related` is ignored: the attachment carries the client's identity),
    /// or a server's reply to the request `related`.
    fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        _only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        if self.deleted.load(Ordering::SeqCst) {
            return Err(DdsError::ParticipantDeleted);
        }
        if self.entity.is_server() {
            let related = related.ok_or(DdsError::RelatedSampleIdentityUnsupported)?;
            self.entity.reply(body, related)
        } else {
            self.entity.request(body)
        }
    }

    /// At once: a query or reply is sent on reliable links, with nothing to acknowledge.
    fn wait_for_acknowledgments(&self, _timeout: Duration) -> bool {
        true
    }
}

impl Drop for ServiceWriter {
    fn drop(&mut self) {
        self.graph.remove_local(self.gid);
    }
}
