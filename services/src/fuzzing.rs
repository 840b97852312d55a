//! Fuzzing entry points for the two request/reply wire conventions (see `horus_ros_rmw::service`): each takes
//! arbitrary bytes, reads them as a server reads a request and as a client reads a reply, and
//! panics only on a bug (called by the `fuzz/` targets and `tests/fuzz_wire.rs`).
//!
//! Input layouts (the selector byte picks the message type, modulo their number, from
//! [`horus_ros_msgs::fuzzing::SERVICE_PAYLOAD_TYPES`]; bit 0 of the flags byte is the sample's
//! byte order, 1 = big-endian):
//! - [`cyclone`]: `flags, selector, body` — the body starts with rmw_cyclonedds' 16-byte header.
//! - [`fastrtps`]: `flags, selector, related sequence number (8, LE), body` — the sequence
//!   number of the `related_sample_identity` rustdds reads from the sample's inline QoS.

use serde::{de::DeserializeOwned, Serialize};

use horus_ros_msgs::with_service_payload_type;

use crate::cdr::{decode, encode};
use horus_ros_rmw::service::{CycloneHeader, CYCLONE_HEADER_LEN};

/// Decodes a message body of type `T` in the given byte order; if it is accepted, checks that it
/// re-encodes (little-endian, as we send) to bytes that decode to a value encoding the same.
/// Returns the re-encoded body.
fn body_round_trip<T: Serialize + DeserializeOwned>(
    body: &[u8],
    big_endian: bool,
) -> Option<Vec<u8>> {
    let value: T = decode(body, big_endian).ok()?;
    let encoded = encode(&value).expect("a decoded message encodes");
    let again: T = decode(&encoded, false).expect("a re-encoded message decodes");
    assert_eq!(
        encode(&again).expect("a decoded message encodes"),
        encoded,
        "round trip of {} changed the message",
        std::any::type_name::<T>()
    );
    Some(encoded)
}

/// A horus-ros error reply's body (the handler's message as a CDR string), as a client reads it.
fn error_message(body: &[u8], big_endian: bool) {
    if let Ok(message) = decode::<String>(body, big_endian) {
        let encoded = encode(&message).expect("a decoded string encodes");
        assert_eq!(decode::<String>(&encoded, false).ok(), Some(message));
    }
}

/// rmw_cyclonedds' convention: the body as a server reads a request (header, then the request;
/// the reply echoes the header) and as a client reads a reply (header, then the response, or a
/// horus-ros server's error reply when the sequence number is negative).
pub fn cyclone(data: &[u8]) {
    let [flags, selector, body @ ..] = data else {
        return;
    };
    let big_endian = flags & 1 == 1;
    let Some((header, message)) = CycloneHeader::split(body, big_endian) else {
        assert!(body.len() < CYCLONE_HEADER_LEN);
        return;
    };
    assert_eq!(message, &body[CYCLONE_HEADER_LEN..]);
    if !big_endian {
        assert_eq!(header.prepend(message), body);
    }
    fn message_of<T: Serialize + DeserializeOwned>(
        header: CycloneHeader,
        message: &[u8],
        big_endian: bool,
    ) {
        if let Some(encoded) = body_round_trip::<T>(message, big_endian) {
            let framed = header.prepend(&encoded);
            assert_eq!(
                CycloneHeader::split(&framed, false),
                Some((header, &encoded[..]))
            );
        }
        if header.seq < 0 {
            error_message(message, big_endian);
        }
    }
    with_service_payload_type!(
        usize::from(*selector),
        message_of(header, message, big_endian)
    );
}

/// rmw_fastrtps' convention: plain bodies, correlated by `related_sample_identity` (read by
/// rustdds from the inline QoS), whose sequence number, when negative in a reply, marks a
/// horus-ros server's error reply. The body is read as the message (request or response) and,
/// for a negative sequence number, as an error reply.
pub fn fastrtps(data: &[u8]) {
    let [flags, selector, rest @ ..] = data else {
        return;
    };
    let Some((sequence, body)) = rest.split_first_chunk::<8>() else {
        return;
    };
    let big_endian = flags & 1 == 1;
    let sequence = i64::from_le_bytes(*sequence);
    fn message_of<T: Serialize + DeserializeOwned>(sequence: i64, body: &[u8], big_endian: bool) {
        let _ = body_round_trip::<T>(body, big_endian);
        if sequence < 0 {
            error_message(body, big_endian);
        }
    }
    with_service_payload_type!(
        usize::from(*selector),
        message_of(sequence, body, big_endian)
    );
}
