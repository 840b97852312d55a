//! Fuzzing entry points: each takes arbitrary bytes, runs one decoder of wire data on them and,
//! when it accepts them, checks that what it decoded encodes and decodes back to the same thing.
//!
//! They are called by the `fuzz/` targets (cargo-fuzz) and by `tests/fuzz_decoders.rs`; a panic
//! (including a failed round-trip assertion) is a bug.

use serde::{de::DeserializeOwned, Serialize};

use crate::cdr::{from_cdr, to_cdr, CdrError};
use crate::rmw_dds_common::ParticipantEntitiesInfo;
use crate::type_description_interfaces::srv::{
    GetTypeDescriptionRequest, GetTypeDescriptionResponse,
};
use crate::user_data::{parse_key_value, parse_type_hash_from_user_data};
use crate::{example_interfaces, rcl_interfaces, std_srvs, Message, TypeDescription, TypeHash};

/// Decodes a CDR payload (with its encapsulation header) as `T`; if it is accepted, checks that
/// the value re-encodes (CDR_LE) to bytes that decode to a value encoding to the same bytes.
///
/// Bytes rather than values are compared: they are exact for every field type (NaN floats
/// included, which `PartialEq` would call unequal). Returns the decoded value.
///
/// Decoding does not check `string<=N`, `wstring<=N` and `T[<=N]` bounds (a peer's over-long
/// value is kept, nothing is lost), encoding does ([`CdrError::BoundExceeded`]): a decoded value
/// over a bound is not re-encoded, and that refusal is the only encoding failure allowed.
pub fn cdr_round_trip<T: Serialize + DeserializeOwned>(data: &[u8]) -> Option<T> {
    let value = from_cdr::<T>(data).ok()?;
    let encoded = match to_cdr(&value) {
        Ok(encoded) => encoded,
        Err(CdrError::BoundExceeded(_)) => return Some(value),
        Err(e) => panic!("a decoded value encodes: {e:?}"),
    };
    let again = from_cdr::<T>(&encoded).expect("a re-encoded value decodes");
    assert_eq!(
        to_cdr(&again).expect("a decoded value encodes"),
        encoded,
        "CDR round trip of {} changed the value",
        std::any::type_name::<T>()
    );
    Some(value)
}

/// A `ros_discovery_info` sample (`rmw_dds_common/msg/ParticipantEntitiesInfo`, CDR with header).
pub fn participant_entities_info(data: &[u8]) {
    if let Some(info) = cdr_round_trip::<ParticipantEntitiesInfo>(data) {
        let Ok(encoded) = to_cdr(&info) else {
            return; // over a bound (see `cdr_round_trip`)
        };
        assert_eq!(
            from_cdr::<ParticipantEntitiesInfo>(&encoded).ok(),
            Some(info)
        );
    }
}

/// The service payload types compiled in, in the order [`service_payload`] selects them.
pub const SERVICE_PAYLOAD_TYPES: &[&str] = &[
    example_interfaces::srv::AddTwoIntsRequest::TYPE_NAME,
    example_interfaces::srv::AddTwoIntsResponse::TYPE_NAME,
    std_srvs::srv::EmptyRequest::TYPE_NAME,
    std_srvs::srv::EmptyResponse::TYPE_NAME,
    std_srvs::srv::TriggerRequest::TYPE_NAME,
    std_srvs::srv::TriggerResponse::TYPE_NAME,
    std_srvs::srv::SetBoolRequest::TYPE_NAME,
    std_srvs::srv::SetBoolResponse::TYPE_NAME,
    rcl_interfaces::srv::ListParametersRequest::TYPE_NAME,
    rcl_interfaces::srv::ListParametersResponse::TYPE_NAME,
    rcl_interfaces::srv::GetParametersRequest::TYPE_NAME,
    rcl_interfaces::srv::GetParametersResponse::TYPE_NAME,
    rcl_interfaces::srv::GetParameterTypesRequest::TYPE_NAME,
    rcl_interfaces::srv::GetParameterTypesResponse::TYPE_NAME,
    rcl_interfaces::srv::SetParametersRequest::TYPE_NAME,
    rcl_interfaces::srv::SetParametersResponse::TYPE_NAME,
    rcl_interfaces::srv::SetParametersAtomicallyRequest::TYPE_NAME,
    rcl_interfaces::srv::SetParametersAtomicallyResponse::TYPE_NAME,
    rcl_interfaces::srv::DescribeParametersRequest::TYPE_NAME,
    rcl_interfaces::srv::DescribeParametersResponse::TYPE_NAME,
    GetTypeDescriptionRequest::TYPE_NAME,
    GetTypeDescriptionResponse::TYPE_NAME,
];

/// Calls `$f::<T>($($arg),*)` for the service payload type `SERVICE_PAYLOAD_TYPES[$index]`
/// (`$index` taken modulo their number).
#[doc(hidden)]
#[macro_export]
macro_rules! with_service_payload_type {
    ($index:expr, $f:ident ( $($arg:expr),* )) => {{
        use $crate::example_interfaces::srv as ex;
        use $crate::rcl_interfaces::srv as rcl;
        use $crate::std_srvs::srv as ss;
        use $crate::type_description_interfaces::srv as td;
        match $index % $crate::fuzzing::SERVICE_PAYLOAD_TYPES.len() {
            0 => $f::<ex::AddTwoIntsRequest>($($arg),*),
            1 => $f::<ex::AddTwoIntsResponse>($($arg),*),
            2 => $f::<ss::EmptyRequest>($($arg),*),
            3 => $f::<ss::EmptyResponse>($($arg),*),
            4 => $f::<ss::TriggerRequest>($($arg),*),
            5 => $f::<ss::TriggerResponse>($($arg),*),
            6 => $f::<ss::SetBoolRequest>($($arg),*),
            7 => $f::<ss::SetBoolResponse>($($arg),*),
            8 => $f::<rcl::ListParametersRequest>($($arg),*),
            9 => $f::<rcl::ListParametersResponse>($($arg),*),
            10 => $f::<rcl::GetParametersRequest>($($arg),*),
            11 => $f::<rcl::GetParametersResponse>($($arg),*),
            12 => $f::<rcl::GetParameterTypesRequest>($($arg),*),
            13 => $f::<rcl::GetParameterTypesResponse>($($arg),*),
            14 => $f::<rcl::SetParametersRequest>($($arg),*),
            15 => $f::<rcl::SetParametersResponse>($($arg),*),
            16 => $f::<rcl::SetParametersAtomicallyRequest>($($arg),*),
            17 => $f::<rcl::SetParametersAtomicallyResponse>($($arg),*),
            18 => $f::<rcl::DescribeParametersRequest>($($arg),*),
            19 => $f::<rcl::DescribeParametersResponse>($($arg),*),
            20 => $f::<td::GetTypeDescriptionRequest>($($arg),*),
            _ => $f::<td::GetTypeDescriptionResponse>($($arg),*),
        }
    }};
}

/// A service request or response payload: the first byte selects the type
/// ([`SERVICE_PAYLOAD_TYPES`], modulo their number), the rest is its CDR payload with header.
pub fn service_payload(data: &[u8]) {
    let Some((&selector, payload)) = data.split_first() else {
        return;
    };
    fn one<T: Serialize + DeserializeOwned>(payload: &[u8]) {
        let _ = cdr_round_trip::<T>(payload);
    }
    with_service_payload_type!(usize::from(selector), one(payload));
}

/// What `~/get_type_description` returns (a `GetTypeDescription_Response` payload, CDR with
/// header), and the same bytes as a bare `TypeDescription` and as a request: each accepted one
/// round-trips, a description is hashed (RIHS01) and a request's hash string parsed.
pub fn type_description(data: &[u8]) {
    if let Some(response) = cdr_round_trip::<GetTypeDescriptionResponse>(data) {
        hash_round_trip(&response.type_description);
    }
    if let Some(description) = cdr_round_trip::<TypeDescription>(data) {
        hash_round_trip(&description);
    }
    if let Some(request) = cdr_round_trip::<GetTypeDescriptionRequest>(data) {
        type_hash_string(request.type_hash.as_bytes());
    }
}

/// The hash of a description is a pure function of it, and prints to a string that parses back.
fn hash_round_trip(description: &TypeDescription) {
    let hash = description.compute_type_hash();
    assert_eq!(description.compute_type_hash(), hash);
    assert_eq!(TypeHash::parse(&hash.to_string()), Ok(hash));
}

/// A `RIHS01_…` string: what parses prints back to a string that parses to the same hash.
pub fn type_hash_string(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(hash) = TypeHash::parse(text) {
        assert_eq!(TypeHash::parse(&hash.to_string()), Ok(hash));
        assert!(text.eq_ignore_ascii_case(&hash.to_string()));
    }
}

/// USER_DATA octets as a peer announces them (`key=value;…`, e.g. `typehash=RIHS01_…;`).
///
/// A parsed map whose values hold no `;` is written back as `key=value;…` and must parse to the
/// same map; a type hash found must be written back and parsed the same.
pub fn user_data(data: &[u8]) {
    let map = parse_key_value(data);
    for (key, value) in &map {
        assert!(!key.is_empty() && key.bytes().all(|b| b.is_ascii_alphanumeric()));
        assert!(!value.is_empty());
    }
    if !map.is_empty() && map.values().all(|v| !v.contains(&b';')) {
        let mut written = Vec::new();
        for (key, value) in &map {
            written.extend_from_slice(key.as_bytes());
            written.push(b'=');
            written.extend_from_slice(value);
            written.push(b';');
        }
        assert_eq!(parse_key_value(&written), map, "key=value round trip");
    }
    if let Ok(hash) = parse_type_hash_from_user_data(data) {
        if hash.is_set() {
            let written = hash.to_user_data();
            assert_eq!(parse_type_hash_from_user_data(written.as_bytes()), Ok(hash));
        } else {
            assert!(!map.contains_key("typehash"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_service_payload_table_matches_the_dispatch() {
        fn name<T: Message>() -> &'static str {
            T::TYPE_NAME
        }
        for (i, expected) in SERVICE_PAYLOAD_TYPES.iter().enumerate() {
            assert_eq!(with_service_payload_type!(i, name()), *expected);
        }
    }
}
