//! CDR (XCDR1) encoding of messages with the 4-byte RTPS encapsulation header.
//!
//! The serialized payload starts with the encapsulation identifier (`00 00` CDR_BE,
//! `00 01` CDR_LE) and two option bytes, then the body; alignment is relative to the body
//! (OMG DDS-RTPS 2.5 §10.5; ROS 2 writes CDR_LE, `00 01 00 00`).

use byteorder::{BigEndian, LittleEndian};
use serde::{de::DeserializeOwned, Serialize};

use crate::runtime::{take_bound_error, BoundError};

/// Encapsulation header of little-endian plain CDR, as ROS 2 writes it.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];
/// Encapsulation identifier of big-endian plain CDR.
pub const CDR_BE_ID: [u8; 2] = [0x00, 0x00];
/// Encapsulation identifier of little-endian plain CDR.
pub const CDR_LE_ID: [u8; 2] = [0x00, 0x01];

/// Errors of [`to_cdr`] / [`from_cdr`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CdrError {
    /// Fewer than the 4 bytes of the encapsulation header.
    #[error("CDR payload of {0} bytes is shorter than its 4-byte encapsulation header")]
    TooShort(usize),
    /// An encapsulation other than CDR_BE / CDR_LE (e.g. PL_CDR or XCDR2).
    #[error("unsupported CDR encapsulation {0:02x?}")]
    UnsupportedEncapsulation([u8; 2]),
    /// The body does not decode as the expected type (truncated, bad bool, bad UTF-8…).
    #[error("malformed CDR body: {0}")]
    Decode(cdr_encoding::Error),
    /// The value cannot be encoded.
    #[error("CDR encoding failed: {0}")]
    Encode(cdr_encoding::Error),
    /// A bounded field (`string<=N`, `wstring<=N`, `T[<=N]`) holds more than its bound allows
    /// (checked by [`crate::runtime::Bounded`]).
    #[error(transparent)]
    BoundExceeded(BoundError),
}

/// Runs one encode: drops a stale bound violation first, and reports the one the encode left
/// as [`CdrError::BoundExceeded`] instead of the serializer's message.
fn encode<R>(run: impl FnOnce() -> Result<R, cdr_encoding::Error>) -> Result<R, CdrError> {
    take_bound_error();
    let result = run();
    let bound = take_bound_error();
    result.map_err(|e| match bound {
        Some(b) => CdrError::BoundExceeded(b),
        None => CdrError::Encode(e),
    })
}

/// Encodes `value` as CDR_LE with the encapsulation header `00 01 00 00`.
pub fn to_cdr<T: Serialize>(value: &T) -> Result<Vec<u8>, CdrError> {
    let mut out = Vec::with_capacity(64);
    out.extend_from_slice(&CDR_LE_HEADER);
    encode(|| cdr_encoding::to_writer::<_, LittleEndian, _>(&mut out, value))?;
    Ok(out)
}

/// Encodes only the CDR_LE body (no encapsulation header).
pub fn to_cdr_body<T: Serialize>(value: &T) -> Result<Vec<u8>, CdrError> {
    encode(|| cdr_encoding::to_vec::<_, LittleEndian>(value))
}

/// Decodes a payload that starts with a CDR_LE or CDR_BE encapsulation header.
/// Trailing bytes after the value (padding) are ignored.
pub fn from_cdr<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, CdrError> {
    let (header, body) = match bytes.split_first_chunk::<4>() {
        Some(split) => split,
        None => return Err(CdrError::TooShort(bytes.len())),
    };
    let id = [header[0], header[1]];
    match id {
        CDR_LE_ID => from_cdr_body::<T, LittleEndian>(body),
        CDR_BE_ID => from_cdr_body::<T, BigEndian>(body),
        other => Err(CdrError::UnsupportedEncapsulation(other)),
    }
}

/// Decodes a body without header in the given byte order.
pub fn from_cdr_body<T: DeserializeOwned, BO: byteorder::ByteOrder>(
    body: &[u8],
) -> Result<T, CdrError> {
    cdr_encoding::from_bytes::<T, BO>(body)
        .map(|(v, _consumed)| v)
        .map_err(CdrError::Decode)
}
