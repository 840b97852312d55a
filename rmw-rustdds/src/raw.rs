//! Samples as raw CDR bodies: the services layer lays out request and reply payloads itself
//! (the rmw_cyclonedds header, or none for rmw_fastrtps), so rustdds only moves bytes.

use rustdds::bytes::Bytes;
use rustdds::no_key::{Decode, DefaultDecoder, DeserializerAdapter, SerializerAdapter};
use rustdds::RepresentationIdentifier;

/// A sample's CDR body (after the 4-byte encapsulation header) and its byte order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct RawPayload {
    /// True for CDR_BE, false for CDR_LE.
    pub(crate) big_endian: bool,
    /// The body.
    pub(crate) body: Vec<u8>,
}

/// Why a sample could not be taken as raw CDR (never: every plain-CDR body is accepted).
#[derive(Debug, thiserror::Error)]
#[error("raw CDR payload error")]
pub(crate) struct RawError;

/// Writes bodies as CDR_LE, reads CDR_LE and CDR_BE bodies as they are.
pub(crate) struct RawAdapter;

impl SerializerAdapter<RawPayload> for RawAdapter {
    type Error = RawError;

    fn output_encoding() -> RepresentationIdentifier {
        RepresentationIdentifier::CDR_LE
    }

    fn to_bytes(value: &RawPayload) -> Result<Bytes, RawError> {
        Ok(Bytes::copy_from_slice(&value.body))
    }
}

impl DeserializerAdapter<RawPayload> for RawAdapter {
    type Error = RawError;
    type Decoded = RawPayload;

    fn supported_encodings() -> &'static [RepresentationIdentifier] {
        &[
            RepresentationIdentifier::CDR_LE,
            RepresentationIdentifier::CDR_BE,
        ]
    }

    fn transform_decoded(decoded: RawPayload) -> RawPayload {
        decoded
    }
}

/// Copies the body.
#[derive(Clone, Copy)]
pub(crate) struct RawDecoder;

impl Decode<'_, RawPayload> for RawDecoder {
    type Error = RawError;

    fn decode_bytes(
        self,
        input: &[u8],
        encoding: RepresentationIdentifier,
    ) -> Result<RawPayload, RawError> {
        Ok(RawPayload {
            big_endian: encoding == RepresentationIdentifier::CDR_BE,
            body: input.to_vec(),
        })
    }
}

impl DefaultDecoder<RawPayload> for RawAdapter {
    type Decoder = RawDecoder;
    const DECODER: RawDecoder = RawDecoder;
}
