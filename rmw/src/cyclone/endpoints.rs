//! Raw CDR writers and readers on blob topics: the Cyclone side of `RawWriter`/`RawReader` and of
//! the typed publishers and subscriptions.

use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use horus_ros_msgs::cdr::{CDR_BE_ID, CDR_LE_HEADER, CDR_LE_ID};
use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_rmw_cyclone as cyc;

use super::{gid, qos, CycloneParticipant, LocalEndpoints};
use crate::dds_error::DdsError;
use crate::qos::{DdsQos, EndpointKind};

/// The blob topic `topic_name` of type `type_name` (each endpoint gets its own topic entity;
/// Cyclone shares what lies behind same-named ones).
fn topic(
    p: &CycloneParticipant,
    topic_name: &str,
    type_name: &str,
) -> Result<cyc::Topic, DdsError> {
    p.participant
        .blob_topic(topic_name, type_name)
        .map_err(DdsError::Cyclone)
}

/// The GID of a new endpoint of ours, listed with the context's live endpoints.
fn register(
    p: &CycloneParticipant,
    entity: &cyc::Entity,
    kind: EndpointKind,
) -> Result<Gid, DdsError> {
    let gid = gid(entity.guid().map_err(DdsError::Cyclone)?);
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
    /// Creates a writer of `topic_name`/`type_name` with this QoS and USER_DATA.
    pub(crate) fn create(
        p: &CycloneParticipant,
        topic_name: &str,
        type_name: &str,
        policies: &DdsQos,
        user_data: &[u8],
    ) -> Result<(Self, Gid), DdsError> {
        let fail = DdsError::Cyclone;
        let writer = p
            .participant
            .writer(
                &topic(p, topic_name, type_name)?,
                &qos::endpoint_qos(policies),
                user_data,
            )
            .map_err(fail)?;
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

    /// Writes a CDR_LE body; returns the sample's sequence number (counted here, as RTPS does:
    /// one per write, from 1).
    pub(crate) fn write(&self, body: &[u8]) -> Result<i64, DdsError> {
        let mut cdr = Vec::with_capacity(4 + body.len());
        cdr.extend_from_slice(&CDR_LE_HEADER);
        cdr.extend_from_slice(body);
        self.writer.write(&cdr).map_err(DdsError::Cyclone)?;
        Ok(self.last_sequence_number.fetch_add(1, Ordering::Relaxed) + 1)
    }
}

impl Drop for RawWriter {
    fn drop(&mut self) {
        self.local_endpoints.remove(self.gid);
    }
}

/// Signal token of a reader's own data.
const DATA: usize = 0;

/// A sample taken from a [`RawReader`].
pub(crate) struct Sample {
    /// The CDR body (after the encapsulation header).
    pub(crate) body: Vec<u8>,
    /// CDR_BE rather than CDR_LE.
    pub(crate) big_endian: bool,
    /// The writer's GID (all zero if the writer was gone when the sample was taken).
    pub(crate) writer: Gid,
    /// Cyclone's local instance handle of the writer (`dds_sample_info_t::publication_handle`).
    pub(crate) publication_handle: u64,
}

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
}

impl RawReader {
    /// Creates a reader of `topic_name`/`type_name` with this QoS and USER_DATA.
    pub(crate) fn create(
        p: &CycloneParticipant,
        topic_name: &str,
        type_name: &str,
        policies: &DdsQos,
        user_data: &[u8],
        responses_of: Option<u64>,
    ) -> Result<(Self, Gid), DdsError> {
        let fail = DdsError::Cyclone;
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
            .reader(&topic, &qos::endpoint_qos(policies), user_data)
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
            },
            gid,
        ))
    }

    /// Takes the next sample, if any. A sample in an encoding other than plain CDR is consumed
    /// and reported as an error.
    pub(crate) fn take(&self) -> Result<Option<Sample>, DdsError> {
        let Some(sample) = self.reader.take().map_err(DdsError::Cyclone)? else {
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
        Ok(Some(Sample {
            body: body.to_vec(),
            big_endian,
            writer,
            publication_handle: sample.publication_handle,
        }))
    }

    /// Reports this reader's data to `signal` under `token` from now on, instead of to its own
    /// [`wait`](Self::wait) (which then returns only when woken); dropping the notice detaches
    /// it.
    pub(crate) fn attach_to(&mut self, signal: &Arc<cyc::Signal>, token: usize) -> cyc::DataNotice {
        self.own = None;
        self.reader.notify(signal, token)
    }

    /// The signal whose [`wake`](cyc::Signal::wake) ends [`wait`](Self::wait).
    pub(crate) fn signal(&self) -> Arc<cyc::Signal> {
        Arc::clone(&self.signal)
    }

    /// Waits until a sample may be there or the signal was woken, at most `timeout`; returns
    /// whether something was signalled. Edge-triggered: take until `None` after it.
    pub(crate) fn wait(&mut self, timeout: Option<Duration>) -> bool {
        self.signal.wait(timeout, &mut self.ready)
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
