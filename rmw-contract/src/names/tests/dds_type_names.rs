use crate::names::{
    DdsTypeNameError, InterfaceKind, RosTypeName, RosTypeNameError, ServiceTypeRole,
};

// Type-name mangling of rmw_fastrtps_cpp type_support_common.hpp /
// rmw_cyclonedds_cpp *TypeSupport_impl.hpp; demangling as
// rmw_fastrtps_shared_cpp demangle.cpp (jazzy).
#[test]
fn message_type_round_trips() {
    let cases = [
        ("std_msgs/msg/String", "std_msgs::msg::dds_::String_"),
        (
            "rmw_dds_common/msg/ParticipantEntitiesInfo",
            "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_",
        ),
        (
            "example_interfaces/srv/AddTwoInts_Request",
            "example_interfaces::srv::dds_::AddTwoInts_Request_",
        ),
        (
            "action_tutorials_interfaces/action/Fibonacci_FeedbackMessage",
            "action_tutorials_interfaces::action::dds_::Fibonacci_FeedbackMessage_",
        ),
    ];
    for (ros, dds) in cases {
        let ty = RosTypeName::new(ros).expect("valid");
        assert_eq!(ty.to_dds_type_name(), dds);
        assert_eq!(RosTypeName::from_dds_type_name(dds), Ok(ty));
    }
}

#[test]
fn service_type_round_trips() {
    let ty = RosTypeName::new("example_interfaces/srv/AddTwoInts").expect("valid");
    assert_eq!(ty.package(), "example_interfaces");
    assert_eq!(ty.kind(), InterfaceKind::Srv);
    assert_eq!(ty.name(), "AddTwoInts");
    for (role, dds) in [
        (
            ServiceTypeRole::Request,
            "example_interfaces::srv::dds_::AddTwoInts_Request_",
        ),
        (
            ServiceTypeRole::Response,
            "example_interfaces::srv::dds_::AddTwoInts_Response_",
        ),
    ] {
        assert_eq!(ty.to_dds_service_type_name(role), dds);
        assert_eq!(
            RosTypeName::from_dds_service_type_name(dds),
            Ok((ty.clone(), role))
        );
    }
    let action = RosTypeName::new("pkg/action/Fibonacci_SendGoal").expect("valid");
    assert_eq!(
        action.to_dds_service_type_name(ServiceTypeRole::Request),
        "pkg::action::dds_::Fibonacci_SendGoal_Request_"
    );
}

#[test]
fn non_ros_dds_types() {
    for dds in [
        "",
        "DDS::String",
        "std_msgs::msg::String_",
        "std_msgs::msg::dds_::String",
    ] {
        assert_eq!(
            RosTypeName::from_dds_type_name(dds),
            Err(DdsTypeNameError::NotRosType(dds.to_owned())),
            "{dds:?}"
        );
    }
    assert!(matches!(
        RosTypeName::from_dds_type_name("dds_::Foo_"),
        Err(DdsTypeNameError::InvalidTypeName { .. })
    ));
    assert_eq!(
        RosTypeName::from_dds_service_type_name("std_msgs::msg::dds_::String_"),
        Err(DdsTypeNameError::NoServiceSuffix(
            "std_msgs::msg::dds_::String_".to_owned()
        ))
    );
    assert_eq!(
        RosTypeName::from_dds_service_type_name("pkg::srv::dds_::X_Request_Y"),
        Err(DdsTypeNameError::NoServiceSuffix(
            "pkg::srv::dds_::X_Request_Y".to_owned()
        ))
    );
}

// Package rule cases from ros2/rosidl (jazzy) rosidl_adapter/test/test_valid_names.py.
#[test]
fn ros_type_name_validation() {
    use RosTypeNameError as E;
    for ok in ["foo/msg/Foo", "foo_bar/srv/FooBar", "a1/action/X_Goal"] {
        assert!(RosTypeName::new(ok).is_ok(), "{ok}");
    }
    let cases = [
        ("_foo/msg/Foo", E::InvalidPackage { index: 0 }),
        ("foo_/msg/Foo", E::InvalidPackage { index: 3 }),
        ("foo__bar/msg/Foo", E::InvalidPackage { index: 3 }),
        ("foo-bar/msg/Foo", E::InvalidPackage { index: 3 }),
        ("/msg/Foo", E::InvalidPackage { index: 0 }),
        (
            "foo/idl/Foo",
            E::UnknownKind {
                kind: "idl".to_owned(),
            },
        ),
        ("foo/msg/0foo", E::InvalidName { index: 8 }),
        ("foo/msg/_Foo", E::InvalidName { index: 8 }),
        ("foo/msg/Foo_", E::InvalidName { index: 11 }),
        ("foo/msg/", E::InvalidName { index: 8 }),
        ("foo/msg", E::WrongForm),
        ("foo/msg/Foo/Bar", E::WrongForm),
    ];
    for (input, expected) in cases {
        assert_eq!(RosTypeName::new(input), Err(expected), "{input}");
    }
    assert_eq!(
        RosTypeName::from_parts("std_msgs", InterfaceKind::Msg, "String")
            .map(|t| t.to_string())
            .as_deref(),
        Ok("std_msgs/msg/String")
    );
}
