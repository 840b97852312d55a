//! TypeHash string form, USER_DATA encoding/parsing.

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::user_data::{parse_key_value, parse_type_hash_from_user_data};
use horus_ros_msgs::{Message, TypeHash, TypeHashError};

const TIME: &str = "RIHS01_b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197";

#[test]
fn display_and_parse() {
    let h: TypeHash = TIME.parse().expect("parse");
    assert_eq!(h.version, 1);
    assert_eq!(h.value[0], 0xb1);
    assert_eq!(h.to_string(), TIME);
    assert_eq!(h, Time::type_hash());
    // rosidl_runtime_c test_type_hash.cpp vector; upper-case hex is accepted as in rosidl.
    let v = "RIHS01_000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";
    let h = TypeHash::parse(v).expect("parse");
    assert_eq!(h.value, core::array::from_fn(|i| i as u8));
    assert_eq!(TypeHash::parse(&v.to_uppercase()), Ok(h));
}

#[test]
fn parse_errors() {
    assert_eq!(TypeHash::parse("RIHS0"), Err(TypeHashError::BadLength(5)));
    assert_eq!(
        TypeHash::parse("XIHS01_00"),
        Err(TypeHashError::MissingPrefix)
    );
    assert_eq!(TypeHash::parse("RIHSzz_00"), Err(TypeHashError::BadVersion));
    assert_eq!(
        TypeHash::parse(&TIME.replace("RIHS01", "RIHS02")),
        Err(TypeHashError::UnsupportedVersion(2))
    );
    // Lengths from rosidl_runtime_c test_type_hash.cpp (one byte short / one byte long).
    assert_eq!(
        TypeHash::parse(&TIME[..69]),
        Err(TypeHashError::BadLength(69))
    );
    assert_eq!(
        TypeHash::parse(&format!("{TIME}00")),
        Err(TypeHashError::BadLength(73))
    );
    assert_eq!(
        TypeHash::parse(&TIME.replacen('b', "g", 1)),
        Err(TypeHashError::BadHexDigit)
    );
}

#[test]
fn zero_hash() {
    assert!(!TypeHash::ZERO.is_set());
    assert_eq!(TypeHash::default(), TypeHash::ZERO);
    assert_eq!(TypeHash::ZERO.to_user_data(), "");
}

#[test]
fn user_data_round_trip() {
    let h = Time::type_hash();
    let ud = h.to_user_data();
    assert_eq!(ud, format!("typehash={TIME};"));
    assert_eq!(parse_type_hash_from_user_data(ud.as_bytes()), Ok(h));
    let cyclone = format!("typehash={TIME};serviceid=0110abcd;");
    assert_eq!(parse_type_hash_from_user_data(cyclone.as_bytes()), Ok(h));
    let kv = parse_key_value(cyclone.as_bytes());
    assert_eq!(
        kv.get("serviceid").map(Vec::as_slice),
        Some(&b"0110abcd"[..])
    );
    // Trailing NULs are accepted.
    let mut with_nul = ud.clone().into_bytes();
    with_nul.extend_from_slice(&[0, 0]);
    assert_eq!(parse_type_hash_from_user_data(&with_nul), Ok(h));
}

#[test]
fn user_data_without_hash_is_zero() {
    assert_eq!(parse_type_hash_from_user_data(b""), Ok(TypeHash::ZERO));
    assert_eq!(
        parse_type_hash_from_user_data(b"enclave=/;"),
        Ok(TypeHash::ZERO)
    );
    // Not key-value data at all: rmw treats it as foreign USER_DATA.
    assert_eq!(
        parse_type_hash_from_user_data(b"hello world"),
        Ok(TypeHash::ZERO)
    );
    assert!(parse_key_value(b"=x;").is_empty());
    assert!(parse_key_value(b"a=;").is_empty());
}

#[test]
fn malformed_hash_in_user_data_is_an_error() {
    assert!(parse_type_hash_from_user_data(b"typehash=RIHS01_12;").is_err());
    assert!(parse_type_hash_from_user_data(b"typehash=\xff\xfe;").is_err());
}

#[test]
fn serde_as_string() {
    let h = Time::type_hash();
    let json = serde_json::to_string(&h).expect("ser");
    assert_eq!(json, format!("\"{TIME}\""));
    let back: TypeHash = serde_json::from_str(&json).expect("de");
    assert_eq!(back, h);
    assert!(serde_json::from_str::<TypeHash>("\"nope\"").is_err());
}
