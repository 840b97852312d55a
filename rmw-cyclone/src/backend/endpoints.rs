//! Raw CDR writers and readers on blob topics: the Cyclone side of `RawWriter`/`RawReader` and of
//! the typed publishers and subscriptions.

use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use crate as cyc;
use horus_ros_msgs::cdr::{CDR_BE_ID, CDR_LE_HEADER, CDR_LE_ID};
use horus_ros_msgs::rmw_dds_common::Gid;

use super::wait_set::{SignalWake, WaitSet};
use super::{cyclone_error, gid, qos, CycloneParticipant, LocalEndpoints};
use horus_ros_rmw_contract::dds_error::DdsError;
use horus_ros_rmw_contract::qos::{DdsQos, EndpointKind};
use horus_ros_rmw_contract::WaitSetError;
use horus_ros_rmw_contract::{unix_time_ns, RawEndpointSpec, RawSample, SampleId};
use horus_ros_rmw_contract::{ReaderBackend, WaitSetBackend, Wake, WriterBackend};

/// The blob topic `topic_name` of type `type_name` (each endpoint gets its own topic entity;
/// Cyclone shares what lies behind same-named ones).
fn topic(
    p: &CycloneParticipant,
    topic_name: &str,
    type_name: &str,
) -> Result<cyc::Topic, DdsError> {
    p.participant
        .blob_topic(topic_name, type_name)
        .map_err(cyclone_error)
}

/// The GID of a new endpoint of ours, listed with the context's live endpoints.
fn register(
    p: &CycloneParticipant,
    entity: &cyc::Entity,
    kind: EndpointKind,
) -> Result<Gid, DdsError> {
    let gid = gid(entity.guid().map_err(cyclone_error)?);
    p.local_endpoints.insert(gid, entity, kind);
    Ok(gid)
}

/// A raw writer, listed with the context's live endpoints while it exists.
pub(crate) struct RawWriter {
    writer: cyc::Writer,
    last_sequence_number: AtomicI64,
    local_endpoints: Arc<LocalEndpoints>,
    gid: Gid,
}

impl RawWriter {
    /// Creates a writer of the spec's topic and type with this QoS and the spec's USER_DATA.
    pub(crate) fn create(
        p: &CycloneParticipant,
        spec: &RawEndpointSpec,
        policies: &DdsQos,
    ) -> Result<(Self, Gid), DdsError> {
        let writer = p
            .participant
            .writer(
                &topic(p, &spec.dds_topic_name, &spec.dds_type_name)?,
                &qos::endpoint_qos(policies),
                spec.user_data().as_bytes(),
            )
            .map_err(cyclone_error)?;
        let gid = register(p, &writer.entity(), EndpointKind::Writer)?;
        Ok((
            Self {
                writer,
                last_sequence_number: AtomicI64::new(0),
                local_endpoints: Arc::clone(&p.local_endpoints),
                gid,
            },
            gid,
        ))
    }
}

impl WriterBackend for RawWriter {
    /// Writes a CDR_LE body to every matched reader; the sequence number is counted here, as
    /// RTPS does (one per write, from 1). `related` is refused (Cyclone DDS cannot send it) and
    /// `only_to` ignored.
    fn write(
        &self,
        body: Vec<u8>,
        related: Option<SampleId>,
        _only_to: Option<Gid>,
    ) -> Result<SampleId, DdsError> {
        if related.is_some() {
            return Err(DdsError::RelatedSampleIdentityUnsupported);
        }
        let mut cdr = Vec::with_capacity(4 + body.len());
        cdr.extend_from_slice(&CDR_LE_HEADER);
        cdr.extend_from_slice(&body);
        self.writer.write(&cdr).map_err(cyclone_error)?;
        Ok(SampleId {
            writer: self.gid,
            sequence_number: self.last_sequence_number.fetch_add(1, Ordering::Relaxed) + 1,
        })
    }

    /// At once: Cyclone DDS delivers unacknowledged samples of a deleted writer itself (its
    /// writer linger duration).
    fn wait_for_acknowledgments(&self, _timeout: Duration) -> bool {
        true
    }
}

impl Drop for RawWriter {
    fn drop(&mut self) {
        self.local_endpoints.remove(self.gid);
    }
}

/// Signal token of a reader's own data.
const DATA: usize = 0;

/// Whether a reply reader of `client` stores the sample starting with `head`: rmw_cyclonedds'
/// `rmw_take_response` keeps a response whose request header (`cdds_request_header_t`, right
/// after the encapsulation header) names the client's id, and drops the others'. What does not
/// hold a header is kept, for the reader to report.
fn keeps_response(head: &[u8], client: u64) -> bool {
    let Some((encapsulation, rest)) = head.split_first_chunk::<4>() else {
        return true;
    };
    let Some(guid) = rest.first_chunk::<8>() else {
        return true;
    };
    match [encapsulation[0], encapsulation[1]] {
        CDR_LE_ID => u64::from_le_bytes(*guid) == client,
        CDR_BE_ID => u64::from_be_bytes(*guid) == client,
        _ => true,
    }
}

/// A raw reader with its own [`cyc::Signal`] (raised on data and by its waker), listed with the
/// context's live endpoints while it exists.
pub(crate) struct RawReader {
    signal: Arc<cyc::Signal>,
    /// The reader's data raising its own signal; `None` once it is attached to a wait set.
    own: Option<cyc::DataNotice>,
    ready: Vec<usize>,
    reader: cyc::Reader,
    local_endpoints: Arc<LocalEndpoints>,
    gid: Gid,
    /// The wait sets this reader reports its data to.
    attachments: Vec<cyc::DataNotice>,
}

impl RawReader {
    /// Creates a reader of the spec's topic and type with this QoS and the spec's USER_DATA;
    /// with `responses_of`, a content filter keeps only that client's responses.
    pub(crate) fn create(
        p: &CycloneParticipant,
        spec: &RawEndpointSpec,
        policies: &DdsQos,
        responses_of: Option<u64>,
    ) -> Result<(Self, Gid), DdsError> {
        let fail = cyclone_error;
        let (topic_name, type_name) = (spec.dds_topic_name.as_str(), spec.dds_type_name.as_str());
        let topic = match responses_of {
            None => topic(p, topic_name, type_name)?,
            Some(client) => p
                .participant
                .filtered_blob_topic(topic_name, type_name, move |head| {
                    keeps_response(head, client)
                })
                .map_err(fail)?,
        };
        let reader = p
            .participant
            .reader(
                &topic,
                &qos::endpoint_qos(policies),
                spec.user_data().as_bytes(),
            )
            .map_err(fail)?;
        let signal = cyc::Signal::new();
        let own = Some(reader.notify(&signal, DATA));
        let gid = register(p, &reader.entity(), EndpointKind::Reader)?;
        Ok((
            Self {
                signal,
                own,
                ready: Vec::new(),
                reader,
                local_endpoints: Arc::clone(&p.local_endpoints),
                gid,
                attachments: Vec::new(),
            },
            gid,
        ))
    }
}

impl ReaderBackend for RawReader {
    /// Takes the next sample, if any. A sample in an encoding other than plain CDR is consumed
    /// and reported as an error. Samples carry no `related_sample_identity` and their sequence
    /// number is [`SampleId::UNKNOWN_SEQUENCE_NUMBER`] (Cyclone DDS reports neither).
    fn take(&mut self) -> Result<Option<RawSample>, DdsError> {
        let Some(sample) = self.reader.take().map_err(cyclone_error)? else {
            return Ok(None);
        };
        let writer = sample.writer_guid.map(gid).unwrap_or_default();
        let Some((header, body)) = sample.cdr.split_first_chunk::<4>() else {
            return Err(DdsError::ShortSample {
                len: sample.cdr.len(),
            });
        };
        let big_endian = match [header[0], header[1]] {
            CDR_LE_ID => false,
            CDR_BE_ID => true,
            id => return Err(DdsError::UnsupportedEncapsulation { id }),
        };
        Ok(Some(RawSample {
            body: body.to_vec(),
            big_endian,
            id: SampleId {
                writer,
                sequence_number: SampleId::UNKNOWN_SEQUENCE_NUMBER,
            },
            related: None,
            publication_handle: Some(sample.publication_handle),
            source_timestamp: Some(sample.source_timestamp_ns),
            received_timestamp: unix_time_ns(),
        }))
    }

    /// Reports this reader's data to the set's signal under `key` from now on, instead of to
    /// its own [`wait`](Self::wait) (which then returns only when woken); the notice lives as
    /// long as the reader.
    fn attach_to(&mut self, set: &dyn WaitSetBackend, key: usize) -> Result<(), WaitSetError> {
        let set = set
            .as_any()
            .downcast_ref::<WaitSet>()
            .ok_or(WaitSetError::OtherBackend)?;
        self.own = None;
        let notice = self.reader.notify(&set.signal, key);
        self.attachments.push(notice);
        Ok(())
    }

    /// Waits until a sample may be there or the signal was woken, at most `timeout`; returns
    /// whether something was signalled. Edge-triggered: take until `None` after it.
    fn wait(&mut self, timeout: Option<Duration>) -> bool {
        self.signal.wait(timeout, &mut self.ready)
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::new(SignalWake(Arc::clone(&self.signal)))
    }
}

impl Drop for RawReader {
    fn drop(&mut self) {
        self.local_endpoints.remove(self.gid);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reply_reader_keeps_its_clients_responses_and_what_it_cannot_judge() {
        let mut le = vec![0, 1, 0, 0];
        le.extend_from_slice(&7u64.to_le_bytes());
        le.extend_from_slice(&1i64.to_le_bytes());
        assert!(keeps_response(&le, 7));
        assert!(!keeps_response(&le, 8));
        let mut be = vec![0, 0, 0, 0];
        be.extend_from_slice(&7u64.to_be_bytes());
        assert!(keeps_response(&be, 7));
        assert!(!keeps_response(&be, 7u64.swap_bytes()));
        assert!(
            keeps_response(&[0, 1, 0, 0, 7], 8),
            "too short for a header"
        );
        assert!(
            keeps_response(&[0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0], 8),
            "not plain CDR"
        );
    }
}
