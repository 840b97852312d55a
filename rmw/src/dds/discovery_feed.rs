//! Turns rustdds discovery status events and our `ros_discovery_info` reader into
//! [`DiscoveryEvent`]s.

use std::collections::VecDeque;

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use horus_ros_msgs::user_data::parse_type_hash_from_user_data;
use horus_ros_msgs::TypeHash;
use rustdds::{
    no_key, CDRDeserializerAdapter, DomainParticipantStatusEvent, DomainParticipantStatusListener,
    EndpointDescription, StatusEvented,
};

use super::gid_from_guid;
use crate::discovery::{DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId};
use crate::qos::{EndpointKind, Qos};
use crate::Gid;

/// Most samples drained from the `ros_discovery_info` reader per call, so one call stays short.
const MAX_SAMPLES_PER_POLL: usize = 64;

/// The rustdds side of a discovery feed.
pub(crate) struct DdsDiscoveryFeed {
    pub(crate) listener: DomainParticipantStatusListener,
    pub(crate) reader: no_key::DataReader<
        ParticipantEntitiesInfo,
        CDRDeserializerAdapter<ParticipantEntitiesInfo>,
    >,
    pub(crate) own_gid: Gid,
    pub(crate) pending: VecDeque<DiscoveryEvent>,
}

impl DdsDiscoveryFeed {
    /// The next event, if any (non-blocking).
    pub(crate) fn try_next(&mut self) -> Option<DiscoveryEvent> {
        if self.pending.is_empty() {
            self.poll();
        }
        self.pending.pop_front()
    }

    fn poll(&mut self) {
        while let Some(status) = self.listener.try_recv_status() {
            if let Some(event) = self.convert(status) {
                self.pending.push_back(event);
            }
        }
        for _ in 0..MAX_SAMPLES_PER_POLL {
            match self.reader.take_next_sample() {
                Ok(Some(sample)) => {
                    let info = sample.into_value();
                    // As rmw_dds_common's reader (ignore_local_publications): skip our own.
                    if info.gid != self.own_gid {
                        self.pending
                            .push_back(DiscoveryEvent::ParticipantEntities(info));
                    }
                }
                Ok(None) => break,
                // Malformed CDR from the wire: that sample is dropped, the feed goes on.
                Err(e) => tracing::warn!("dropped a malformed ros_discovery_info sample: {e}"),
            }
        }
    }

    fn convert(&self, status: DomainParticipantStatusEvent) -> Option<DiscoveryEvent> {
        match status {
            DomainParticipantStatusEvent::ParticipantDiscovered { dpd } => Some(
                DiscoveryEvent::ParticipantDiscovered(DiscoveredParticipant {
                    gid: gid_from_guid(dpd.guid),
                    vendor_id: VendorId(dpd.vendor_id.vendor_id),
                }),
            ),
            DomainParticipantStatusEvent::ParticipantLost { id, .. } => {
                Some(DiscoveryEvent::ParticipantLost {
                    gid: participant_gid(id.as_ref()),
                })
            }
            DomainParticipantStatusEvent::ReaderDetected { reader } => Some(
                DiscoveryEvent::EndpointDiscovered(endpoint(reader, EndpointKind::Reader)),
            ),
            DomainParticipantStatusEvent::WriterDetected { writer } => Some(
                DiscoveryEvent::EndpointDiscovered(endpoint(writer, EndpointKind::Writer)),
            ),
            DomainParticipantStatusEvent::ReaderLost { guid, .. } => {
                Some(DiscoveryEvent::EndpointLost {
                    gid: gid_from_guid(guid),
                    kind: EndpointKind::Reader,
                })
            }
            DomainParticipantStatusEvent::WriterLost { guid, .. } => {
                Some(DiscoveryEvent::EndpointLost {
                    gid: gid_from_guid(guid),
                    kind: EndpointKind::Writer,
                })
            }
            _ => None,
        }
    }
}

/// The participant GID for a GUID prefix: the prefix + `ENTITYID_PARTICIPANT` (`00 00 01 c1`).
fn participant_gid(prefix: &[u8]) -> Gid {
    let mut bytes = [0u8; 16];
    for (b, p) in bytes[..12].iter_mut().zip(prefix) {
        *b = *p;
    }
    bytes[12..].copy_from_slice(&[0x00, 0x00, 0x01, 0xc1]);
    Gid::from_bytes(bytes)
}

/// The octets of a USER_DATA policy as rustdds 0.15 reports it for remote endpoints.
///
/// rustdds hands over the raw PID_USER_DATA parameter value: the CDR `sequence<octet>` length
/// (4 bytes, little-endian in every RTPS stack seen here) followed by the octets and up to 3 bytes
/// of padding. When the bytes have that shape, the octets are returned; anything else is taken as
/// already bare octets.
pub(crate) fn user_data_octets(raw: &[u8]) -> &[u8] {
    if let Some((len, rest)) = raw.split_first_chunk::<4>() {
        let n = u32::from_le_bytes(*len) as usize;
        if n <= rest.len() && rest.len() - n < 4 {
            return &rest[..n];
        }
    }
    raw
}

fn endpoint(d: EndpointDescription, kind: EndpointKind) -> DiscoveredEndpoint {
    let user_data = user_data_octets(&d.user_data).to_vec();
    let type_hash = parse_type_hash_from_user_data(&user_data).unwrap_or_else(|e| {
        tracing::debug!(topic = %d.topic_name, "unusable type hash in USER_DATA: {e}");
        TypeHash::ZERO
    });
    DiscoveredEndpoint {
        gid: gid_from_guid(d.guid),
        participant_gid: participant_gid(d.guid.prefix.as_ref()),
        kind,
        dds_topic_name: d.topic_name,
        dds_type_name: d.type_name,
        qos: Qos::from_dds(&d.qos, kind),
        type_hash,
        user_data,
    }
}

#[cfg(test)]
mod tests {
    use super::user_data_octets;

    #[test]
    fn user_data_length_prefix_and_padding_are_removed() {
        let mut raw = vec![5, 0, 0, 0];
        raw.extend_from_slice(b"abcde\0\0\0");
        assert_eq!(user_data_octets(&raw), b"abcde");
        assert_eq!(user_data_octets(&[0, 0, 0, 0]), b"");
        assert_eq!(
            user_data_octets(b"typehash=x;"),
            b"typehash=x;",
            "bare octets stay as they are"
        );
        assert_eq!(user_data_octets(&[]), b"");
        assert_eq!(
            user_data_octets(&[200, 0, 0, 0, 1]),
            &[200, 0, 0, 0, 1],
            "length past the end"
        );
    }
}
