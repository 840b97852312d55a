//! The types compiled into horus-ros-msgs, by ROS name, with their descriptions: what the CLI
//! knows without an install (`interface list`, `service call` of a compiled service type).

use horus_ros_msgs::{
    builtin_interfaces, example_interfaces, geometry_msgs, rcl_interfaces, rmw_dds_common,
    sensor_msgs, service_msgs, std_msgs, std_srvs, type_description_interfaces,
};
use horus_ros_msgs::{Message, Service, TypeDescription};

/// A type compiled into horus-ros-msgs.
#[derive(Clone, Copy, Debug)]
pub struct CompiledType {
    /// `pkg/msg/Name` or `pkg/srv/Name`.
    pub name: &'static str,
    /// Its description (with every type it references).
    pub describe: fn() -> TypeDescription,
}

impl CompiledType {
    /// Whether this is a service (`pkg/srv/Name`).
    pub fn is_service(&self) -> bool {
        self.name.split('/').nth(1) == Some("srv")
    }
}

const fn m<M: Message>() -> CompiledType {
    CompiledType {
        name: M::TYPE_NAME,
        describe: M::type_description,
    }
}

const fn s<S: Service>() -> CompiledType {
    CompiledType {
        name: S::TYPE_NAME,
        describe: S::type_description,
    }
}

/// Every compiled message and service type, messages first.
pub const COMPILED_TYPES: &[CompiledType] = &[
    m::<builtin_interfaces::msg::Time>(),
    m::<builtin_interfaces::msg::Duration>(),
    m::<geometry_msgs::msg::Vector3>(),
    m::<geometry_msgs::msg::Point>(),
    m::<geometry_msgs::msg::Quaternion>(),
    m::<geometry_msgs::msg::Pose>(),
    m::<geometry_msgs::msg::PoseStamped>(),
    m::<geometry_msgs::msg::Twist>(),
    m::<geometry_msgs::msg::TwistStamped>(),
    m::<rcl_interfaces::msg::ParameterType>(),
    m::<rcl_interfaces::msg::ParameterValue>(),
    m::<rcl_interfaces::msg::Parameter>(),
    m::<rcl_interfaces::msg::FloatingPointRange>(),
    m::<rcl_interfaces::msg::IntegerRange>(),
    m::<rcl_interfaces::msg::ParameterDescriptor>(),
    m::<rcl_interfaces::msg::SetParametersResult>(),
    m::<rcl_interfaces::msg::ListParametersResult>(),
    m::<rcl_interfaces::msg::Log>(),
    m::<rcl_interfaces::msg::ParameterEvent>(),
    m::<rmw_dds_common::Gid>(),
    m::<rmw_dds_common::NodeEntitiesInfo>(),
    m::<rmw_dds_common::ParticipantEntitiesInfo>(),
    m::<sensor_msgs::msg::LaserScan>(),
    m::<sensor_msgs::msg::Imu>(),
    m::<sensor_msgs::msg::JointState>(),
    m::<service_msgs::msg::ServiceEventInfo>(),
    m::<std_msgs::msg::String>(),
    m::<std_msgs::msg::Header>(),
    m::<std_msgs::msg::Empty>(),
    m::<std_msgs::msg::Bool>(),
    m::<std_msgs::msg::Byte>(),
    m::<std_msgs::msg::Char>(),
    m::<std_msgs::msg::Int8>(),
    m::<std_msgs::msg::Int16>(),
    m::<std_msgs::msg::Int32>(),
    m::<std_msgs::msg::Int64>(),
    m::<std_msgs::msg::UInt8>(),
    m::<std_msgs::msg::UInt16>(),
    m::<std_msgs::msg::UInt32>(),
    m::<std_msgs::msg::UInt64>(),
    m::<std_msgs::msg::Float32>(),
    m::<std_msgs::msg::Float64>(),
    m::<type_description_interfaces::msg::FieldType>(),
    m::<type_description_interfaces::msg::Field>(),
    m::<type_description_interfaces::msg::IndividualTypeDescription>(),
    m::<type_description_interfaces::msg::TypeDescription>(),
    m::<type_description_interfaces::msg::KeyValue>(),
    m::<type_description_interfaces::msg::TypeSource>(),
    s::<example_interfaces::srv::AddTwoInts>(),
    s::<std_srvs::srv::Empty>(),
    s::<std_srvs::srv::Trigger>(),
    s::<std_srvs::srv::SetBool>(),
    s::<rcl_interfaces::srv::ListParameters>(),
    s::<rcl_interfaces::srv::GetParameters>(),
    s::<rcl_interfaces::srv::GetParameterTypes>(),
    s::<rcl_interfaces::srv::SetParameters>(),
    s::<rcl_interfaces::srv::SetParametersAtomically>(),
    s::<rcl_interfaces::srv::DescribeParameters>(),
    s::<type_description_interfaces::srv::GetTypeDescription>(),
];

/// The compiled type named `type_name` (`pkg/msg/Name` or `pkg/srv/Name`).
pub fn compiled_type(type_name: &str) -> Option<&'static CompiledType> {
    COMPILED_TYPES.iter().find(|t| t.name == type_name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_compiled_type_is_listed_once_and_describes_itself() {
        let mut names: Vec<&str> = COMPILED_TYPES.iter().map(|t| t.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), COMPILED_TYPES.len());
        for t in COMPILED_TYPES {
            assert_eq!((t.describe)().type_description.type_name, t.name);
        }
        assert!(compiled_type("std_srvs/srv/SetBool").is_some_and(CompiledType::is_service));
        assert!(compiled_type("std_msgs/msg/String").is_some_and(|t| !t.is_service()));
    }
}
