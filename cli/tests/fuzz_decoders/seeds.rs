//! The seed inputs of every fuzz target, built from valid encodings: what `fuzz/seeds/<target>/`
//! holds (`HORUS_ROS_WRITE_FUZZ_SEEDS=1 cargo test -p horus-ros-cli --test fuzz_decoders` writes
//! them; the test checks that the committed files are these).

use byteorder::BigEndian;
use horus_ros_dynamic::cdr;
use horus_ros_dynamic::fuzzing::{compiled_roots, compiled_schema};
use horus_ros_msgs::cdr::{to_cdr, to_cdr_body};
use horus_ros_msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
use horus_ros_msgs::fuzzing::SERVICE_PAYLOAD_TYPES;
use horus_ros_msgs::rcl_interfaces::msg::{Parameter, ParameterValue};
use horus_ros_msgs::rcl_interfaces::srv::{SetParameters, SetParametersRequest};
use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolResponse};
use horus_ros_msgs::type_description_interfaces::srv::{
    GetTypeDescriptionRequest, GetTypeDescriptionResponse,
};
use horus_ros_msgs::{with_service_payload_type, Byte, Message, Service, TypeDescription};
use serde::Serialize;

/// One seed: a file name and its bytes.
pub type Seed = (String, Vec<u8>);

fn seed(name: impl Into<String>, bytes: Vec<u8>) -> Seed {
    (name.into(), bytes)
}

fn le<T: Serialize>(value: &T) -> Vec<u8> {
    to_cdr(value).expect("seed encodes")
}

/// `00 00 00 00` + big-endian body.
fn be<T: Serialize>(value: &T) -> Vec<u8> {
    let mut out = vec![0, 0, 0, 0];
    out.extend(cdr_encoding::to_vec::<_, BigEndian>(value).expect("seed encodes"));
    out
}

fn body<T: Serialize>(value: &T) -> Vec<u8> {
    to_cdr_body(value).expect("seed encodes")
}

fn body_be<T: Serialize>(value: &T) -> Vec<u8> {
    cdr_encoding::to_vec::<_, BigEndian>(value).expect("seed encodes")
}

fn gid(last: u8) -> Gid {
    let mut data = [
        0x01, 0x0f, 0xc8, 0xb6, 0xfe, 0x43, 0xb3, 0x44, 0, 0, 0, 0, 0, 0, 0, 0,
    ];
    data[12..].copy_from_slice(&[0, 0, 0x0e, last]);
    Gid::from_bytes(data)
}

fn participant_info() -> ParticipantEntitiesInfo {
    ParticipantEntitiesInfo {
        gid: gid(0xc1),
        node_entities_info_seq: vec![
            NodeEntitiesInfo {
                node_namespace: "/".into(),
                node_name: "add_two_ints_server".into(),
                reader_gid_seq: vec![gid(0x04), gid(0x07)],
                writer_gid_seq: vec![gid(0x03)],
            },
            NodeEntitiesInfo {
                node_namespace: "/robot1".into(),
                node_name: "talker".into(),
                reader_gid_seq: Vec::new(),
                writer_gid_seq: vec![gid(0x13), gid(0x23)],
            },
        ],
    }
}

fn set_parameters_request() -> SetParametersRequest {
    SetParametersRequest {
        parameters: vec![
            Parameter {
                name: "use_sim_time".into(),
                value: ParameterValue {
                    r#type: 1,
                    bool_value: true,
                    ..Default::default()
                },
            },
            Parameter {
                name: "gains".into(),
                value: ParameterValue {
                    r#type: 8,
                    double_array_value: vec![1.5, -2.0, f64::NAN],
                    ..Default::default()
                },
            },
            Parameter {
                name: "blob".into(),
                value: ParameterValue {
                    r#type: 5,
                    byte_array_value: vec![Byte(0), Byte(255)],
                    string_array_value: vec!["x".into(), "yz".into()],
                    ..Default::default()
                },
            },
        ],
    }
}

fn description_response(description: TypeDescription) -> GetTypeDescriptionResponse {
    GetTypeDescriptionResponse {
        successful: true,
        failure_reason: String::new(),
        type_description: description,
        type_sources: Vec::new(),
        extra_information: Vec::new(),
    }
}

const TYPE_HASH: &str = "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a";

fn user_data_strings() -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("typehash", format!("typehash={TYPE_HASH};").into_bytes()),
        (
            "client_typehash",
            format!(
                "clientid=01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04;typehash={TYPE_HASH};"
            )
            .into_bytes(),
        ),
        ("enclave", b"enclave=/;".to_vec()),
        ("trailing_nuls", b"enclave=/robot;\0\0\0".to_vec()),
        ("escaped_semicolon", b"key=a;;b;other=c;".to_vec()),
        ("bad_hash", b"typehash=RIHS01_xyz;".to_vec()),
    ]
}

/// The `sequence<octet>` PID_USER_DATA value: length, octets, padding to 4.
fn user_data_parameter(octets: &[u8]) -> Vec<u8> {
    let mut out = u32::try_from(octets.len())
        .expect("short")
        .to_le_bytes()
        .to_vec();
    out.extend_from_slice(octets);
    out.resize(out.len().next_multiple_of(4), 0);
    out
}

fn payload_selector(type_name: &str) -> u8 {
    let i = SERVICE_PAYLOAD_TYPES
        .iter()
        .position(|t| *t == type_name)
        .expect("a compiled payload type");
    u8::try_from(i).expect("few types")
}

fn root_selector(type_name: &str) -> u8 {
    let i = compiled_roots()
        .iter()
        .position(|t| t == type_name)
        .expect("a compiled root");
    u8::try_from(i).expect("few roots")
}

fn cyclone_header(guid: u64, seq: i64, big_endian: bool) -> Vec<u8> {
    if big_endian {
        [guid.to_be_bytes(), seq.to_be_bytes()].concat()
    } else {
        [guid.to_le_bytes(), seq.to_le_bytes()].concat()
    }
}

/// The seeds of `target`.
pub fn seeds(target: &str) -> Vec<Seed> {
    let mut out = Vec::new();
    match target {
        "cdr_participant_entities_info" => {
            out.push(seed("empty_le", le(&ParticipantEntitiesInfo::default())));
            out.push(seed("two_nodes_le", le(&participant_info())));
            out.push(seed("two_nodes_be", be(&participant_info())));
        }
        "cdr_service_payload" => {
            fn default_payload<T: Default + Serialize>() -> Vec<u8> {
                le(&T::default())
            }
            for (i, name) in SERVICE_PAYLOAD_TYPES.iter().enumerate() {
                let mut bytes = vec![u8::try_from(i).expect("few types")];
                bytes.extend(with_service_payload_type!(i, default_payload()));
                out.push(seed(format!("default_{}", file_name(name)), bytes));
            }
            let add = payload_selector(AddTwoIntsRequest::TYPE_NAME);
            out.push(seed(
                "add_two_ints_request_be",
                [vec![add], be(&AddTwoIntsRequest { a: 2, b: -3 })].concat(),
            ));
            let set = payload_selector(SetParametersRequest::TYPE_NAME);
            out.push(seed(
                "set_parameters_request",
                [vec![set], le(&set_parameters_request())].concat(),
            ));
            let describe = payload_selector(GetTypeDescriptionRequest::TYPE_NAME);
            out.push(seed(
                "get_type_description_request",
                [
                    vec![describe],
                    le(&GetTypeDescriptionRequest {
                        type_name: AddTwoInts::TYPE_NAME.into(),
                        type_hash: TYPE_HASH.into(),
                        include_type_sources: true,
                    }),
                ]
                .concat(),
            ));
        }
        "cdr_type_description" => {
            out.push(seed(
                "add_two_ints_response",
                le(&description_response(AddTwoInts::type_description())),
            ));
            out.push(seed(
                "set_bool_response_be",
                be(&description_response(SetBool::type_description())),
            ));
            out.push(seed(
                "participant_entities_info_description",
                le(&ParticipantEntitiesInfo::type_description()),
            ));
            out.push(seed(
                "request",
                le(&GetTypeDescriptionRequest {
                    type_name: AddTwoInts::TYPE_NAME.into(),
                    type_hash: TYPE_HASH.into(),
                    include_type_sources: false,
                }),
            ));
        }
        "user_data" => {
            for (name, bytes) in user_data_strings() {
                out.push(seed(name, bytes));
            }
        }
        "rmw_user_data" => {
            for (name, bytes) in user_data_strings() {
                out.push(seed(
                    format!("{name}_parameter"),
                    user_data_parameter(&bytes),
                ));
            }
            out.push(seed("bare", format!("typehash={TYPE_HASH};").into_bytes()));
        }
        "dds_names" => {
            for (name, topic, ty) in [
                ("topic", "rt/chatter", "std_msgs::msg::dds_::String_"),
                (
                    "request",
                    "rq/add_two_intsRequest",
                    "example_interfaces::srv::dds_::AddTwoInts_Request_",
                ),
                (
                    "reply",
                    "rr/robot1/add_two_intsReply",
                    "example_interfaces::srv::dds_::AddTwoInts_Response_",
                ),
                (
                    "discovery_info",
                    "ros_discovery_info",
                    "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_",
                ),
            ] {
                out.push(seed(name, [topic.as_bytes(), &[0], ty.as_bytes()].concat()));
            }
        }
        "service_wire_cyclone" => {
            let add = payload_selector(AddTwoIntsRequest::TYPE_NAME);
            let sum = payload_selector(AddTwoIntsResponse::TYPE_NAME);
            let set = payload_selector(SetParametersRequest::TYPE_NAME);
            let horus_id = 0x484f_0000_1234_5678u64;
            out.push(seed(
                "add_two_ints_request",
                [
                    vec![0, add],
                    cyclone_header(0x0123_4567_89ab_cdef, 1, false),
                    body(&AddTwoIntsRequest { a: 2, b: 3 }),
                ]
                .concat(),
            ));
            out.push(seed(
                "add_two_ints_request_be",
                [
                    vec![1, add],
                    cyclone_header(0x0123_4567_89ab_cdef, 7, true),
                    body_be(&AddTwoIntsRequest { a: 2, b: 3 }),
                ]
                .concat(),
            ));
            out.push(seed(
                "add_two_ints_response",
                [
                    vec![0, sum],
                    cyclone_header(horus_id, 1, false),
                    body(&AddTwoIntsResponse { sum: 5 }),
                ]
                .concat(),
            ));
            out.push(seed(
                "error_reply",
                [
                    vec![0, sum],
                    cyclone_header(horus_id, -1, false),
                    body(&"Unknown joint: wrist".to_owned()),
                ]
                .concat(),
            ));
            out.push(seed(
                "set_parameters_request",
                [
                    vec![0, set],
                    cyclone_header(horus_id, 3, false),
                    body(&set_parameters_request()),
                ]
                .concat(),
            ));
        }
        "service_wire_fastrtps" => {
            let add = payload_selector(AddTwoIntsRequest::TYPE_NAME);
            let set_bool = payload_selector(SetBoolResponse::TYPE_NAME);
            out.push(seed(
                "add_two_ints_request",
                [
                    vec![0, add],
                    0x484f_5255_0000_0001i64.to_le_bytes().to_vec(),
                    body(&AddTwoIntsRequest { a: 2, b: 3 }),
                ]
                .concat(),
            ));
            out.push(seed(
                "set_bool_response_be",
                [
                    vec![1, set_bool],
                    4i64.to_le_bytes().to_vec(),
                    body_be(&SetBoolResponse {
                        success: true,
                        message: "héllo".into(),
                    }),
                ]
                .concat(),
            ));
            out.push(seed(
                "error_reply",
                [
                    vec![0, set_bool],
                    (-4i64).to_le_bytes().to_vec(),
                    body(&"the service handler failed".to_owned()),
                ]
                .concat(),
            ));
        }
        "dynamic_cdr" => {
            let schema = compiled_schema();
            for (i, root) in compiled_roots().iter().enumerate() {
                let value = schema.default_value(root).expect("a compiled type");
                let bytes = cdr::encode(schema, root, &value).expect("default encodes");
                let selector = u8::try_from(i).expect("few roots");
                out.push(seed(
                    format!("default_{}", file_name(root)),
                    [vec![0, selector], bytes].concat(),
                ));
            }
            let set = root_selector(SetParametersRequest::TYPE_NAME);
            out.push(seed(
                "set_parameters_request",
                [vec![0, set], body(&set_parameters_request())].concat(),
            ));
            out.push(seed(
                "set_parameters_request_be",
                [vec![1, set], body_be(&set_parameters_request())].concat(),
            ));
            let info = root_selector(ParticipantEntitiesInfo::TYPE_NAME);
            out.push(seed(
                "participant_entities_info",
                [vec![0, info], body(&participant_info())].concat(),
            ));
            let described = root_selector(GetTypeDescriptionResponse::TYPE_NAME);
            out.push(seed(
                "get_type_description_response",
                [
                    vec![0, described],
                    body(&description_response(AddTwoInts::type_description())),
                ]
                .concat(),
            ));
        }
        "dynamic_yaml" => {
            let add = root_selector(AddTwoIntsRequest::TYPE_NAME);
            let set = root_selector(SetParametersRequest::TYPE_NAME);
            for (name, selector, text) in [
                ("add_two_ints", add, "{a: 2, b: -3}"),
                ("add_two_ints_block", add, "a: 2\nb: 0x10\n"),
                ("empty", add, ""),
                (
                    "set_parameters",
                    set,
                    "parameters:\n  - name: a\n    value: {type: 2, integer_value: 7}\n  - name: \
                     bcd\n    value:\n      type: 9\n      byte_array_value: [1, 255]\n      \
                     double_array_value: [1.5, -2, .nan, -.inf]\n      string_array_value: ['x', \
                     \"y\\u00e9z\"]\n      bool_array_value: [true, false, true]\n",
                ),
                (
                    "set_bool",
                    root_selector("std_srvs/srv/SetBool_Request"),
                    "data: true",
                ),
                (
                    "describe",
                    root_selector(GetTypeDescriptionRequest::TYPE_NAME),
                    "{type_name: example_interfaces/srv/AddTwoInts, type_hash: 'RIHS01_00', \
                     include_type_sources: false}",
                ),
                (
                    "event",
                    root_selector("example_interfaces/srv/AddTwoInts_Event"),
                    "{info: {event_type: 1, stamp: {sec: 1, nanosec: 2}, client_gid: [0, 1, 2, \
                     3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15], sequence_number: 3}, \
                     request: [{a: 1, b: 2}]}",
                ),
            ] {
                let mut bytes = vec![selector];
                bytes.extend_from_slice(text.as_bytes());
                out.push(seed(name, bytes));
            }
        }
        "dynamic_description" => {
            for (name, description, message) in [
                (
                    "add_two_ints",
                    AddTwoInts::type_description(),
                    body(&AddTwoIntsRequest { a: 2, b: 3 }),
                ),
                (
                    "set_bool",
                    SetBool::type_description(),
                    body(&SetBoolResponse {
                        success: false,
                        message: "no".into(),
                    }),
                ),
                (
                    "set_parameters_event",
                    SetParameters::event_type_description(),
                    body(&set_parameters_request()),
                ),
                (
                    "participant_entities_info",
                    ParticipantEntitiesInfo::type_description(),
                    body(&participant_info()),
                ),
            ] {
                let payload = le(&description_response(description));
                let len = u16::try_from(payload.len()).expect("a description under 64 KiB");
                out.push(seed(
                    name,
                    [len.to_le_bytes().to_vec(), payload, vec![0], message].concat(),
                ));
            }
        }
        other => panic!("no seeds for fuzz target {other}"),
    }
    out
}

/// `pkg/srv/Name_Request` → `pkg_srv_name_request`.
fn file_name(type_name: &str) -> String {
    type_name.replace('/', "_").to_lowercase()
}
