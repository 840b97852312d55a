//! Request/reply in rmw's words: [`Client`] (`rmw_send_request`, `rmw_take_response`) and
//! [`Server`] (`rmw_take_request`, `rmw_send_response`) over raw DDS endpoints, in each peer's
//! wire convention ([`WireFlavour`]) with rmw's request ids ([`RequestId`]).
//!
//! What a server needs to know of its peers (their vendors, and whether a client's response
//! reader is matched yet) comes from the graph above this layer, through [`Peers`].

mod client;
mod convention;
mod reply_park;
mod request_header;
mod server;
#[cfg(test)]
mod shapes;

pub use client::{Client, TakenResponse};
pub use convention::{is_reader, vendor_hint, ConventionError, WireFlavour};
pub use request_header::{
    client_id, is_horus_client_id, CycloneHeader, RequestId, CYCLONE_HEADER_LEN,
    HORUS_CLIENT_ID_MARK, HORUS_CLIENT_MARKER,
};
pub use server::{OnSent, ReplyRoute, Request, Response, Server, TakenRequest};

use std::sync::Arc;
use std::time::Instant;

use crate::{Gid, VendorId};

/// What discovery announced of an endpoint's rmw_cyclonedds client id (USER_DATA `clientid=`,
/// the same on a client's request writer and reply reader: rmw_cyclonedds jazzy `rmw_node.cpp`
/// `rmw_init_cs`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ClientIdLookup {
    /// The endpoint has not been discovered (yet).
    Undiscovered,
    /// The endpoint announces no client id (not an rmw_cyclonedds client, or an old one).
    Absent,
    /// The client id, as announced (rmw_cyclonedds `csid_to_string`).
    Id(Arc<str>),
}

/// What request/reply needs to know of the peers on the graph (implemented by the graph cache
/// above rmw, which learns it from discovery).
pub trait Peers: Send + Sync {
    /// The DDS vendor of the participant `gid` belongs to, as SPDP told it.
    fn participant_vendor(&self, gid: Gid) -> Option<VendorId>;

    /// Whether our endpoint `local` is matched with the remote endpoint `remote`.
    fn is_matched(&self, local: Gid, remote: Gid) -> bool;

    /// Since when our endpoint `local` has been matched with an endpoint in the participant of
    /// `remote`: the earliest of those matches that still hold; `None` if there is none.
    fn participant_matched_since(&self, local: Gid, remote: Gid) -> Option<Instant>;

    /// The rmw_cyclonedds client id that endpoint `gid` announced.
    fn client_id(&self, gid: Gid) -> ClientIdLookup;

    /// Whether our endpoint `local` is matched with an endpoint in the participant of `remote`
    /// that announced the client id `id`.
    fn matched_with_client_id(&self, local: Gid, remote: Gid, id: &str) -> bool;

    /// The vendor of `gid`'s participant: as SPDP told it, or until then as its GUID prefix
    /// hints ([`vendor_hint`]).
    fn vendor_of(&self, gid: Gid) -> Option<VendorId> {
        self.participant_vendor(gid).or_else(|| vendor_hint(gid))
    }
}
