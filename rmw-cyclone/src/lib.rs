//! horus-ros' Cyclone DDS backend ([`Cyclone`], in [`backend`]: `horus-ros-rmw`'s cargo feature
//! `cyclone`, chosen per context with `ContextBuilder::backend(Backend::Cyclone)` or
//! `HORUS_ROS_BACKEND=cyclone`), and under it a safe binding layer over
//! [Cyclone DDS](https://cyclonedds.io) 11 (through the `cyclors` crate, which builds Cyclone
//! from source). The backend depends only on the backend contract and the shared DDS layer.
//!
//! What the binding offers, all with owned Rust values and RAII:
//! - [`config`]: the domain XML rmw_cyclonedds_cpp (Jazzy) builds from
//!   `ROS_AUTOMATIC_DISCOVERY_RANGE` / `ROS_STATIC_PEERS`, followed by `CYCLONEDDS_URI`, and
//!   [`Domain`], a per-process, per-domain-id shared configured domain (like rmw_cyclonedds'
//!   `CddsDomain`).
//! - [`Participant`] with USER_DATA; keyless "blob" [`Topic`]s of any topic/type name whose
//!   samples are raw CDR; [`Writer`] / [`Reader`] with [`EndpointQos`] and USER_DATA; raw
//!   [`Writer::write`] / [`Reader::take`] (with the writer's GUID); GUIDs and instance handles
//!   ([`Entity`]); matched endpoints.
//! - [`BuiltinReader`]: DCPSParticipant / DCPSPublication / DCPSSubscription as owned
//!   [`BuiltinSample`]s, including remote USER_DATA and liveness.
//! - [`Signal`]: what the backend waits on for readers' data: [`Reader::notify`] raises it
//!   from the reader's DATA_AVAILABLE listener (after Cyclone released the reader's history
//!   cache), and it wakes one waiting thread with a condition variable notified outside its
//!   lock. That listener is the only one installed; it runs no user code.
//! - [`Waiter`]: a waitset blocking in the caller's thread on reader data, entity statuses and
//!   [`GuardCondition`]s (the discovery feed's).
//!
//! **All `unsafe` code of the Cyclone backend is in this crate, in one private module
//! (`sys`)**, with a `SAFETY:` comment per block; the crate denies `unsafe_code` everywhere else
//! (the workspace forbids it outright; `forbid` could not be relaxed for one module, hence this
//! crate's own `[lints]` table), and `horus-ros-rmw` keeps `unsafe_code = "forbid"`. Leaks are
//! checked under valgrind by two tests: this crate's `tests/leakcheck.rs` (running
//! `examples/leakcheck.rs`, every resource path of the binding) and `horus-ros-rmw`'s
//! `tests/cyclone_leakcheck.rs` (running `examples/cyclone_leakcheck.rs`, the backend end to
//! end: context, node, typed and raw endpoints, discovery feed).
//!
//! What Cyclone DDS's C API cannot do, and so this layer cannot offer: `related_sample_identity`
//! on written or received samples, sequence numbers of received samples, and writes directed at
//! one reader. The backend therefore speaks only the rmw_cyclonedds service convention.
//!
//! ```no_run
//! use horus_ros_rmw_cyclone::{config, Domain, EndpointQos, Participant};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let xml = config::domain_config_from_env(config::DiscoveryRange::Localhost, &[]);
//! let p = Participant::new(Domain::acquire(0, &xml)?, b"enclave=/;")?;
//! let topic = p.blob_topic("rt/chatter", "std_msgs::msg::dds_::String_")?;
//! let w = p.writer(&topic, &EndpointQos::default(), b"typehash=RIHS01_...;")?;
//! w.write(&[0, 1, 0, 0, 3, 0, 0, 0, b'h', b'i', 0, 0])?;
//! # Ok(()) }
//! ```
#![deny(unsafe_code)]

pub mod backend;
pub mod config;
pub mod qos;
mod signal;
mod sys;

pub use backend::{Cyclone, CAPABILITIES, CONFIGURATION_ENV, NAME, RMW_IMPLEMENTATION, VENDOR_ID};
pub use qos::{Durability, EndpointQos, History, Liveliness, Reliability};
pub use signal::Signal;
pub use sys::{
    BuiltinReader, BuiltinSample, BuiltinTopic, DataNotice, Domain, EndpointInfo, Entity, Error,
    GuardCondition, MatchedEndpoint, Participant, ParticipantInfo, Reader, Result, Sample,
    StatusMask, Topic, Waiter, WeakEntity, Writer, HEAD_LEN,
};

/// A DDS GUID: 12-byte GUID prefix (shared by a participant and its endpoints) + 4-byte
/// entity id. ROS 2 GIDs on Jazzy are these 16 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Guid(pub [u8; 16]);

impl Guid {
    /// The 12-byte GUID prefix.
    pub fn prefix(&self) -> [u8; 12] {
        let mut p = [0; 12];
        p.copy_from_slice(&self.0[..12]);
        p
    }

    /// The GUID of the participant this entity belongs to (same prefix, entity id 0x000001c1).
    pub fn participant(&self) -> Guid {
        let mut g = self.0;
        g[12..].copy_from_slice(&[0, 0, 1, 0xc1]);
        Guid(g)
    }

    /// Best guess at the DDS vendor that created this GUID.
    ///
    /// Cyclone's API does not expose a remote participant's vendor id (it is in the SPDP
    /// message, not in the built-in topic samples). But the RTPS specification recommends,
    /// and Cyclone DDS (`ddsi_init.c`: prefix bytes 0..1 = `DDSI_VENDORID_ECLIPSE`), Fast DDS
    /// and OpenDDS do, putting the vendor id in the first two bytes of the GUID prefix. So
    /// those two bytes are returned as a *hint*: implementations that ignore the
    /// recommendation (e.g. RTI Connext, which starts with a host id) yield arbitrary values;
    /// match the result against [`vendor::name`] and treat unknown values as unknown.
    pub fn vendor_hint(&self) -> [u8; 2] {
        [self.0[0], self.0[1]]
    }
}

impl std::fmt::Display for Guid {
    /// Dotted hex bytes, as `ros2` prints GIDs (`01.10.ab.…`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, b) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(".")?;
            }
            write!(f, "{b:02x}")?;
        }
        Ok(())
    }
}

/// DDS vendor ids (OMG's assigned list) for [`Guid::vendor_hint`].
pub mod vendor {
    /// Eclipse Cyclone DDS.
    pub const CYCLONE: [u8; 2] = [0x01, 0x10];
    /// eProsima Fast DDS.
    pub const FAST_DDS: [u8; 2] = [0x01, 0x0f];
    /// RTI Connext DDS.
    pub const CONNEXT: [u8; 2] = [0x01, 0x01];
    /// OCI OpenDDS.
    pub const OPENDDS: [u8; 2] = [0x01, 0x03];

    /// The vendor's name for a known vendor id.
    pub fn name(id: [u8; 2]) -> Option<&'static str> {
        match id {
            CYCLONE => Some("Eclipse Cyclone DDS"),
            FAST_DDS => Some("eProsima Fast DDS"),
            CONNEXT => Some("RTI Connext DDS"),
            OPENDDS => Some("OpenDDS"),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guid_display_and_parts() {
        let mut b = [0u8; 16];
        b[0] = 0x01;
        b[1] = 0x10;
        b[15] = 0x03;
        let g = Guid(b);
        assert_eq!(
            g.to_string(),
            "01.10.00.00.00.00.00.00.00.00.00.00.00.00.00.03"
        );
        assert_eq!(g.participant().0[12..], [0, 0, 1, 0xc1]);
        assert_eq!(g.prefix(), g.participant().prefix());
        assert_eq!(vendor::name(g.vendor_hint()), Some("Eclipse Cyclone DDS"));
        assert_eq!(vendor::name([0xaa, 0xbb]), None);
    }
}
