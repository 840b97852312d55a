//! `horus-ros service echo --passive` (our own): prints a service's requests and replies, paired,
//! with the time between them, read from the service's own DDS topics, so that it works without
//! the server's or the client's cooperation (ros2cli's `service echo` needs introspection on).
//!
//! Two raw readers, listed under no node in `ros_discovery_info`
//! ([`Node::create_raw_reader_unlisted`]), read `rq/<service>Request` and `rr/<service>Reply`.
//! Each sample's correlation is read in the convention its writer follows
//! ([`WireFlavour`]):
//!
//! - rmw_fastrtps: a request is identified by its `related_sample_identity`'s GUID (the
//!   client's reply reader; the request writer's own GUID where a request carries none) and its
//!   own sequence number; the reply carries that pair as its `related_sample_identity`
//!   (rmw_fastrtps_shared_cpp jazzy `rmw_service.cpp` `__rmw_take_request`, `rmw_response.cpp`
//!   `__rmw_send_response`). Backends that do not report sample identities (Cyclone DDS) cannot
//!   pair such traffic: its requests and replies are printed unpaired, saying so.
//! - rmw_cyclonedds: both bodies begin with `cdds_request_header_t { uint64 guid; int64 seq; }`
//!   (rmw_cyclonedds_cpp jazzy `serdata.hpp`); the message follows.
//!
//! A reply is paired with the request of the same client and sequence number; the latency is
//! the time between the two samples' arrival here. Requests without a reply within
//! `--reply-timeout` are printed as `no_response`; replies whose request was not seen (e.g. sent
//! before the echo started) as `response_only`. At most `--max-outstanding` requests (and as
//! many replies) wait to be paired: beyond that the oldest is dropped, and the drops are counted
//! on stderr.
//!
//! The readers are still announced by DDS discovery (no DDS reader is matched otherwise), and
//! so is a reply writer that never writes, which keeps rmw_fastrtps clients taking the service
//! for available (they require as many request readers as reply writers): graphs see three
//! endpoints of no node, so no node lists a server or client (`ros2 node info`, a node's
//! services and clients), but counts by topic alone see one more server and one more client
//! (rmw_fastrtps' `rmw_count_services` counts writers on `rr/<service>Reply`,
//! `rmw_count_clients` readers there).

use std::collections::VecDeque;
use std::io::Write;
use std::sync::mpsc;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use horus_ros_msgs::dds_type_name;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::{EndpointKind, HistoryPolicy, Qos};
use horus_ros_rmw::service::{vendor_hint, CycloneHeader};
use horus_ros_rmw::{Gid, RawEndpointSpec, RawReader, RawSample, SampleId, VendorId};
use serde_json::{json, Value as Json};

use crate::dynamic::convert::{to_ordereddict, ConvertOptions};
use crate::dynamic::json::to_json;
use crate::dynamic::pyyaml::{dump, PyValue};
use crate::dynamic::{cdr, ServiceType};
use crate::session::Session;
use crate::CliError;

/// History depth of the two readers: samples wait there only until the reader threads take
/// them.
const READER_DEPTH: usize = 4096;

/// How long the readers wait to be matched with the writers discovery lists before reading.
const MATCH_WAIT: Duration = Duration::from_secs(5);

/// How the output is written.
#[derive(Clone, Copy, Debug)]
pub struct PassiveOptions {
    /// One JSON object per line.
    pub json: bool,
    /// YAML flow style for collections.
    pub flow_style: bool,
    /// Truncation and omission of fields.
    pub convert: ConvertOptions,
    /// How long a request waits for its reply.
    pub reply_timeout: Duration,
    /// How many requests (and replies) wait to be paired at most.
    pub max_outstanding: usize,
    /// Exit after this many printed records (for tests).
    pub count: Option<u64>,
}

/// Which convention a sample was read in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Convention {
    FastRtps,
    CycloneDds,
}

impl Convention {
    fn name(self) -> &'static str {
        match self {
            Self::FastRtps => "rmw_fastrtps",
            Self::CycloneDds => "rmw_cyclonedds",
        }
    }
}

/// What pairs a request with its reply: the client and the request's sequence number there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Key {
    /// rmw_fastrtps: a GUID (the client's reply reader, or its request writer).
    Fast { guid: Gid, seq: i64 },
    /// rmw_cyclonedds: the header's client id.
    Cyclone { client: u64, seq: i64 },
}

impl Key {
    fn client(self) -> String {
        match self {
            Self::Fast { guid, .. } => dotted(guid.as_bytes()),
            Self::Cyclone { client, .. } => format!("{client:016x}"),
        }
    }

    fn seq(self) -> i64 {
        match self {
            Self::Fast { seq, .. } | Self::Cyclone { seq, .. } => seq,
        }
    }
}

/// A GID as `01.0f.…` (as `service echo --json` writes `client_gid`).
fn dotted(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(".")
}

/// Which side a sample was read on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Request,
    Reply,
}

/// A sample as a reader thread hands it over.
struct Arrival {
    side: Side,
    sample: RawSample,
    at: Instant,
    wall: SystemTime,
}

/// A sample's correlation and message, read in its convention.
struct Read {
    /// What pairs it (a request may be known by two); empty where it cannot be read here.
    keys: Vec<Key>,
    convention: Convention,
    /// The message's CDR body (after any header).
    body: Vec<u8>,
    /// Why it cannot be paired, where it cannot.
    unpairable: Option<&'static str>,
}

/// Why Fast DDS traffic cannot be paired on a backend without sample identities.
const NO_IDENTITY: &str = "this backend does not report sample identities, which pair \
     rmw_fastrtps requests and replies; use the rustdds backend (HORUS_ROS_BACKEND=rustdds)";

/// Reads a sample's correlation in the convention its writer follows: a sample with a
/// `related_sample_identity` follows rmw_fastrtps'; one from a Cyclone DDS writer, or from a
/// writer of another vendor that carries none (a horus-ros peer speaking rmw_cyclonedds'), the
/// in-payload header; a Fast DDS writer's sample without one follows rmw_fastrtps' and can be
/// paired only where the backend reports sequence numbers.
fn read_sample(side: Side, s: &RawSample) -> Read {
    let vendor = vendor_hint(s.id.writer);
    let fast = |keys: Vec<Key>, unpairable| Read {
        keys,
        convention: Convention::FastRtps,
        body: s.body.clone(),
        unpairable,
    };
    let id_known = s.id.sequence_number != SampleId::UNKNOWN_SEQUENCE_NUMBER;
    match (side, s.related) {
        (Side::Request, Some(related)) => {
            let seq = s.id.sequence_number;
            let mut keys = vec![Key::Fast {
                guid: related.writer,
                seq,
            }];
            if related.writer != s.id.writer {
                keys.push(Key::Fast {
                    guid: s.id.writer,
                    seq,
                });
            }
            fast(keys, None)
        }
        (Side::Reply, Some(related))
            if related.sequence_number != SampleId::UNKNOWN_SEQUENCE_NUMBER =>
        {
            fast(
                vec![Key::Fast {
                    guid: related.writer,
                    seq: related.sequence_number,
                }],
                None,
            )
        }
        _ if vendor == Some(VendorId::FAST_DDS) => match side {
            Side::Request if id_known => fast(
                vec![Key::Fast {
                    guid: s.id.writer,
                    seq: s.id.sequence_number,
                }],
                None,
            ),
            _ => fast(Vec::new(), Some(NO_IDENTITY)),
        },
        _ => match CycloneHeader::split(&s.body, s.big_endian) {
            Some((header, message)) => Read {
                keys: vec![Key::Cyclone {
                    client: header.guid,
                    seq: header.seq,
                }],
                convention: Convention::CycloneDds,
                body: message.to_vec(),
                unpairable: None,
            },
            None => Read {
                keys: Vec::new(),
                convention: Convention::CycloneDds,
                body: Vec::new(),
                unpairable: Some("shorter than rmw_cyclonedds' request header"),
            },
        },
    }
}

/// A request or reply waiting for its other half.
struct Waiting {
    keys: Vec<Key>,
    convention: Convention,
    value: Decoded,
    at: Instant,
    wall: SystemTime,
}

/// A decoded message, or why it could not be decoded.
type Decoded = Result<crate::dynamic::Value, String>;

/// One printed record.
struct Record<'a> {
    status: &'static str,
    convention: Convention,
    key: Option<Key>,
    stamp: SystemTime,
    latency: Option<Duration>,
    request: Option<&'a Decoded>,
    response: Option<&'a Decoded>,
    note: Option<&'static str>,
}

/// Runs `service echo --passive` on `service` of `info`'s type.
pub fn run(
    session: &Session,
    service: &ServiceName,
    info: &ServiceType,
    options: PassiveOptions,
) -> Result<(), CliError> {
    let mut qos = Qos::services_default();
    if qos.history == HistoryPolicy::KeepLast {
        qos.depth = qos.depth.max(READER_DEPTH);
    }
    let (request_hash, response_hash) = info.part_hashes();
    let request_spec = RawEndpointSpec {
        dds_topic_name: service.to_dds_request_topic_name(false),
        dds_type_name: dds_type_name(info.request_type()),
        type_hash: request_hash,
        qos,
        service_id: None,
    };
    let reply_spec = RawEndpointSpec {
        dds_topic_name: service.to_dds_reply_topic_name(false),
        dds_type_name: dds_type_name(info.response_type()),
        type_hash: response_hash,
        qos,
        service_id: None,
    };
    // rmw_fastrtps clients take a service for available only while they see as many readers
    // on rq/ as writers on rr/ (rmw_fastrtps_shared_cpp jazzy `rmw_service_server_is_available`
    // `number_of_request_subscribers != number_of_response_publishers`): the request reader
    // alone would make every such client wait for the service. A reply writer that never
    // writes balances it, created right beside it.
    let mut balance_spec = reply_spec.clone();
    balance_spec.qos = Qos::services_default();
    let balance = session.node.create_raw_writer_unlisted(&balance_spec)?;
    let mut requests = session.node.create_raw_reader_unlisted(&request_spec)?;
    let mut replies = session.node.create_raw_reader_unlisted(&reply_spec)?;
    tracing::debug!(
        requests = %requests.gid(),
        replies = %replies.gid(),
        ?request_spec,
        "passive echo: reading"
    );
    start_matched(
        session,
        [
            (&mut requests, &request_spec.dds_topic_name),
            (&mut replies, &reply_spec.dds_topic_name),
        ],
        &[balance.gid()],
    );
    if !session.context.capabilities().carries_sample_identity {
        eprintln!(
            "Note: on this backend, requests and replies of rmw_fastrtps peers cannot be paired \
             ({NO_IDENTITY}); rmw_cyclonedds peers' can."
        );
    }
    let (tx, rx) = mpsc::channel();
    spawn_reader(Side::Request, requests, tx.clone())?;
    spawn_reader(Side::Reply, replies, tx)?;

    let mut pairing = Pairing::new(options.max_outstanding);
    let mut printer = Printer {
        info,
        options,
        printed: 0,
        out: std::io::stdout(),
    };
    loop {
        let wait = pairing
            .next_expiry(options.reply_timeout)
            .map(|t| t.saturating_duration_since(Instant::now()));
        let arrival = match wait {
            Some(w) => match rx.recv_timeout(w) {
                Ok(a) => Some(a),
                Err(mpsc::RecvTimeoutError::Timeout) => None,
                Err(mpsc::RecvTimeoutError::Disconnected) => return Ok(()),
            },
            None => match rx.recv() {
                Ok(a) => Some(a),
                Err(_) => return Ok(()),
            },
        };
        if let Some(a) = arrival {
            if !pairing.arrive(a, info, &mut printer) {
                return Ok(());
            }
        }
        if !pairing.expire(Instant::now(), options.reply_timeout, &mut printer) {
            return Ok(());
        }
    }
}

/// Waits, at most [`MATCH_WAIT`] in all, until each reader is matched with every writer
/// discovery lists on its DDS topic (but `ours`), then discards what they read until then: a
/// request read before the reply reader was matched with its server's reply writer would be
/// printed as `no_response` although it was answered. Says on stderr when the bound is hit.
fn start_matched(session: &Session, readers: [(&mut RawReader, &str); 2], ours: &[Gid]) {
    let deadline = Instant::now() + MATCH_WAIT;
    for (reader, topic) in readers {
        let left = deadline.saturating_duration_since(Instant::now());
        if !session.graph.wait_for_all_matched(
            reader.gid(),
            topic,
            EndpointKind::Writer,
            ours,
            left,
        ) {
            eprintln!(
                "Warning: not matched with every writer on {topic} after {} s: the first \
                 records may be incomplete",
                MATCH_WAIT.as_secs()
            );
        }
        while let Ok(Some(_)) = reader.take() {}
    }
}

/// Takes `reader`'s samples on a thread of its own, stamped as they arrive.
fn spawn_reader(
    side: Side,
    mut reader: RawReader,
    tx: mpsc::Sender<Arrival>,
) -> Result<(), CliError> {
    std::thread::Builder::new()
        .name(format!("passive-{side:?}").to_lowercase())
        .spawn(move || loop {
            reader.wait(None);
            loop {
                match reader.take() {
                    Ok(Some(sample)) => {
                        tracing::debug!(
                            ?side,
                            id = ?sample.id,
                            related = ?sample.related,
                            "passive echo: a sample"
                        );
                        let arrival = Arrival {
                            side,
                            sample,
                            at: Instant::now(),
                            wall: SystemTime::now(),
                        };
                        if tx.send(arrival).is_err() {
                            return;
                        }
                    }
                    Ok(None) => break,
                    Err(e) => tracing::warn!("dropped a sample: {e}"),
                }
            }
        })
        .map(drop)
        .map_err(|e| CliError::new(format!("Could not start a reader thread: {e}")))
}

/// Requests waiting for replies and replies waiting for requests, oldest first, each bounded.
struct Pairing {
    max: usize,
    requests: VecDeque<Waiting>,
    replies: VecDeque<Waiting>,
    dropped: u64,
}

impl Pairing {
    fn new(max: usize) -> Self {
        Self {
            max: max.max(1),
            requests: VecDeque::new(),
            replies: VecDeque::new(),
            dropped: 0,
        }
    }

    /// When the oldest waiting sample expires.
    fn next_expiry(&self, timeout: Duration) -> Option<Instant> {
        [self.requests.front(), self.replies.front()]
            .into_iter()
            .flatten()
            .map(|w| w.at + timeout)
            .min()
    }

    /// Handles one sample; `false` when output should end.
    fn arrive(&mut self, a: Arrival, info: &ServiceType, printer: &mut Printer<'_>) -> bool {
        let read = read_sample(a.side, &a.sample);
        let type_name = match a.side {
            Side::Request => info.request_type(),
            Side::Reply => info.response_type(),
        };
        let value = cdr::decode(info.schema(), type_name, &read.body, a.sample.big_endian)
            .map_err(|e| e.to_string());
        if let Some(note) = read.unpairable {
            let (request, response) = match a.side {
                Side::Request => (Some(&value), None),
                Side::Reply => (None, Some(&value)),
            };
            return printer.print(&Record {
                status: match a.side {
                    Side::Request => "request_only",
                    Side::Reply => "response_only",
                },
                convention: read.convention,
                key: None,
                stamp: a.wall,
                latency: None,
                request,
                response,
                note: Some(note),
            });
        }
        let (mine, theirs) = match a.side {
            Side::Request => (&mut self.requests, &mut self.replies),
            Side::Reply => (&mut self.replies, &mut self.requests),
        };
        let found = theirs
            .iter()
            .position(|w| w.keys.iter().any(|k| read.keys.contains(k)));
        if let Some(i) = found {
            let Some(other) = theirs.remove(i) else {
                return true;
            };
            let key = read.keys.first().copied();
            let (request, response, latency) = match a.side {
                Side::Request => (
                    &value,
                    &other.value,
                    other.at.saturating_duration_since(a.at),
                ),
                Side::Reply => (
                    &other.value,
                    &value,
                    a.at.saturating_duration_since(other.at),
                ),
            };
            let stamp = match a.side {
                Side::Request => a.wall,
                Side::Reply => other.wall,
            };
            return printer.print(&Record {
                status: "paired",
                convention: read.convention,
                key,
                stamp,
                latency: Some(latency),
                request: Some(request),
                response: Some(response),
                note: None,
            });
        }
        if mine.len() >= self.max {
            mine.pop_front();
            self.dropped += 1;
            eprintln!(
                "Dropped the oldest unpaired {} (more than {} waiting; {} dropped so far)",
                match a.side {
                    Side::Request => "request",
                    Side::Reply => "reply",
                },
                self.max,
                self.dropped
            );
        }
        mine.push_back(Waiting {
            keys: read.keys,
            convention: read.convention,
            value,
            at: a.at,
            wall: a.wall,
        });
        true
    }

    /// Prints the samples that waited longer than `timeout`; `false` when output should end.
    fn expire(&mut self, now: Instant, timeout: Duration, printer: &mut Printer<'_>) -> bool {
        for side in [Side::Request, Side::Reply] {
            let queue = match side {
                Side::Request => &mut self.requests,
                Side::Reply => &mut self.replies,
            };
            while queue.front().is_some_and(|w| w.at + timeout <= now) {
                let Some(w) = queue.pop_front() else { break };
                let value = &w.value;
                let (status, request, response) = match side {
                    Side::Request => ("no_response", Some(value), None),
                    Side::Reply => ("response_only", None, Some(value)),
                };
                let ok = printer.print(&Record {
                    status,
                    convention: w.convention,
                    key: w.keys.first().copied(),
                    stamp: w.wall,
                    latency: None,
                    request,
                    response,
                    note: None,
                });
                if !ok {
                    return false;
                }
            }
        }
        true
    }
}

/// Writes records as YAML documents or JSON lines.
struct Printer<'a> {
    info: &'a ServiceType,
    options: PassiveOptions,
    printed: u64,
    out: std::io::Stdout,
}

impl Printer<'_> {
    /// Prints one record; `false` when output should end (stdout closed, or `--count` reached).
    fn print(&mut self, r: &Record<'_>) -> bool {
        let text = if self.options.json {
            serde_json::to_string(&self.json(r)).unwrap_or_default()
        } else {
            let mut t = dump(&self.yaml(r), self.options.flow_style);
            t.push_str("---");
            t
        };
        let mut out = self.out.lock();
        if writeln!(out, "{text}").and_then(|()| out.flush()).is_err() {
            return false;
        }
        self.printed += 1;
        self.options.count.is_none_or(|n| self.printed < n)
    }

    fn yaml(&self, r: &Record<'_>) -> PyValue {
        let mut m = vec![
            ("status".to_owned(), PyValue::Str(r.status.to_owned())),
            (
                "convention".to_owned(),
                PyValue::Str(r.convention.name().to_owned()),
            ),
        ];
        if let Some(k) = r.key {
            m.push(("client".to_owned(), PyValue::Str(k.client())));
            m.push(("sequence_number".to_owned(), PyValue::Int(k.seq().into())));
        }
        let (sec, nanosec) = stamp(r.stamp);
        m.push((
            "stamp".to_owned(),
            PyValue::Map(vec![
                ("sec".to_owned(), PyValue::Int(sec.into())),
                ("nanosec".to_owned(), PyValue::Int(nanosec.into())),
            ]),
        ));
        if let Some(l) = r.latency {
            m.push(("latency".to_owned(), PyValue::Float(l.as_secs_f64())));
        }
        let o = self.options.convert;
        let schema = self.info.schema();
        for (field, value, type_name) in [
            ("request", r.request, self.info.request_type()),
            ("response", r.response, self.info.response_type()),
        ] {
            match value {
                Some(Ok(v)) => m.push((field.to_owned(), to_ordereddict(schema, type_name, v, o))),
                Some(Err(e)) => m.push((
                    field.to_owned(),
                    PyValue::Str(format!("<could not decode: {e}>")),
                )),
                None => {}
            }
        }
        if let Some(n) = r.note {
            m.push(("note".to_owned(), PyValue::Str(n.to_owned())));
        }
        PyValue::Map(m)
    }

    fn json(&self, r: &Record<'_>) -> Json {
        let schema = self.info.schema();
        let part = |value: Option<&Decoded>, type_name: &str| match value {
            Some(Ok(v)) => to_json(schema, type_name, v),
            Some(Err(e)) => json!({ "error": e }),
            None => Json::Null,
        };
        let (sec, nanosec) = stamp(r.stamp);
        json!({
            "status": r.status,
            "convention": r.convention.name(),
            "client": r.key.map(Key::client),
            "sequence_number": r.key.map(Key::seq),
            "stamp": { "sec": sec, "nanosec": nanosec },
            "latency": r.latency.map(|l| l.as_secs_f64()),
            "request": part(r.request, self.info.request_type()),
            "response": part(r.response, self.info.response_type()),
            "note": r.note,
        })
    }
}

/// Seconds and nanoseconds since the epoch.
fn stamp(t: SystemTime) -> (i64, u32) {
    let d = t.duration_since(UNIX_EPOCH).unwrap_or_default();
    (
        i64::try_from(d.as_secs()).unwrap_or(i64::MAX),
        d.subsec_nanos(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(writer: [u8; 16], seq: i64, related: Option<SampleId>, body: Vec<u8>) -> RawSample {
        RawSample {
            body,
            big_endian: false,
            id: SampleId {
                writer: Gid::from_bytes(writer),
                sequence_number: seq,
            },
            related,
            publication_handle: None,
            source_timestamp: None,
            received_timestamp: 0,
        }
    }

    #[test]
    fn fast_rtps_requests_pair_with_replies_by_reader_guid_and_sequence_number() {
        let mut client_writer = [0u8; 16];
        client_writer[..2].copy_from_slice(&VendorId::FAST_DDS.0);
        client_writer[15] = 0x03;
        let mut client_reader = client_writer;
        client_reader[15] = 0x04;
        let mut server_writer = [7u8; 16];
        server_writer[..2].copy_from_slice(&VendorId::FAST_DDS.0);
        let related = SampleId {
            writer: Gid::from_bytes(client_reader),
            sequence_number: SampleId::UNKNOWN_SEQUENCE_NUMBER,
        };
        let request = read_sample(
            Side::Request,
            &sample(client_writer, 5, Some(related), vec![]),
        );
        let reply_related = SampleId {
            writer: Gid::from_bytes(client_reader),
            sequence_number: 5,
        };
        let reply = read_sample(
            Side::Reply,
            &sample(server_writer, 1, Some(reply_related), vec![]),
        );
        assert!(reply.keys.iter().any(|k| request.keys.contains(k)));
        assert_eq!(reply.convention, Convention::FastRtps);
        // Seen without identities (the Cyclone backend): printed, never paired.
        let blind = read_sample(
            Side::Reply,
            &sample(
                server_writer,
                SampleId::UNKNOWN_SEQUENCE_NUMBER,
                None,
                vec![],
            ),
        );
        assert!(blind.keys.is_empty() && blind.unpairable.is_some());
    }

    #[test]
    fn cyclone_headers_pair_and_are_stripped() {
        let mut writer = [0u8; 16];
        writer[..2].copy_from_slice(&VendorId::CYCLONE_DDS.0);
        let header = CycloneHeader { guid: 42, seq: 3 };
        let body = header.prepend(&[1, 0, 0, 0]);
        let request = read_sample(
            Side::Request,
            &sample(
                writer,
                SampleId::UNKNOWN_SEQUENCE_NUMBER,
                None,
                body.clone(),
            ),
        );
        let reply = read_sample(
            Side::Reply,
            &sample(writer, SampleId::UNKNOWN_SEQUENCE_NUMBER, None, body),
        );
        assert_eq!(request.keys, reply.keys);
        assert_eq!(request.body, vec![1, 0, 0, 0]);
        assert_eq!(request.convention, Convention::CycloneDds);
    }
}
