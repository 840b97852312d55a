//! The two DDS wire conventions for request/reply, and CDR helpers.
//!
//! - rmw_fastrtps_cpp (Jazzy's default RMW): plain CDR bodies; a request carries the inline QoS
//!   `related_sample_identity` = {client's reply reader GUID, SN unknown}; the server's request id
//!   is the request's own sample identity with the writer GUID replaced by that reader GUID; the
//!   reply carries `related_sample_identity` = {that GUID, request SN}. (rmw_fastrtps_shared_cpp
//!   jazzy `rmw_request.cpp` `__rmw_send_request` / `rmw_response.cpp` `__rmw_take_response`,
//!   `rmw_service.cpp` `__rmw_take_request`.)
//! - rmw_cyclonedds_cpp: every request and reply body begins with
//!   `cdds_request_header_t { uint64_t guid; int64_t seq; }` inside the CDR stream, before the
//!   message fields; the server echoes it (rmw_cyclonedds_cpp jazzy `serdata.hpp`, `serdata.cpp`,
//!   `rmw_node.cpp` `rmw_send_request` / `rmw_take_request` / `rmw_send_response`).
//!
//! Fast DDS and Cyclone DDS cannot call each other's services (ros2/rmw_cyclonedds#184), so the
//! convention is chosen per peer from its participant's vendor id.

use horus_ros_graph::Graph;
use horus_ros_rmw::{Backend, Gid, VendorId};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::ServiceError;

/// Which request/reply convention a peer follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WireFlavour {
    /// rmw_fastrtps_cpp: correlation through `related_sample_identity`. Also used with RustDDS
    /// peers (horus-ros, ros2-client) and unknown vendors.
    FastRtps,
    /// rmw_cyclonedds_cpp: correlation through the 16-byte in-payload request header.
    CycloneDds,
}

impl WireFlavour {
    /// The convention a participant of `vendor` follows.
    pub fn for_vendor(vendor: Option<VendorId>) -> Self {
        if vendor == Some(VendorId::CYCLONE_DDS) {
            Self::CycloneDds
        } else {
            Self::FastRtps
        }
    }

    /// The convention to use with a peer of `vendor` from a context on `backend`, given an
    /// explicit choice `forced`; `Err` (a message) when the backend cannot speak the one needed.
    ///
    /// A backend that carries `related_sample_identity` (RustDDS) follows the peer. One that
    /// does not (Cyclone DDS) speaks only rmw_cyclonedds' convention — as rmw_cyclonedds itself
    /// (ros2/rmw_cyclonedds#184) — which horus-ros peers on any backend understand; Fast DDS
    /// peers (rmw_fastrtps) do not.
    pub fn choose(
        backend: Backend,
        vendor: Option<VendorId>,
        forced: Option<Self>,
    ) -> Result<Self, String> {
        if backend.carries_sample_identity() {
            return Ok(forced.unwrap_or_else(|| Self::for_vendor(vendor)));
        }
        match forced {
            Some(Self::FastRtps) => Err(format!(
                "the rmw_fastrtps service convention needs related_sample_identity, which the \
                 {backend} backend cannot carry; use the rustdds backend (HORUS_ROS_BACKEND=rustdds)"
            )),
            Some(Self::CycloneDds) => Ok(Self::CycloneDds),
            None if vendor == Some(VendorId::FAST_DDS) => Err(format!(
                "the peer runs Fast DDS (rmw_fastrtps), whose service convention needs \
                 related_sample_identity, which the {backend} backend cannot carry (neither can \
                 rmw_cyclonedds: ros2/rmw_cyclonedds#184); use the rustdds backend \
                 (HORUS_ROS_BACKEND=rustdds)"
            )),
            None => Ok(Self::CycloneDds),
        }
    }
}

/// The DDS vendor of the participant `peer` belongs to: as SPDP told the graph, or until then the
/// vendor id that Fast DDS, Cyclone DDS and RustDDS put in the first two bytes of their GUID
/// prefixes (other values are not trusted: not every vendor does this).
pub(crate) fn peer_vendor(graph: &Graph, peer: Gid) -> Option<VendorId> {
    graph.participant_vendor(peer).or_else(|| {
        let bytes = peer.as_bytes();
        let hint = VendorId([bytes[0], bytes[1]]);
        [VendorId::FAST_DDS, VendorId::CYCLONE_DDS, VendorId::RUSTDDS]
            .contains(&hint)
            .then_some(hint)
    })
}

/// Marks a request as coming from a horus-ros client, in the otherwise unused sequence number of
/// its `related_sample_identity` (rmw_fastrtps sends SEQUENCENUMBER_UNKNOWN there and ignores it
/// on receipt). A horus-ros server answers such a client's failed handler with an error reply.
pub(crate) const HORUS_CLIENT_MARKER: i64 = 0x484f_5255_0000_0001;

/// Length of rmw_cyclonedds' request header.
pub(crate) const CYCLONE_HEADER_LEN: usize = 16;

/// rmw_cyclonedds `cdds_request_header_t`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct CycloneHeader {
    /// The client's id (rmw_cyclonedds: its request writer's instance handle).
    pub(crate) guid: u64,
    /// The request's sequence number at that client.
    pub(crate) seq: i64,
}

impl CycloneHeader {
    /// `header` followed by `body` (both little-endian CDR).
    pub(crate) fn prepend(self, body: &[u8]) -> Vec<u8> {
        let mut out = Vec::with_capacity(CYCLONE_HEADER_LEN + body.len());
        out.extend_from_slice(&self.guid.to_le_bytes());
        out.extend_from_slice(&self.seq.to_le_bytes());
        out.extend_from_slice(body);
        out
    }

    /// Splits a body into header and message, in the stream's byte order.
    pub(crate) fn split(body: &[u8], big_endian: bool) -> Option<(Self, &[u8])> {
        let (guid, rest) = body.split_first_chunk::<8>()?;
        let (seq, rest) = rest.split_first_chunk::<8>()?;
        let (guid, seq) = if big_endian {
            (u64::from_be_bytes(*guid), i64::from_be_bytes(*seq))
        } else {
            (u64::from_le_bytes(*guid), i64::from_le_bytes(*seq))
        };
        Some((Self { guid, seq }, rest))
    }
}

/// The top 16 bits of a horus-ros client's id in rmw_cyclonedds' header ("HO"): a horus-ros
/// server answers such a client's failed handler with an error reply (negated sequence number,
/// the message as a CDR string), as it does through [`HORUS_CLIENT_MARKER`] in the other
/// convention. rmw_cyclonedds ids are writer instance handles, pseudo-random 64-bit values: one
/// in 65,536 carries the mark by chance, and would then receive (and drop, as a reply to no
/// request) such an error reply instead of none.
pub(crate) const HORUS_CLIENT_ID_MARK: u64 = 0x484f;

/// A 64-bit client id for the Cyclone header: [`HORUS_CLIENT_ID_MARK`] in the top 16 bits, the
/// low 48 bits of an FNV-1a hash of the request writer's GID below (so clients of one server do
/// not collide).
pub(crate) fn client_id(writer: Gid) -> u64 {
    let hash = writer
        .as_bytes()
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
        });
    (HORUS_CLIENT_ID_MARK << 48) | (hash & 0xffff_ffff_ffff)
}

/// Whether a Cyclone header's client id is a horus-ros client's.
pub(crate) fn is_horus_client_id(id: u64) -> bool {
    id >> 48 == HORUS_CLIENT_ID_MARK
}

/// Whether a GID names a data reader (entity kinds 0x04/0x07, user or built-in).
pub(crate) fn is_reader(gid: Gid) -> bool {
    matches!(gid.as_bytes()[15] & 0x0f, 0x04 | 0x07)
}

/// Encodes a message as a CDR_LE body.
pub(crate) fn encode<T: Serialize>(value: &T) -> Result<Vec<u8>, ServiceError> {
    horus_ros_msgs::cdr::to_cdr_body(value)
        .map_err(|e| ServiceError::Transport(format!("encoding failed: {e}")))
}

/// Decodes a CDR body in the given byte order.
pub(crate) fn decode<T: DeserializeOwned>(
    body: &[u8],
    big_endian: bool,
) -> Result<T, ServiceError> {
    let result = if big_endian {
        horus_ros_msgs::cdr::from_cdr_body::<T, byteorder::BigEndian>(body)
    } else {
        horus_ros_msgs::cdr::from_cdr_body::<T, byteorder::LittleEndian>(body)
    };
    result.map_err(|e| ServiceError::Transport(format!("malformed payload: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cyclone_header_round_trips_in_both_byte_orders() {
        let h = CycloneHeader {
            guid: 0x0102_0304_0506_0708,
            seq: 42,
        };
        let body = h.prepend(&[9, 9]);
        assert_eq!(&body[..8], &[8, 7, 6, 5, 4, 3, 2, 1]);
        assert_eq!(&body[8..16], &[42, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(CycloneHeader::split(&body, false), Some((h, &[9u8, 9][..])));
        let mut be = Vec::new();
        be.extend_from_slice(&h.guid.to_be_bytes());
        be.extend_from_slice(&h.seq.to_be_bytes());
        assert_eq!(CycloneHeader::split(&be, true), Some((h, &[][..])));
        assert_eq!(CycloneHeader::split(&[1, 2, 3], false), None);
    }

    #[test]
    fn flavour_follows_the_vendor() {
        assert_eq!(
            WireFlavour::for_vendor(Some(VendorId::CYCLONE_DDS)),
            WireFlavour::CycloneDds
        );
        assert_eq!(
            WireFlavour::for_vendor(Some(VendorId::FAST_DDS)),
            WireFlavour::FastRtps
        );
        assert_eq!(
            WireFlavour::for_vendor(Some(VendorId::RUSTDDS)),
            WireFlavour::FastRtps
        );
        assert_eq!(WireFlavour::for_vendor(None), WireFlavour::FastRtps);
    }

    #[test]
    fn a_backend_without_sample_identity_speaks_only_the_cyclone_convention() {
        let fast = Some(VendorId::FAST_DDS);
        assert_eq!(
            WireFlavour::choose(Backend::RustDds, fast, None),
            Ok(WireFlavour::FastRtps)
        );
        assert_eq!(
            WireFlavour::choose(Backend::RustDds, fast, Some(WireFlavour::CycloneDds)),
            Ok(WireFlavour::CycloneDds)
        );
        for vendor in [Some(VendorId::CYCLONE_DDS), Some(VendorId::RUSTDDS), None] {
            assert_eq!(
                WireFlavour::choose(Backend::Cyclone, vendor, None),
                Ok(WireFlavour::CycloneDds)
            );
        }
        let refused = WireFlavour::choose(Backend::Cyclone, fast, None);
        assert!(refused.is_err_and(|m| m.contains("rmw_fastrtps") && m.contains("rustdds")));
        assert!(WireFlavour::choose(Backend::Cyclone, None, Some(WireFlavour::FastRtps)).is_err());
    }

    #[test]
    fn client_ids_carry_the_horus_mark() {
        let mut a = [0u8; 16];
        a[15] = 3;
        let mut b = a;
        b[15] = 4;
        let (ia, ib) = (client_id(Gid::from_bytes(a)), client_id(Gid::from_bytes(b)));
        assert_ne!(ia, ib);
        assert!(is_horus_client_id(ia) && is_horus_client_id(ib));
        assert!(!is_horus_client_id(0x0123_4567_89ab_cdef));
    }

    #[test]
    fn readers_are_told_from_writers_by_entity_kind() {
        let mut b = [0u8; 16];
        b[15] = 0x04;
        assert!(is_reader(Gid::from_bytes(b)));
        b[15] = 0x07;
        assert!(is_reader(Gid::from_bytes(b)));
        b[15] = 0x03;
        assert!(!is_reader(Gid::from_bytes(b)));
        b[15] = 0xc1;
        assert!(!is_reader(Gid::from_bytes(b)));
    }
}
