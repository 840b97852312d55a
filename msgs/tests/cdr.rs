//! CDR encoding: hand-computed XCDR1 bytes, round trips and malformed input.

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::cdr::CdrError;
use horus_ros_msgs::example_interfaces::srv::{AddTwoIntsRequest, AddTwoIntsResponse};
use horus_ros_msgs::rcl_interfaces::msg::{
    FloatingPointRange, Parameter, ParameterDescriptor, ParameterType, ParameterValue,
};
use horus_ros_msgs::rcl_interfaces::srv::{ListParametersRequest, SetParametersRequest};
use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_msgs::std_srvs::srv::{EmptyRequest, TriggerResponse};
use horus_ros_msgs::{from_cdr, to_cdr, Byte, Message};

fn round_trip<T: Message + PartialEq>(v: &T) {
    let bytes = to_cdr(v).expect("encode");
    let back: T = from_cdr(&bytes).expect("decode");
    assert_eq!(&back, v);
}

#[test]
fn add_two_ints_request_bytes() {
    let bytes = to_cdr(&AddTwoIntsRequest { a: 2, b: 3 }).expect("encode");
    let expected = [
        0x00, 0x01, 0x00, 0x00, // CDR_LE header
        2, 0, 0, 0, 0, 0, 0, 0, // a
        3, 0, 0, 0, 0, 0, 0, 0, // b
    ];
    assert_eq!(bytes, expected);
    let back: AddTwoIntsRequest = from_cdr(&bytes).expect("decode");
    assert_eq!(back, AddTwoIntsRequest { a: 2, b: 3 });
    let resp = to_cdr(&AddTwoIntsResponse { sum: -1 }).expect("encode");
    assert_eq!(
        resp,
        [0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff]
    );
}

#[test]
fn time_bytes_le_and_be() {
    let t = Time {
        sec: 1,
        nanosec: 0x0102_0304,
    };
    let bytes = to_cdr(&t).expect("encode");
    assert_eq!(bytes, [0, 1, 0, 0, 1, 0, 0, 0, 4, 3, 2, 1]);
    let be = [0, 0, 0, 0, 0, 0, 0, 1, 1, 2, 3, 4];
    assert_eq!(from_cdr::<Time>(&be).expect("decode BE"), t);
}

#[test]
fn string_alignment_bytes() {
    let v = TriggerResponse {
        success: true,
        message: "hi".into(),
    };
    let bytes = to_cdr(&v).expect("encode");
    let expected = [
        0, 1, 0, 0, // header
        1, // success
        0, 0, 0, // pad to 4
        3, 0, 0, 0, // length incl. NUL
        b'h', b'i', 0,
    ];
    assert_eq!(bytes, expected);
    round_trip(&v);
}

#[test]
fn int64_aligned_to_8_after_string_sequence() {
    let v = ListParametersRequest {
        prefixes: vec!["a".into()],
        depth: 5,
    };
    let bytes = to_cdr(&v).expect("encode");
    let expected = [
        0, 1, 0, 0, // header
        1, 0, 0, 0, // 1 prefix
        2, 0, 0, 0, b'a', 0, // "a"
        0, 0, 0, 0, 0, 0, // pad to 8 (body offset 10 → 16)
        5, 0, 0, 0, 0, 0, 0, 0, // depth
    ];
    assert_eq!(bytes, expected);
    round_trip(&v);
}

#[test]
fn participant_entities_info_bytes() {
    let gid = |last: u8| {
        let mut d = [0u8; 16];
        d[0] = 0x01;
        d[1] = 0x0f;
        d[15] = last;
        Gid::from_bytes(d)
    };
    let v = ParticipantEntitiesInfo {
        gid: gid(0xc1),
        node_entities_info_seq: vec![NodeEntitiesInfo {
            node_namespace: "/".into(),
            node_name: "n".into(),
            reader_gid_seq: vec![gid(0x04)],
            writer_gid_seq: vec![],
        }],
    };
    let bytes = to_cdr(&v).expect("encode");
    let mut expected = vec![0, 1, 0, 0];
    expected.extend_from_slice(gid(0xc1).as_bytes()); // gid: char[16], no length
    expected.extend_from_slice(&[1, 0, 0, 0]); // 1 node
    expected.extend_from_slice(&[2, 0, 0, 0, b'/', 0]); // namespace
    expected.extend_from_slice(&[0, 0]); // pad to 4
    expected.extend_from_slice(&[2, 0, 0, 0, b'n', 0]); // name
    expected.extend_from_slice(&[0, 0]); // pad to 4
    expected.extend_from_slice(&[1, 0, 0, 0]); // 1 reader
    expected.extend_from_slice(gid(0x04).as_bytes());
    expected.extend_from_slice(&[0, 0, 0, 0]); // 0 writers
    assert_eq!(bytes, expected);
    assert_eq!(bytes.len(), 4 + 60);
    round_trip(&v);
}

#[test]
fn empty_request_has_placeholder_byte() {
    let bytes = to_cdr(&EmptyRequest::default()).expect("encode");
    assert_eq!(bytes, [0, 1, 0, 0, 0]);
}

#[test]
fn service_event_info_bytes() {
    let v = ServiceEventInfo {
        event_type: ServiceEventInfo::RESPONSE_SENT,
        stamp: Time { sec: 1, nanosec: 2 },
        client_gid: [7; 16],
        sequence_number: 9,
    };
    let bytes = to_cdr(&v).expect("encode");
    let mut expected = vec![0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0];
    expected.extend_from_slice(&[7; 16]); // body offset 12..28
    expected.extend_from_slice(&[0, 0, 0, 0]); // pad to 8 (28 → 32)
    expected.extend_from_slice(&[9, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(bytes, expected);
    round_trip(&v);
}

#[test]
fn parameter_round_trips() {
    round_trip(&SetParametersRequest {
        parameters: vec![Parameter {
            name: "p".into(),
            value: ParameterValue {
                r#type: ParameterType::PARAMETER_BYTE_ARRAY,
                byte_array_value: vec![Byte(1), Byte(255)],
                double_array_value: vec![1.5],
                string_array_value: vec!["x".into(), String::new()],
                ..Default::default()
            },
        }],
    });
    round_trip(&ParameterDescriptor {
        name: "d".into(),
        floating_point_range: vec![FloatingPointRange {
            from_value: 0.0,
            to_value: 1.0,
            step: 0.1,
        }],
        ..Default::default()
    });
}

#[test]
fn malformed_input_is_an_error() {
    assert!(matches!(from_cdr::<Time>(&[]), Err(CdrError::TooShort(0))));
    assert!(matches!(
        from_cdr::<Time>(&[0, 1, 0]),
        Err(CdrError::TooShort(3))
    ));
    assert!(matches!(
        from_cdr::<Time>(&[0, 3, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]),
        Err(CdrError::UnsupportedEncapsulation([0, 3]))
    ));
    // Truncated body.
    assert!(matches!(
        from_cdr::<Time>(&[0, 1, 0, 0, 1, 0, 0, 0, 2]),
        Err(CdrError::Decode(_))
    ));
    assert!(matches!(
        from_cdr::<Time>(&[0, 1, 0, 0]),
        Err(CdrError::Decode(_))
    ));
    // A bool that is neither 0 nor 1.
    assert!(from_cdr::<TriggerResponse>(&[0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 0]).is_err());
    // Invalid UTF-8 in a string.
    assert!(from_cdr::<TriggerResponse>(&[0, 1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 0xff, 0]).is_err());
    // A string length running past the end.
    assert!(from_cdr::<TriggerResponse>(&[0, 1, 0, 0, 1, 0, 0, 0, 0xff, 0xff, 0, 0, 0]).is_err());
    // A huge sequence length must fail, not allocate or panic.
    let huge = [0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff, 0, 0, 0, 0];
    assert!(from_cdr::<ListParametersRequest>(&huge).is_err());
    assert!(from_cdr::<ParticipantEntitiesInfo>(&[0, 1, 0, 0, 1, 2, 3]).is_err());
}

#[test]
fn every_prefix_of_a_valid_message_is_rejected_without_panic() {
    let v = ParticipantEntitiesInfo {
        gid: Gid::from_bytes([3; 16]),
        node_entities_info_seq: vec![NodeEntitiesInfo {
            node_namespace: "/ns".into(),
            node_name: "node".into(),
            reader_gid_seq: vec![Gid::from_bytes([1; 16])],
            writer_gid_seq: vec![Gid::from_bytes([2; 16])],
        }],
    };
    let bytes = to_cdr(&v).expect("encode");
    for n in 0..bytes.len() {
        assert!(
            from_cdr::<ParticipantEntitiesInfo>(&bytes[..n]).is_err(),
            "prefix {n}"
        );
    }
}

/// `uint8[]` goes as one block of bytes (`runtime::bytes`): the same XCDR1 as element by
/// element — a 4-aligned `u32` count, then the bytes — both ways and in both byte orders, and
/// a count beyond the payload is an error.
#[test]
fn uint8_sequences_are_a_count_and_the_bytes() {
    use horus_ros_msgs::sensor_msgs::msg::CompressedImage;
    let image = CompressedImage {
        format: "x".into(),
        data: vec![7, 8, 9],
        ..Default::default()
    };
    let bytes = to_cdr(&image).expect("encode");
    let expected = [
        0x00, 0x01, 0x00, 0x00, // CDR_LE header
        0, 0, 0, 0, 0, 0, 0, 0, // header.stamp
        1, 0, 0, 0, 0, 0, 0, 0, // header.frame_id: "" (count 1, NUL), padded to 4
        2, 0, 0, 0, b'x', 0, 0, 0, // format: "x", padded to 4
        3, 0, 0, 0, 7, 8, 9, // data: count 3, the bytes
    ];
    assert_eq!(bytes, expected);
    assert_eq!(from_cdr::<CompressedImage>(&bytes).expect("decode"), image);
    // What a per-element encoder writes decodes the same (the body of a plain Vec<u8>).
    let per_element =
        horus_ros_msgs::cdr::to_cdr_body(&(0u32, 0u32, String::new(), "x", vec![7u8, 8, 9]))
            .expect("encode");
    assert_eq!(per_element, expected[4..]);
    // Big-endian.
    let be = [
        0x00, 0x00, 0x00, 0x00, // CDR_BE header
        0, 0, 0, 0, 0, 0, 0, 0, // header.stamp
        0, 0, 0, 1, 0, 0, 0, 0, // header.frame_id
        0, 0, 0, 2, b'x', 0, 0, 0, // format
        0, 0, 0, 3, 7, 8, 9, // data
    ];
    assert_eq!(from_cdr::<CompressedImage>(&be).expect("decode BE"), image);
    // A count larger than what follows.
    let mut short = expected.to_vec();
    short[28] = 4;
    assert!(from_cdr::<CompressedImage>(&short).is_err());
}
