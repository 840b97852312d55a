//! Raw endpoints: readers and writers of pre-serialized CDR bodies with sample identities, for the
//! services layer (request/reply correlation) and anything that encodes its own payloads.
//!
//! Each endpoint is listed under its node in `ros_discovery_info` like any other; a reader can be
//! waited on without polling. Which endpoints are matched is reported by the discovery feed
//! ([`DiscoveryEvent::Matched`](crate::DiscoveryEvent::Matched)): rustdds' per-endpoint status
//! channels hold only 4 events and drop the rest.

use std::time::Duration;

use horus_ros_msgs::TypeHash;
use rustdds::mio1 as mio;
use rustdds::no_key::{DataReader, DataWriter};
use rustdds::{RTPSEntity, SampleIdentity, SequenceNumber, TopicKind, WriteOptionsBuilder};

use crate::dds::raw::{RawAdapter, RawPayload};
use crate::dds::{gid_from_guid, guid_from_gid};
use crate::discovery::DiscoveredEndpoint;
use crate::entities::EndpointSide;
use crate::node::{Node, Registration};
use crate::pubsub::{EndpointError, PublishError, TakeError};
use crate::qos::{EndpointKind, Qos};
use crate::Gid;

const DATA: mio::Token = mio::Token(0);

/// A sample's identity: the GID of the writer that wrote it and its sequence number there
/// (`rmw_request_id_t` / DDS `SampleIdentity`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SampleId {
    /// The writer's GID.
    pub writer: Gid,
    /// The sample's sequence number at that writer.
    pub sequence_number: i64,
}

impl SampleId {
    /// RTPS `SEQUENCENUMBER_UNKNOWN` ({-1, 0}).
    pub const UNKNOWN_SEQUENCE_NUMBER: i64 = -(1 << 32);

    fn from_dds(s: SampleIdentity) -> Self {
        Self {
            writer: gid_from_guid(s.writer_guid),
            sequence_number: s.sequence_number.into(),
        }
    }

    fn to_dds(self) -> SampleIdentity {
        SampleIdentity {
            writer_guid: guid_from_gid(self.writer),
            sequence_number: SequenceNumber::new(self.sequence_number),
        }
    }
}

/// A sample taken from a [`RawReader`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawSample {
    /// The CDR body (after the 4-byte encapsulation header).
    pub body: Vec<u8>,
    /// Whether the body is big-endian (CDR_BE) rather than little-endian.
    pub big_endian: bool,
    /// The sample's own identity (writer GID and sequence number).
    pub id: SampleId,
    /// The `related_sample_identity` inline QoS it carried, if any (PID 0x0083 or 0x800f).
    pub related: Option<SampleId>,
}

/// What a raw endpoint is: its DDS topic and type, and the hash and QoS it is listed with.
#[derive(Clone, Debug)]
pub struct RawEndpointSpec {
    /// The DDS topic name, already mangled (e.g. `rq/add_two_intsRequest`).
    pub dds_topic_name: String,
    /// The DDS type name (e.g. `example_interfaces::srv::dds_::AddTwoInts_Request_`).
    pub dds_type_name: String,
    /// The RIHS01 hash of the type.
    pub type_hash: TypeHash,
    /// The QoS.
    pub qos: Qos,
}

fn create_topic(
    node: &Node,
    spec: &RawEndpointSpec,
    dds_qos: &rustdds::QosPolicies,
) -> Result<rustdds::Topic, EndpointError> {
    node.context()
        .inner()
        .participant
        .create_topic(
            spec.dds_topic_name.clone(),
            spec.dds_type_name.clone(),
            dds_qos,
            TopicKind::NoKey,
        )
        .map_err(|e| EndpointError::Dds {
            kind: "topic",
            topic: spec.dds_topic_name.clone(),
            reason: e.to_string(),
        })
}

fn describe(
    node: &Node,
    spec: &RawEndpointSpec,
    gid: Gid,
    kind: EndpointKind,
) -> DiscoveredEndpoint {
    DiscoveredEndpoint {
        gid,
        participant_gid: node.context().gid(),
        kind,
        dds_topic_name: spec.dds_topic_name.clone(),
        dds_type_name: spec.dds_type_name.clone(),
        qos: spec.qos.effective(kind),
        type_hash: spec.type_hash,
        user_data: Vec::new(),
    }
}

/// Waits on `poll` until it signals or `timeout` passes; returns whether it signalled.
fn wait_on(poll: &mut mio::Poll, timeout: Duration) -> bool {
    let mut events = mio::Events::with_capacity(4);
    match poll.poll(&mut events, Some(timeout)) {
        Ok(()) => !events.is_empty(),
        Err(e) => {
            tracing::debug!("poll failed: {e}");
            false
        }
    }
}

/// Writes raw CDR bodies, optionally with a `related_sample_identity`.
pub struct RawWriter {
    // Dropped first: withdrawn from ros_discovery_info before the writer is deleted.
    registration: Registration,
    topic: String,
    writer: DataWriter<RawPayload, RawAdapter>,
}

impl std::fmt::Debug for RawWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RawWriter")
            .field("gid", &self.gid())
            .finish()
    }
}

/// Reads raw CDR bodies with their sample identities.
pub struct RawReader {
    registration: Registration,
    poll: mio::Poll,
    topic: String,
    reader: DataReader<RawPayload, RawAdapter>,
}

impl std::fmt::Debug for RawReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RawReader")
            .field("gid", &self.gid())
            .finish()
    }
}

impl Node {
    /// Creates a raw writer on an already-mangled DDS topic.
    pub fn create_raw_writer(&self, spec: &RawEndpointSpec) -> Result<RawWriter, EndpointError> {
        let dds_qos =
            spec.qos
                .to_dds(EndpointKind::Writer)
                .map_err(|source| EndpointError::InvalidQos {
                    name: spec.dds_topic_name.clone(),
                    source,
                })?;
        let topic = create_topic(self, spec, &dds_qos)?;
        let writer = self
            .context()
            .inner()
            .publisher
            .create_datawriter_no_key::<RawPayload, RawAdapter>(&topic, Some(dds_qos))
            .map_err(|e| EndpointError::Dds {
                kind: "writer",
                topic: spec.dds_topic_name.clone(),
                reason: e.to_string(),
            })?;
        let gid = gid_from_guid(writer.guid());
        let registration = Registration::new(
            self,
            EndpointSide::Writer,
            describe(self, spec, gid, EndpointKind::Writer),
        );
        Ok(RawWriter {
            registration,
            topic: spec.dds_topic_name.clone(),
            writer,
        })
    }

    /// Creates a raw reader on an already-mangled DDS topic.
    pub fn create_raw_reader(&self, spec: &RawEndpointSpec) -> Result<RawReader, EndpointError> {
        let dds_qos =
            spec.qos
                .to_dds(EndpointKind::Reader)
                .map_err(|source| EndpointError::InvalidQos {
                    name: spec.dds_topic_name.clone(),
                    source,
                })?;
        let topic = create_topic(self, spec, &dds_qos)?;
        let mut reader = self
            .context()
            .inner()
            .subscriber
            .create_datareader_no_key::<RawPayload, RawAdapter>(&topic, Some(dds_qos))
            .map_err(|e| EndpointError::Dds {
                kind: "reader",
                topic: spec.dds_topic_name.clone(),
                reason: e.to_string(),
            })?;
        let gid = gid_from_guid(reader.guid());
        let fail = |e: std::io::Error| EndpointError::Dds {
            kind: "poll",
            topic: spec.dds_topic_name.clone(),
            reason: e.to_string(),
        };
        let poll = mio::Poll::new().map_err(fail)?;
        // rustdds' mio 1 sources are drained by take/try_recv, so edge-triggered waking works
        // (its mio 0.6 readiness fires only once: it is never drained).
        poll.registry()
            .register(&mut reader, DATA, mio::Interest::READABLE)
            .map_err(fail)?;
        let registration = Registration::new(
            self,
            EndpointSide::Reader,
            describe(self, spec, gid, EndpointKind::Reader),
        );
        Ok(RawReader {
            registration,
            poll,
            topic: spec.dds_topic_name.clone(),
            reader,
        })
    }
}

impl RawWriter {
    /// The writer's GID.
    pub fn gid(&self) -> Gid {
        self.registration.gid()
    }

    /// Writes `body` (a CDR_LE body) and returns the sample's identity. With `related`, the sample
    /// carries it as `related_sample_identity` (under both PIDs 0x0083 and 0x800f); with `only_to`,
    /// it is sent to that one matched reader only.
    pub fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, PublishError> {
        let mut options = WriteOptionsBuilder::new();
        if let Some(r) = related {
            options = options.related_sample_identity(r.to_dds());
        }
        if let Some(reader) = only_to {
            options = options.to_single_reader(guid_from_gid(reader));
        }
        self.writer
            .write_with_options(
                RawPayload {
                    big_endian: false,
                    body,
                },
                options.build(),
            )
            .map(SampleId::from_dds)
            .map_err(|e| PublishError {
                topic: self.topic.clone(),
                reason: e.to_string(),
            })
    }
}

impl RawReader {
    /// The reader's GID.
    pub fn gid(&self) -> Gid {
        self.registration.gid()
    }

    /// Takes the next sample, if any (non-blocking). A sample the DDS layer could not decode is
    /// reported as an error and dropped; the next call goes on with the following one.
    pub fn take(&mut self) -> Result<Option<RawSample>, TakeError> {
        match self.reader.take_next_sample() {
            Ok(Some(sample)) => {
                let info = sample.sample_info();
                let id = SampleId::from_dds(info.sample_identity());
                let related = info.related_sample_identity().map(SampleId::from_dds);
                let payload = sample.into_value();
                Ok(Some(RawSample {
                    body: payload.body,
                    big_endian: payload.big_endian,
                    id,
                    related,
                }))
            }
            Ok(None) => Ok(None),
            Err(e) => Err(TakeError {
                topic: self.topic.clone(),
                reason: e.to_string(),
            }),
        }
    }

    /// Waits until data may be there, at most `timeout`; returns whether something was
    /// signalled. Take until `None` after it: wake-ups are edge-triggered.
    pub fn wait(&mut self, timeout: Duration) -> bool {
        wait_on(&mut self.poll, timeout)
    }
}
