//! CDR helpers: message bodies encoded and decoded with the errors of this crate.

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::{ServiceError, TransportError};

/// Encodes a message as a CDR_LE body.
pub(crate) fn encode<T: Serialize>(value: &T) -> Result<Vec<u8>, ServiceError> {
    horus_ros_msgs::cdr::to_cdr_body(value)
        .map_err(|e| ServiceError::Transport(TransportError::Serialization(e.to_string())))
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
    result.map_err(|e| ServiceError::Transport(TransportError::Deserialization(e.to_string())))
}
