//! Raw CDR writers and readers: the rustdds side of `RawWriter`/`RawReader` and so of the typed
//! publishers and subscriptions (the Cyclone side is `cyclone/endpoints.rs`).

use std::sync::Arc;
use std::time::Duration;

use horus_ros_msgs::rmw_dds_common::Gid;
use rustdds::mio1 as mio;
use rustdds::no_key::{DataReader, DataWriter};
use rustdds::{RTPSEntity, SampleIdentity, SequenceNumber, TopicKind, WriteOptionsBuilder};

use super::raw::{RawAdapter, RawPayload};
use super::wait_set::{wait_on, WaitSet, Waker};
use super::{gid_from_guid, guid_from_gid, qos, RustddsParticipant};
use crate::contract::WaitSetError;
use crate::contract::{unix_time_ns, RawEndpointSpec, RawSample, SampleId};
use crate::contract::{ReaderBackend, WaitSetBackend, Wake, WriterBackend};
use crate::dds_error::{boxed, DdsError};
use horus_ros_rmw_contract::qos::DdsQos;

/// Poll token of a reader's data.
const DATA: usize = 0;
/// Poll token of a reader's waker.
const WAKE: usize = 1;

fn sample_id(s: SampleIdentity) -> SampleId {
    SampleId {
        writer: gid_from_guid(s.writer_guid),
        sequence_number: s.sequence_number.into(),
    }
}

fn sample_identity(id: SampleId) -> SampleIdentity {
    SampleIdentity {
        writer_guid: guid_from_gid(id.writer),
        sequence_number: SequenceNumber::new(id.sequence_number),
    }
}

/// The topic `topic_name` of type `type_name` (raw bodies: rustdds only moves bytes).
fn topic(
    p: &RustddsParticipant,
    topic_name: &str,
    type_name: &str,
    policies: &rustdds::QosPolicies,
) -> Result<rustdds::Topic, DdsError> {
    p.participant()?
        .create_topic(
            topic_name.to_owned(),
            type_name.to_owned(),
            policies,
            TopicKind::NoKey,
        )
        .map_err(|e| DdsError::Topic(boxed(e)))
}

/// A raw writer.
pub(crate) struct RawWriter {
    writer: DataWriter<RawPayload, RawAdapter>,
}

impl RawWriter {
    /// Creates a writer of the spec's topic and type with this QoS (rustdds cannot send
    /// endpoint USER_DATA).
    pub(crate) fn create(
        p: &RustddsParticipant,
        spec: &RawEndpointSpec,
        policies: &DdsQos,
    ) -> Result<(Self, Gid), DdsError> {
        let policies = qos::to_rustdds(policies);
        let topic = topic(p, &spec.dds_topic_name, &spec.dds_type_name, &policies)?;
        let writer = p
            .publisher
            .create_datawriter_no_key::<RawPayload, RawAdapter>(&topic, Some(policies))
            .map_err(|e| DdsError::Create(boxed(e)))?;
        let gid = gid_from_guid(writer.guid());
        Ok((Self { writer }, gid))
    }
}

impl WriterBackend for RawWriter {
    /// Writes a CDR_LE body stamped with the current time, with `related` as its
    /// `related_sample_identity` (rustdds sends it under both PIDs 0x0083 and 0x800f) and to the
    /// one matched reader `only_to` if given; returns the sample's identity.
    fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        // Stamped as Fast DDS stamps every sample (INFO_TS): readers' `source_timestamp`.
        let mut options = WriteOptionsBuilder::new().source_timestamp(rustdds::Timestamp::now());
        if let Some(r) = related {
            options = options.related_sample_identity(sample_identity(r));
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
            .map(sample_id)
            .map_err(|e| DdsError::Write(boxed(e.forget_data())))
    }

    fn wait_for_acknowledgments(&self, timeout: Duration) -> bool {
        self.writer
            .wait_for_acknowledgments(timeout)
            .unwrap_or(false)
    }
}

/// A raw reader with its own poll (edge-triggered on data).
pub(crate) struct RawReader {
    poll: mio::Poll,
    reader: DataReader<RawPayload, RawAdapter>,
    waker: Waker,
}

impl RawReader {
    /// Creates a reader of the spec's topic and type with this QoS.
    pub(crate) fn create(
        p: &RustddsParticipant,
        spec: &RawEndpointSpec,
        policies: &DdsQos,
    ) -> Result<(Self, Gid), DdsError> {
        let policies = qos::to_rustdds(policies);
        let topic = topic(p, &spec.dds_topic_name, &spec.dds_type_name, &policies)?;
        let mut reader = p
            .subscriber
            .create_datareader_no_key::<RawPayload, RawAdapter>(&topic, Some(policies))
            .map_err(|e| DdsError::Create(boxed(e)))?;
        let gid = gid_from_guid(reader.guid());
        let fail = DdsError::Poll;
        let poll = mio::Poll::new().map_err(fail)?;
        poll.registry()
            .register(&mut reader, mio::Token(DATA), mio::Interest::READABLE)
            .map_err(fail)?;
        let waker = Waker::new(&poll, WAKE).map_err(fail)?;
        Ok((
            Self {
                poll,
                reader,
                waker,
            },
            gid,
        ))
    }
}

impl ReaderBackend for RawReader {
    /// Takes the next sample, if any; one rustdds could not decode is consumed and reported as
    /// an error.
    fn take(&mut self) -> Result<Option<RawSample>, DdsError> {
        let Some(sample) = self
            .reader
            .take_next_sample()
            .map_err(|e| DdsError::Read(boxed(e)))?
        else {
            return Ok(None);
        };
        let info = sample.sample_info();
        let id = sample_id(info.sample_identity());
        let related = info.related_sample_identity().map(sample_id);
        let source_timestamp = info.source_timestamp().and_then(timestamp_ns);
        let payload = sample.into_value();
        Ok(Some(RawSample {
            body: payload.body,
            big_endian: payload.big_endian,
            id,
            related,
            publication_handle: None,
            source_timestamp,
            received_timestamp: unix_time_ns(),
        }))
    }

    /// Moves this reader's data from its own poll to the set's, under `key` (a mio source is
    /// registered with one poll at a time; rustdds' poll forgets it when the reader is gone).
    fn attach_to(&mut self, set: &dyn WaitSetBackend, key: usize) -> Result<(), WaitSetError> {
        let set = set
            .as_any()
            .downcast_ref::<WaitSet>()
            .ok_or(WaitSetError::OtherBackend)?;
        let fail = |e| WaitSetError::Dds(DdsError::Io(e));
        self.poll
            .registry()
            .deregister(&mut self.reader)
            .map_err(fail)?;
        set.registry
            .register(&mut self.reader, mio::Token(key), mio::Interest::READABLE)
            .map_err(fail)
    }

    fn wait(&mut self, timeout: Option<Duration>) -> bool {
        wait_on(&mut self.poll, timeout)
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::new(self.waker.clone())
    }
}

/// An RTPS `Time_t` (seconds and 2^-32 fractions since the Unix epoch) in nanoseconds, as Fast
/// DDS `Time_t::to_ns` reads it; `None` for the reserved ZERO, INVALID and INFINITE values.
fn timestamp_ns(t: rustdds::Timestamp) -> Option<i64> {
    if t == rustdds::Timestamp::ZERO
        || t == rustdds::Timestamp::INVALID
        || t == rustdds::Timestamp::INFINITE
    {
        return None;
    }
    let ticks = t.to_ticks();
    let seconds = i64::try_from(ticks >> 32).ok()?;
    let nanos = i64::try_from(((ticks & 0xffff_ffff) * 1_000_000_000) >> 32).ok()?;
    Some(seconds * 1_000_000_000 + nanos)
}
