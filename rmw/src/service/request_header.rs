//! What a request carries to correlate its reply: rmw's request id, rmw_cyclonedds' in-payload
//! header, and the marks by which a horus-ros server knows a horus-ros client (which takes error
//! replies).

use crate::Gid;

/// rmw `rmw_request_id_t`: who sent a request, and its number there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct RequestId {
    /// The client's GUID as its RMW's convention makes it (what rcl puts in a server's
    /// introspection events as `client_gid`).
    pub writer_guid: [u8; 16],
    /// The request's sequence number at that client.
    pub sequence_number: i64,
}

pub use horus_ros_rmw_contract::HORUS_CLIENT_MARKER;

/// Length of rmw_cyclonedds' request header.
pub const CYCLONE_HEADER_LEN: usize = 16;

/// rmw_cyclonedds `cdds_request_header_t`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CycloneHeader {
    /// The client's id (rmw_cyclonedds: its request writer's instance handle).
    pub guid: u64,
    /// The request's sequence number at that client.
    pub seq: i64,
}

impl CycloneHeader {
    /// `header` followed by `body` (both little-endian CDR).
    pub fn prepend(self, body: &[u8]) -> Vec<u8> {
        let mut out = Vec::with_capacity(CYCLONE_HEADER_LEN + body.len());
        out.extend_from_slice(&self.guid.to_le_bytes());
        out.extend_from_slice(&self.seq.to_le_bytes());
        out.extend_from_slice(body);
        out
    }

    /// Splits a body into header and message, in the stream's byte order.
    pub fn split(body: &[u8], big_endian: bool) -> Option<(Self, &[u8])> {
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
pub const HORUS_CLIENT_ID_MARK: u64 = 0x484f;

/// A 64-bit client id for the Cyclone header: [`HORUS_CLIENT_ID_MARK`] in the top 16 bits, the
/// low 48 bits of an FNV-1a hash of the request writer's GID below (so clients of one server do
/// not collide).
pub fn client_id(writer: Gid) -> u64 {
    let hash = writer
        .as_bytes()
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
        });
    (HORUS_CLIENT_ID_MARK << 48) | (hash & 0xffff_ffff_ffff)
}

/// Whether a Cyclone header's client id is a horus-ros client's.
pub fn is_horus_client_id(id: u64) -> bool {
    id >> 48 == HORUS_CLIENT_ID_MARK
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
}
