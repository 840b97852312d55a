//! Type descriptions and DDS names.

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest};
use horus_ros_msgs::rcl_interfaces::msg::{ParameterDescriptor, ParameterValue};
use horus_ros_msgs::rihs::hashable_json;
use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use horus_ros_msgs::type_description_interfaces::msg::FieldType;
use horus_ros_msgs::{dds_type_name, ros_type_name_from_dds, DescriptionBuilder, Message, Service};

fn names(d: &horus_ros_msgs::TypeDescription) -> Vec<&str> {
    d.referenced_type_descriptions
        .iter()
        .map(|t| t.type_name.as_str())
        .collect()
}

#[test]
fn dds_names() {
    assert_eq!(
        Time::dds_type_name(),
        "builtin_interfaces::msg::dds_::Time_"
    );
    assert_eq!(
        AddTwoInts::request_dds_type_name(),
        "example_interfaces::srv::dds_::AddTwoInts_Request_"
    );
    assert_eq!(
        AddTwoInts::response_dds_type_name(),
        "example_interfaces::srv::dds_::AddTwoInts_Response_"
    );
    assert_eq!(
        ParticipantEntitiesInfo::dds_type_name(),
        "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"
    );
    assert_eq!(
        ros_type_name_from_dds("example_interfaces::srv::dds_::AddTwoInts_Request_").as_deref(),
        Some("example_interfaces/srv/AddTwoInts_Request")
    );
    assert_eq!(ros_type_name_from_dds("Foo"), None);
    assert_eq!(dds_type_name("a/msg/B"), "a::msg::dds_::B_");
}

#[test]
fn hashable_json_matches_python_format() {
    let json = hashable_json(&Time::type_description());
    assert_eq!(
        json,
        "{\"type_description\": {\"type_name\": \"builtin_interfaces/msg/Time\", \"fields\": [\
         {\"name\": \"sec\", \"type\": {\"type_id\": 6, \"capacity\": 0, \"string_capacity\": 0, \
         \"nested_type_name\": \"\"}}, {\"name\": \"nanosec\", \"type\": {\"type_id\": 7, \
         \"capacity\": 0, \"string_capacity\": 0, \"nested_type_name\": \"\"}}]}, \
         \"referenced_type_descriptions\": []}"
    );
}

#[test]
fn hashable_json_is_ascii_like_python() {
    // Python: json.dumps("é😀\x7f\n", ensure_ascii=True) == '"\\u00e9\\ud83d\\ude00\\u007f\\n"'
    let d = DescriptionBuilder::new("p/msg/X")
        .field::<u8>("é😀\u{7f}\n")
        .build();
    let json = hashable_json(&d);
    assert!(
        json.contains(r#""name": "\u00e9\ud83d\ude00\u007f\n""#),
        "{json}"
    );
}

#[test]
fn empty_struct_gets_placeholder() {
    let d = DescriptionBuilder::new("p/msg/Empty").build();
    assert_eq!(d.type_description.fields.len(), 1);
    let f = &d.type_description.fields[0];
    assert_eq!(f.name, "structure_needs_at_least_one_member");
    assert_eq!(f.r#type.type_id, FieldType::FIELD_TYPE_UINT8);
}

#[test]
fn service_description_layout() {
    let d = AddTwoInts::type_description();
    let fields: Vec<_> = d
        .type_description
        .fields
        .iter()
        .map(|f| {
            (
                f.name.as_str(),
                f.r#type.type_id,
                f.r#type.nested_type_name.as_str(),
            )
        })
        .collect();
    assert_eq!(
        fields,
        [
            (
                "request_message",
                1,
                "example_interfaces/srv/AddTwoInts_Request"
            ),
            (
                "response_message",
                1,
                "example_interfaces/srv/AddTwoInts_Response"
            ),
            (
                "event_message",
                1,
                "example_interfaces/srv/AddTwoInts_Event"
            ),
        ]
    );
    assert_eq!(
        names(&d),
        [
            "builtin_interfaces/msg/Time",
            "example_interfaces/srv/AddTwoInts_Event",
            "example_interfaces/srv/AddTwoInts_Request",
            "example_interfaces/srv/AddTwoInts_Response",
            "service_msgs/msg/ServiceEventInfo",
        ]
    );
    let ev = AddTwoInts::event_type_description();
    let req = &ev.type_description.fields[1];
    assert_eq!(
        req.r#type.type_id,
        FieldType::FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE
    );
    assert_eq!(req.r#type.capacity, 1);
    assert_eq!(
        AddTwoIntsRequest::TYPE_NAME,
        "example_interfaces/srv/AddTwoInts_Request"
    );
}

#[test]
fn field_type_mapping() {
    let d = ParameterValue::type_description();
    let f = |n: &str| {
        d.type_description
            .fields
            .iter()
            .find(|f| f.name == n)
            .map(|f| f.r#type.clone())
            .expect("field")
    };
    assert_eq!(f("type").type_id, FieldType::FIELD_TYPE_UINT8);
    assert_eq!(
        f("byte_array_value").type_id,
        FieldType::FIELD_TYPE_BYTE_UNBOUNDED_SEQUENCE
    );
    assert_eq!(
        f("string_array_value").type_id,
        FieldType::FIELD_TYPE_STRING_UNBOUNDED_SEQUENCE
    );
    let d = ParameterDescriptor::type_description();
    let fpr = &d.type_description.fields[6];
    assert_eq!(fpr.name, "floating_point_range");
    assert_eq!(
        fpr.r#type.type_id,
        FieldType::FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE
    );
    assert_eq!(fpr.r#type.capacity, 1);
    assert_eq!(d.type_description.fields[4].default_value, "False");
    assert_eq!(
        names(&d),
        [
            "rcl_interfaces/msg/FloatingPointRange",
            "rcl_interfaces/msg/IntegerRange"
        ]
    );
    let s = <String as horus_ros_msgs::RosField>::field_type().bounded_string(256);
    assert_eq!(s.type_id, FieldType::FIELD_TYPE_BOUNDED_STRING);
    assert_eq!(s.string_capacity, 256);
    let arr = <[String; 3] as horus_ros_msgs::RosField>::field_type().bounded_string(5);
    assert_eq!(arr.type_id, FieldType::FIELD_TYPE_BOUNDED_STRING_ARRAY);
    assert_eq!((arr.capacity, arr.string_capacity), (3, 5));
}
