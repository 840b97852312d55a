//! The `service!` macro: the seed's definitions, ROS package names, RIHS01 hashes equal to the
//! ones ROS 2 Jazzy generates, CDR bytes equal to the msgs crate's types, empty structs,
//! attributes and every kind of field.
//!
//! Reference hashes: `../shared/docs/ros2-jazzy-wire-facts.md` (AddTwoInts, read off a Jazzy
//! build) and the msgs crate's own types, whose hashes `msgs/tests/hashes.rs` checks against
//! published values (the literals below are copied from there).

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::type_description_interfaces::msg::FieldType;
use horus_ros_msgs::{from_cdr, to_cdr, Byte, Message, Service, TypeHash};
use horus_ros_services::service;

// ---- the seed's definitions, unchanged -------------------------------------------------------

service! {
    GetMapRegion {
        request {
            x_min: f64,
            y_min: f64,
            x_max: f64,
            y_max: f64,
            resolution: f64,
        }
        response {
            width: u32,
            height: u32,
            data: Vec<u8>,
            timestamp: u64,
        }
    }
}

service! {
    GetJointLimits {
        request {
            joint_name: String,
        }
        response {
            min_position: f64,
            max_position: f64,
            max_velocity: f64,
            max_effort: f64,
        }
    }
}

fn hex(h: TypeHash) -> String {
    assert_eq!(h.version, 1, "RIHS01");
    h.hex_value()
}

fn round_trip<T: Message + PartialEq>(v: &T) -> Vec<u8> {
    let bytes = to_cdr(v).expect("encode");
    let back: T = from_cdr(&bytes).expect("decode");
    assert_eq!(&back, v);
    bytes
}

/// Same service type (names, DDS names and all four hashes).
fn assert_same_service<A: Service, B: Service>() {
    assert_eq!(A::TYPE_NAME, B::TYPE_NAME);
    assert_eq!(A::Request::TYPE_NAME, B::Request::TYPE_NAME);
    assert_eq!(A::Response::TYPE_NAME, B::Response::TYPE_NAME);
    assert_eq!(A::request_dds_type_name(), B::request_dds_type_name());
    assert_eq!(A::response_dds_type_name(), B::response_dds_type_name());
    assert_eq!(A::type_description(), B::type_description());
    assert_eq!(A::event_type_description(), B::event_type_description());
    assert_eq!(A::type_hash(), B::type_hash(), "{}", A::TYPE_NAME);
    assert_eq!(A::Request::type_hash(), B::Request::type_hash());
    assert_eq!(A::Response::type_hash(), B::Response::type_hash());
    assert_eq!(A::event_type_hash(), B::event_type_hash());
}

#[test]
fn seed_get_map_region() {
    assert_eq!(GetMapRegion::TYPE_NAME, "horus_ros/srv/GetMapRegion");
    assert_eq!(
        GetMapRegionRequest::TYPE_NAME,
        "horus_ros/srv/GetMapRegion_Request"
    );
    assert_eq!(
        GetMapRegionResponse::TYPE_NAME,
        "horus_ros/srv/GetMapRegion_Response"
    );
    assert_eq!(
        GetMapRegion::request_dds_type_name(),
        "horus_ros::srv::dds_::GetMapRegion_Request_"
    );
    assert_eq!(
        GetMapRegion::response_dds_type_name(),
        "horus_ros::srv::dds_::GetMapRegion_Response_"
    );

    let req = GetMapRegionRequest {
        x_min: 0.0,
        y_min: 0.0,
        x_max: 10.0,
        y_max: 10.0,
        resolution: 0.05,
    };
    let bytes = round_trip(&req);
    assert_eq!(bytes.len(), 4 + 5 * 8);
    assert_eq!(&bytes[..4], &[0, 1, 0, 0]);
    assert_eq!(&bytes[4 + 4 * 8..], &0.05f64.to_le_bytes());

    let resp = GetMapRegionResponse {
        width: 3,
        height: 2,
        data: vec![1, 2, 3, 4, 5, 6],
        timestamp: 1_700_000_000_000,
    };
    let bytes = round_trip(&resp);
    #[rustfmt::skip]
    let expected: Vec<u8> = [
        &[0u8, 1, 0, 0][..],           // CDR_LE header
        &[3, 0, 0, 0], &[2, 0, 0, 0],  // width, height
        &[6, 0, 0, 0], &[1, 2, 3, 4, 5, 6], // data: length, bytes
        &[0; 6],                       // padding to 24 (8-byte alignment)
        &1_700_000_000_000u64.to_le_bytes(),
    ]
    .concat();
    assert_eq!(bytes, expected);

    // The hash follows the rosidl rules for this definition (same description, built by hand).
    let d = horus_ros_msgs::DescriptionBuilder::new("horus_ros/srv/GetMapRegion_Response")
        .field::<u32>("width")
        .field::<u32>("height")
        .field::<Vec<u8>>("data")
        .field::<u64>("timestamp")
        .build();
    assert_eq!(GetMapRegionResponse::type_description(), d);
    assert_eq!(
        GetMapRegionResponse::type_hash(),
        horus_ros_msgs::rihs::rihs01(&d)
    );
    assert!(GetMapRegion::type_hash().is_set());
    assert!(GetMapRegion::event_type_hash().is_set());
}

#[test]
fn seed_get_joint_limits() {
    assert_eq!(GetJointLimits::TYPE_NAME, "horus_ros/srv/GetJointLimits");
    let req = GetJointLimitsRequest {
        joint_name: "elbow".into(),
    };
    let bytes = round_trip(&req);
    assert_eq!(
        bytes,
        [0, 1, 0, 0, 6, 0, 0, 0, b'e', b'l', b'b', b'o', b'w', 0]
    );
    round_trip(&GetJointLimitsResponse {
        min_position: 0.0,
        max_position: 2.61,
        max_velocity: 2.0,
        max_effort: 80.0,
    });
    let fields: Vec<_> = GetJointLimitsResponse::type_description()
        .type_description
        .fields
        .into_iter()
        .map(|f| (f.name, f.r#type.type_id))
        .collect();
    let double = FieldType::FIELD_TYPE_DOUBLE;
    assert_eq!(
        fields,
        [
            ("min_position".to_owned(), double),
            ("max_position".to_owned(), double),
            ("max_velocity".to_owned(), double),
            ("max_effort".to_owned(), double),
        ]
    );
}

// ---- a named package: example_interfaces/srv/AddTwoInts --------------------------------------

mod add_two_ints {
    horus_ros_services::service! {
        example_interfaces/AddTwoInts {
            request { a: i64, b: i64 }
            response { sum: i64 }
        }
    }
}

#[test]
fn add_two_ints_is_the_real_type() {
    use add_two_ints::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
    use horus_ros_msgs::example_interfaces::srv as real;

    assert_eq!(AddTwoInts::TYPE_NAME, "example_interfaces/srv/AddTwoInts");
    assert_eq!(
        AddTwoIntsRequest::TYPE_NAME,
        "example_interfaces/srv/AddTwoInts_Request"
    );
    assert_eq!(
        AddTwoIntsResponse::TYPE_NAME,
        "example_interfaces/srv/AddTwoInts_Response"
    );
    assert_eq!(
        AddTwoInts::request_dds_type_name(),
        "example_interfaces::srv::dds_::AddTwoInts_Request_"
    );
    assert_eq!(
        AddTwoInts::response_dds_type_name(),
        "example_interfaces::srv::dds_::AddTwoInts_Response_"
    );
    // ros2-jazzy-wire-facts.md: RIHS01 hashes produced by ROS 2 Jazzy.
    assert_eq!(
        hex(AddTwoInts::type_hash()),
        "e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"
    );
    assert_eq!(
        hex(AddTwoIntsRequest::type_hash()),
        "000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302"
    );
    assert_eq!(
        hex(AddTwoIntsResponse::type_hash()),
        "de5c030d4af33cba2749310b249737b631594703f9300495f48bffb2b44dcc2f"
    );
    assert_eq!(
        hex(AddTwoInts::event_type_hash()),
        "32c1d140259c71e5c355115942bcb31df98b4330e4d906b1b75ccb1c9b3ce6c8"
    );
    assert_eq!(
        AddTwoInts::type_hash().to_string(),
        "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"
    );
    assert_same_service::<AddTwoInts, real::AddTwoInts>();

    // Same bytes as the msgs crate's types, both ways.
    let mine = AddTwoIntsRequest { a: 2, b: -3 };
    let theirs = real::AddTwoIntsRequest { a: 2, b: -3 };
    let bytes = round_trip(&mine);
    assert_eq!(bytes, to_cdr(&theirs).expect("encode"));
    assert_eq!(
        from_cdr::<real::AddTwoIntsRequest>(&bytes).expect("decode"),
        theirs
    );
    let resp = to_cdr(&real::AddTwoIntsResponse { sum: -1 }).expect("encode");
    assert_eq!(
        from_cdr::<AddTwoIntsResponse>(&resp).expect("decode"),
        AddTwoIntsResponse { sum: -1 }
    );
}

mod add_two_ints_srv_form {
    // `pkg/srv/Name` is accepted too.
    horus_ros_services::service! {
        example_interfaces/srv/AddTwoInts {
            request { a: i64, b: i64, }
            response { sum: i64, }
        }
    }
}

#[test]
fn package_srv_name_form() {
    assert_same_service::<
        add_two_ints_srv_form::AddTwoInts,
        horus_ros_msgs::example_interfaces::srv::AddTwoInts,
    >();
}

// ---- empty requests / responses: std_srvs ----------------------------------------------------

mod std_srvs_mine {
    horus_ros_services::service! {
        std_srvs/Trigger {
            request {}
            response {
                success: bool,
                message: String,
            }
        }

        std_srvs/Empty {
            request {}
            response {}
        }
    }
}

#[test]
fn trigger_with_empty_request_matches_std_srvs() {
    use horus_ros_msgs::std_srvs::srv as real;
    use std_srvs_mine::{Trigger, TriggerRequest, TriggerResponse};

    // msgs/tests/hashes.rs (published values).
    assert_eq!(
        hex(Trigger::type_hash()),
        "eeff2cd6fa5ad9d27cdf4dec64818317839b62f212a91e6b5304b634b2062c5f"
    );
    assert_eq!(
        hex(TriggerRequest::type_hash()),
        "d010825374ce8918e72bfd826c82603e60f45419e932ea976f807b74a863a199"
    );
    assert_eq!(
        hex(TriggerResponse::type_hash()),
        "2d946c21e2fc3f1e9ca6986a8191d85fcc70097a8bb7771a053564bc47009cdf"
    );
    assert_eq!(
        hex(Trigger::event_type_hash()),
        "ec4a1d26b0575e61906890342aba9523a2360e9845857c5590fa6e23bc39e1c2"
    );
    assert_same_service::<Trigger, real::Trigger>();

    // The empty request is rosidl's single placeholder byte on the wire.
    let bytes = round_trip(&TriggerRequest {});
    assert_eq!(bytes, [0, 1, 0, 0, 0]);
    assert_eq!(
        bytes,
        to_cdr(&real::TriggerRequest::default()).expect("encode")
    );
    assert_eq!(
        from_cdr::<real::TriggerRequest>(&bytes).expect("decode"),
        real::TriggerRequest::default()
    );
    // A peer's byte (whatever its value) decodes.
    assert_eq!(
        from_cdr::<TriggerRequest>(&[0, 1, 0, 0, 7]).expect("decode"),
        TriggerRequest::default()
    );
    // Nothing after the header is an error, as for the msgs type.
    assert!(from_cdr::<TriggerRequest>(&[0, 1, 0, 0]).is_err());
    assert!(from_cdr::<real::TriggerRequest>(&[0, 1, 0, 0]).is_err());

    let resp = TriggerResponse {
        success: true,
        message: "ok".into(),
    };
    let bytes = round_trip(&resp);
    let theirs = real::TriggerResponse {
        success: true,
        message: "ok".into(),
    };
    assert_eq!(bytes, to_cdr(&theirs).expect("encode"));
}

#[test]
fn empty_service_matches_std_srvs() {
    use horus_ros_msgs::std_srvs::srv as real;
    use std_srvs_mine::{Empty, EmptyRequest, EmptyResponse};

    assert_eq!(
        hex(Empty::type_hash()),
        "5888399dedec5ccc85ea6451949fd2c9f97bfdf963f9a588821639fcd31b5d19"
    );
    assert_eq!(
        hex(EmptyRequest::type_hash()),
        "458eaf200a3f63d9cc53d19436edebc0c140ef4c93ca75d5bd4ce19fd7759e35"
    );
    assert_eq!(
        hex(EmptyResponse::type_hash()),
        "0a2858b3f60df644a61d0fa44cfc923a3d3628e0ad9c8ad8534b1a2c92a413dc"
    );
    assert_eq!(
        hex(Empty::event_type_hash()),
        "66fa7fcfb5f2bf04b9a8a55603318c5c402edfc4bd56bb0ed7b602990c29305a"
    );
    assert_same_service::<Empty, real::Empty>();
    assert_eq!(
        round_trip(&EmptyResponse {}),
        to_cdr(&real::EmptyResponse::default()).expect("encode")
    );
}

// ---- nested messages: rcl_interfaces --------------------------------------------------------

mod rcl_mine {
    use horus_ros_msgs::rcl_interfaces::msg::{
        ListParametersResult, Parameter, SetParametersResult,
    };

    horus_ros_services::service! {
        rcl_interfaces/ListParameters {
            request {
                prefixes: Vec<String>,
                depth: u64,
            }
            response {
                result: ListParametersResult,
            }
        }

        rcl_interfaces/SetParameters {
            request { parameters: Vec<Parameter> }
            response { results: Vec<SetParametersResult> }
        }
    }
}

#[test]
fn nested_messages_hash_like_rosidl() {
    use horus_ros_msgs::rcl_interfaces::srv as real;

    // msgs/tests/hashes.rs (published values).
    assert_eq!(
        hex(rcl_mine::ListParameters::type_hash()),
        "3e6062bfbb27bfb8730d4cef2558221f51a11646d78e7bb30a1e83afac3aad9d"
    );
    assert_eq!(
        hex(rcl_mine::ListParametersResponse::type_hash()),
        "31b937b82de3612426be79f231e386259f97e8dc843e3f2845288b4bfa296bdd"
    );
    assert_eq!(
        hex(rcl_mine::SetParameters::type_hash()),
        "56eed9a67e169f9cb6c1f987bc88f868c14a8fc9f743a263bc734c154015d7e0"
    );
    assert_same_service::<rcl_mine::ListParameters, real::ListParameters>();
    assert_same_service::<rcl_mine::SetParameters, real::SetParameters>();

    let req = rcl_mine::ListParametersRequest {
        prefixes: vec!["a".into(), "bc".into()],
        depth: 3,
    };
    let theirs = real::ListParametersRequest {
        prefixes: vec!["a".into(), "bc".into()],
        depth: 3,
    };
    assert_eq!(round_trip(&req), to_cdr(&theirs).expect("encode"));
}

// ---- attributes, doc comments, every field kind ------------------------------------------------

mod everything {
    use horus_ros_msgs::builtin_interfaces::msg::Time;
    use horus_ros_msgs::Byte;

    horus_ros_services::service! {
        /// Every kind of field.
        ///
        /// Doc comments and attributes pass through.
        #[allow(clippy::doc_markdown)]
        my_robot_msgs/AllKinds {
            /// The request, with extra derives.
            #[derive(Eq, Hash)]
            request {
                /// A flag.
                flag: bool,
                #[doc = "A signed byte."]
                i_8: i8,
                u_8: u8,
                i_16: i16,
                u_16: u16,
                i_32: i32,
                u_32: u32,
                i_64: i64,
                u_64: u64,
                raw: Byte,
                text: String,
                bytes: Vec<u8>,
                names: Vec<String>,
                fixed: [u16; 3],
                fixed_names: [String; 2],
                stamp: Time,
                stamps: Vec<Time>,
                stamp_pair: [Time; 2],
                /// `string<=8`.
                short_text: String => |t| t.bounded_string(8),
                /// `int32[<=4]`.
                few: Vec<i32> => |t| t.bounded_sequence(4),
                /// A raw identifier: the ROS field is `type`.
                r#type: u8,
            }
            /// The response.
            response {
                real: f32,
                double: f64,
                reals: Vec<f32>,
                doubles: [f64; 2],
                byte_seq: Vec<Byte>,
            }
        }
    }
}

#[test]
fn every_field_kind() {
    use everything::{AllKinds, AllKindsRequest, AllKindsResponse};

    assert_eq!(AllKinds::TYPE_NAME, "my_robot_msgs/srv/AllKinds");
    let req = AllKindsRequest {
        flag: true,
        i_8: -1,
        u_8: 2,
        i_16: -3,
        u_16: 4,
        i_32: -5,
        u_32: 6,
        i_64: -7,
        u_64: 8,
        raw: Byte(9),
        text: "héllo".into(),
        bytes: vec![1, 2, 3],
        names: vec!["x".into(), String::new()],
        fixed: [1, 2, 3],
        fixed_names: ["a".into(), "b".into()],
        stamp: Time { sec: 1, nanosec: 2 },
        stamps: vec![Time { sec: 3, nanosec: 4 }],
        stamp_pair: [Time { sec: 5, nanosec: 6 }, Time::default()],
        short_text: "short".into(),
        few: vec![-1, 1],
        r#type: 7,
    };
    round_trip(&req);
    // `#[derive(Eq, Hash)]` on `request` reached the struct.
    let set: std::collections::HashSet<AllKindsRequest> = [req.clone(), req].into_iter().collect();
    assert_eq!(set.len(), 1);
    round_trip(&AllKindsResponse {
        real: 1.5,
        double: -2.25,
        reals: vec![0.5; 3],
        doubles: [1.0, 2.0],
        byte_seq: vec![Byte(0xff)],
    });

    let d = AllKindsRequest::type_description();
    let fields: Vec<(&str, u8, u64, u64, &str)> = d
        .type_description
        .fields
        .iter()
        .map(|f| {
            let t = &f.r#type;
            (
                f.name.as_str(),
                t.type_id,
                t.capacity,
                t.string_capacity,
                t.nested_type_name.as_str(),
            )
        })
        .collect();
    let time = "builtin_interfaces/msg/Time";
    type F = FieldType;
    assert_eq!(
        fields,
        [
            ("flag", F::FIELD_TYPE_BOOLEAN, 0, 0, ""),
            ("i_8", F::FIELD_TYPE_INT8, 0, 0, ""),
            ("u_8", F::FIELD_TYPE_UINT8, 0, 0, ""),
            ("i_16", F::FIELD_TYPE_INT16, 0, 0, ""),
            ("u_16", F::FIELD_TYPE_UINT16, 0, 0, ""),
            ("i_32", F::FIELD_TYPE_INT32, 0, 0, ""),
            ("u_32", F::FIELD_TYPE_UINT32, 0, 0, ""),
            ("i_64", F::FIELD_TYPE_INT64, 0, 0, ""),
            ("u_64", F::FIELD_TYPE_UINT64, 0, 0, ""),
            ("raw", F::FIELD_TYPE_BYTE, 0, 0, ""),
            ("text", F::FIELD_TYPE_STRING, 0, 0, ""),
            ("bytes", F::FIELD_TYPE_UINT8_UNBOUNDED_SEQUENCE, 0, 0, ""),
            ("names", F::FIELD_TYPE_STRING_UNBOUNDED_SEQUENCE, 0, 0, ""),
            ("fixed", F::FIELD_TYPE_UINT16_ARRAY, 3, 0, ""),
            ("fixed_names", F::FIELD_TYPE_STRING_ARRAY, 2, 0, ""),
            ("stamp", F::FIELD_TYPE_NESTED_TYPE, 0, 0, time),
            (
                "stamps",
                F::FIELD_TYPE_NESTED_TYPE_UNBOUNDED_SEQUENCE,
                0,
                0,
                time
            ),
            ("stamp_pair", F::FIELD_TYPE_NESTED_TYPE_ARRAY, 2, 0, time),
            ("short_text", F::FIELD_TYPE_BOUNDED_STRING, 0, 8, ""),
            ("few", F::FIELD_TYPE_INT32_BOUNDED_SEQUENCE, 4, 0, ""),
            ("type", F::FIELD_TYPE_UINT8, 0, 0, ""),
        ]
    );
    // The nested type is referenced once.
    let referenced: Vec<&str> = d
        .referenced_type_descriptions
        .iter()
        .map(|t| t.type_name.as_str())
        .collect();
    assert_eq!(referenced, [time]);
    assert_eq!(
        d.referenced_type_descriptions[0],
        Time::type_description().type_description
    );

    let resp: Vec<u8> = AllKindsResponse::type_description()
        .type_description
        .fields
        .iter()
        .map(|f| f.r#type.type_id)
        .collect();
    assert_eq!(
        resp,
        [
            F::FIELD_TYPE_FLOAT,
            F::FIELD_TYPE_DOUBLE,
            F::FIELD_TYPE_FLOAT_UNBOUNDED_SEQUENCE,
            F::FIELD_TYPE_DOUBLE_ARRAY,
            F::FIELD_TYPE_BYTE_UNBOUNDED_SEQUENCE,
        ]
    );
    // The service description references request, response, event and what they use.
    let all: Vec<String> = AllKinds::type_description()
        .referenced_type_descriptions
        .into_iter()
        .map(|t| t.type_name)
        .collect();
    assert_eq!(
        all,
        [
            time,
            "my_robot_msgs/srv/AllKinds_Event",
            "my_robot_msgs/srv/AllKinds_Request",
            "my_robot_msgs/srv/AllKinds_Response",
            "service_msgs/msg/ServiceEventInfo",
        ]
    );
}

#[test]
fn serde_names_and_json() {
    // CDR does not carry field names; self-describing formats do: they are the ROS names.
    horus_ros_services::service! {
        RawNames {
            request { r#type: u8, name: String }
            response {}
        }
    }
    let req = RawNamesRequest {
        r#type: 3,
        name: "n".into(),
    };
    let json = serde_json::to_string(&req).expect("json");
    assert_eq!(json, r#"{"type":3,"name":"n"}"#);
    assert_eq!(
        serde_json::from_str::<RawNamesRequest>(&json).expect("json"),
        req
    );
    // From a sequence too (what CDR-like formats use).
    assert_eq!(
        serde_json::from_str::<RawNamesRequest>(r#"[3, "n"]"#).expect("json"),
        req
    );
    let json = serde_json::to_string(&RawNamesResponse {}).expect("json");
    assert_eq!(json, r#"{"structure_needs_at_least_one_member":0}"#);
    assert_eq!(
        serde_json::from_str::<RawNamesResponse>(&json).expect("json"),
        RawNamesResponse {}
    );
    // Same JSON as the msgs crate's types.
    assert_eq!(
        serde_json::to_value(add_two_ints::AddTwoIntsRequest { a: 1, b: 2 }).expect("json"),
        serde_json::to_value(horus_ros_msgs::example_interfaces::srv::AddTwoIntsRequest {
            a: 1,
            b: 2
        })
        .expect("json")
    );
    assert_eq!(
        serde_json::to_value(std_srvs_mine::EmptyRequest {}).expect("json"),
        serde_json::to_value(horus_ros_msgs::std_srvs::srv::EmptyRequest::default()).expect("json")
    );
}

#[test]
fn defined_inside_a_function() {
    horus_ros_services::service! {
        /// Local.
        Local {
            request { x: u8 }
            response { y: u8 }
        }
    }
    assert_eq!(Local::TYPE_NAME, "horus_ros/srv/Local");
    assert_eq!(round_trip(&LocalRequest { x: 7 }), [0, 1, 0, 0, 7]);
    let _ = LocalResponse { y: 1 };
}

#[test]
fn name_checks() {
    use horus_ros_services::__private::names::{
        is_valid_field_name, is_valid_package_name, is_valid_type_name, DEFAULT_PACKAGE,
    };
    assert_eq!(DEFAULT_PACKAGE, "horus_ros");
    for ok in [
        "a",
        "example_interfaces",
        "std_srvs",
        "p2",
        "a_b_c",
        "r#type",
    ] {
        assert!(is_valid_package_name(ok), "{ok}");
        assert!(is_valid_field_name(ok), "{ok}");
    }
    for bad in ["", "A", "_a", "a_", "a__b", "2a", "aB", "a-b", "r#", "é"] {
        assert!(!is_valid_package_name(bad), "{bad}");
    }
    for ok in ["AddTwoInts", "A", "GetMap2D", "r#Foo"] {
        assert!(is_valid_type_name(ok), "{ok}");
    }
    for bad in ["", "addTwoInts", "Add_Two", "_A", "2A", "Ä"] {
        assert!(!is_valid_type_name(bad), "{bad}");
    }
}
