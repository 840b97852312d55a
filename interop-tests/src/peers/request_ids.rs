//! What a Jazzy server's introspection events (`{"event": …}` lines of `jazzy_node.py`, rcl's
//! `ServiceEventInfo`) say of the requests of one of our clients: the request id its RMW took
//! each one with.
//!
//! - rmw_fastrtps (`__rmw_take_request`): the writer GUID is the reader named in the request's
//!   `related_sample_identity` (our client's reply reader), the sequence number the request
//!   sample's own (1, 2, … at a fresh request writer).
//! - rmw_cyclonedds (`rmw_take_response_request`): the first 8 bytes of the writer GUID are the
//!   client id of the request header (ours: `horus_ros_rmw::service::client_id` of the request
//!   writer), the last 8 the `publication_handle` of the sample, an instance handle local to
//!   the server's process; the sequence number is the header's (a process-wide count at the
//!   client, as rmw_cyclonedds' `next_request_id`).
//! - rmw_zenoh (rmw_zenoh_cpp 0.2.10 `rmw_service_data.cpp`, `ServiceData::take_request`): both
//!   from the query's attachment: the writer GUID is the client's GID (ours: the GID of our
//!   client's `SC` token, its request writer's), the sequence number the client's own (1, 2, …
//!   per client, as rmw_zenoh's `ClientData` numbers its requests).

use horus_ros_rmw::service::client_id;
use horus_ros_rmw::Gid;
use horus_ros_test_support::jazzy::Rmw;

/// A GID's bytes as `jazzy_node.py` prints a `client_gid` (dotted lowercase hex).
fn dotted(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(".")
}

/// Whether `client_gid`, as `jazzy_node.py` prints it, is the request id writer GUID under which
/// a server on `rmw` takes the requests of our client whose request writer and reply reader are
/// `gids` (`ServiceClient::gids`).
pub fn names_our_client(rmw: Rmw, gids: (Gid, Gid), client_gid: &str) -> bool {
    let (request_writer, reply_reader) = gids;
    match rmw {
        Rmw::FastRtps => client_gid == reply_reader.to_string(),
        Rmw::CycloneDds => {
            let header = dotted(&client_id(request_writer).to_le_bytes());
            // Then a '.' and the 8 bytes of the server's local instance handle.
            client_gid.len() == dotted(&[0; 16]).len()
                && client_gid.starts_with(&format!("{header}."))
        }
        Rmw::Zenoh => client_gid == request_writer.to_string(),
    }
}

/// Whether `numbers`, the request ids' sequence numbers of `calls` requests of one client in the
/// order it sent them, are what a server on `rmw` takes them with: 1, 2, … on rmw_fastrtps and
/// rmw_zenoh; consecutive on rmw_cyclonedds, where our clients number the requests of the whole
/// process (`consecutive`: no other client of the process sent a request in between; else only
/// distinct and increasing).
pub fn sequence_numbers_are_ours(rmw: Rmw, numbers: &[i64], consecutive: bool) -> bool {
    match rmw {
        Rmw::FastRtps | Rmw::Zenoh => numbers.iter().copied().eq(1..=numbers.len() as i64),
        Rmw::CycloneDds => {
            numbers.first().is_some_and(|first| *first >= 1)
                && numbers.windows(2).all(|w| {
                    if consecutive {
                        w[1] == w[0] + 1
                    } else {
                        w[1] > w[0]
                    }
                })
        }
    }
}
