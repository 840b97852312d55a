//! [`WireFlavour`]: which of the two DDS request/reply conventions a peer follows.
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

use crate::{Capabilities, Gid, VendorId};

/// Which request/reply convention a peer follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WireFlavour {
    /// rmw_fastrtps_cpp: correlation through `related_sample_identity`. Also used with RustDDS
    /// peers (horus-ros, ros2-client) and unknown vendors.
    FastRtps,
    /// rmw_cyclonedds_cpp: correlation through the 16-byte in-payload request header.
    CycloneDds,
}

/// Why a context cannot speak the convention a peer needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ConventionError {
    /// The rmw_fastrtps convention was asked for on a backend that cannot carry it.
    #[error(
        "the rmw_fastrtps service convention needs related_sample_identity, which this \
         backend cannot carry; use the rustdds backend (HORUS_ROS_BACKEND=rustdds)"
    )]
    FastRtpsUnsupported,
    /// The peer runs Fast DDS, whose convention this backend cannot carry.
    #[error(
        "the peer runs Fast DDS (rmw_fastrtps), whose service convention needs \
         related_sample_identity, which this backend cannot carry (neither can \
         rmw_cyclonedds: ros2/rmw_cyclonedds#184); use the rustdds backend \
         (HORUS_ROS_BACKEND=rustdds)"
    )]
    FastDdsPeer,
}

/// How long a client's reply reader must have been matched with an rmw_cyclonedds server's
/// reply writer before its first request, when the client cannot announce `clientid=`: such a
/// server then cannot tell whether its writer reached our reader (rmw_cyclonedds
/// `check_for_response_reader` looks for the client id), and learns of our reader about when we
/// learn of its writer. No event tells when it has.
const CYCLONE_MATCH_SETTLE: std::time::Duration = std::time::Duration::from_millis(100);

impl WireFlavour {
    /// How long a client of this convention, on a backend that can do `capabilities`, lets a
    /// server's reply writer match its reply reader before its first request
    /// (100 ms for the rmw_cyclonedds convention without USER_DATA); `None`:
    /// no wait, the matches tell.
    pub fn reply_match_settle(self, capabilities: Capabilities) -> Option<std::time::Duration> {
        (self == Self::CycloneDds && !capabilities.announces_user_data)
            .then_some(CYCLONE_MATCH_SETTLE)
    }

    /// The convention a participant of `vendor` follows.
    pub fn for_vendor(vendor: Option<VendorId>) -> Self {
        if vendor == Some(VendorId::CYCLONE_DDS) {
            Self::CycloneDds
        } else {
            Self::FastRtps
        }
    }

    /// The convention to use with a peer of `vendor` from a context whose backend can do
    /// `capabilities`, given an explicit choice `forced`.
    ///
    /// A backend that carries `related_sample_identity` (RustDDS) follows the peer. One that
    /// does not (Cyclone DDS) speaks only rmw_cyclonedds' convention — as rmw_cyclonedds itself
    /// (ros2/rmw_cyclonedds#184) — which horus-ros peers on any backend understand; Fast DDS
    /// peers (rmw_fastrtps) do not.
    pub fn choose(
        capabilities: Capabilities,
        vendor: Option<VendorId>,
        forced: Option<Self>,
    ) -> Result<Self, ConventionError> {
        // A backend whose services are its own request/reply (Zenoh) carries the identities
        // both ways, whoever the peer: its endpoints speak the rmw_fastrtps shape of them.
        if capabilities.service_queries {
            return Ok(Self::FastRtps);
        }
        if capabilities.carries_sample_identity {
            return Ok(forced.unwrap_or_else(|| Self::for_vendor(vendor)));
        }
        match forced {
            Some(Self::FastRtps) => Err(ConventionError::FastRtpsUnsupported),
            Some(Self::CycloneDds) => Ok(Self::CycloneDds),
            None if vendor == Some(VendorId::FAST_DDS) => Err(ConventionError::FastDdsPeer),
            None => Ok(Self::CycloneDds),
        }
    }
}

/// The vendor that Fast DDS, Cyclone DDS and RustDDS put in the first two bytes of their GUID
/// prefixes, read from `gid` (other values are not trusted: not every vendor does this). What
/// to go by until SPDP has told the participant's vendor.
pub fn vendor_hint(gid: Gid) -> Option<VendorId> {
    let bytes = gid.as_bytes();
    let hint = VendorId([bytes[0], bytes[1]]);
    [VendorId::FAST_DDS, VendorId::CYCLONE_DDS, VendorId::RUSTDDS]
        .contains(&hint)
        .then_some(hint)
}

/// Whether a GID names a data reader (entity kinds 0x04/0x07, user or built-in).
pub fn is_reader(gid: Gid) -> bool {
    matches!(gid.as_bytes()[15] & 0x0f, 0x04 | 0x07)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::service::shapes;
    use crate::Backend;

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
            WireFlavour::choose(shapes::capabilities(Backend::RustDds), fast, None),
            Ok(WireFlavour::FastRtps)
        );
        assert_eq!(
            WireFlavour::choose(
                shapes::capabilities(Backend::RustDds),
                fast,
                Some(WireFlavour::CycloneDds)
            ),
            Ok(WireFlavour::CycloneDds)
        );
        for vendor in [Some(VendorId::CYCLONE_DDS), Some(VendorId::RUSTDDS), None] {
            assert_eq!(
                WireFlavour::choose(shapes::capabilities(Backend::Cyclone), vendor, None),
                Ok(WireFlavour::CycloneDds)
            );
        }
        let refused = WireFlavour::choose(shapes::capabilities(Backend::Cyclone), fast, None);
        assert!(refused.is_err_and(|e| {
            let m = e.to_string();
            m.contains("rmw_fastrtps") && m.contains("rustdds")
        }));
        assert!(WireFlavour::choose(
            shapes::capabilities(Backend::Cyclone),
            None,
            Some(WireFlavour::FastRtps)
        )
        .is_err());
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

    #[test]
    fn vendors_are_read_from_known_guid_prefixes_only() {
        let mut b = [0u8; 16];
        b[..2].copy_from_slice(&VendorId::CYCLONE_DDS.0);
        assert_eq!(vendor_hint(Gid::from_bytes(b)), Some(VendorId::CYCLONE_DDS));
        b[..2].copy_from_slice(&[0x01, 0x03]);
        assert_eq!(vendor_hint(Gid::from_bytes(b)), None);
    }
}
