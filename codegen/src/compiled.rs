//! The message types compiled into horus-ros-msgs, by ROS type name: generated code uses them
//! rather than generating them again (so a generated message's `std_msgs/Header` is the
//! `Header` the rest of horus-ros publishes).

use horus_ros_msgs::Message;

use crate::definition::NamedType;

macro_rules! compiled {
    ($($first:ident $(:: $rest:ident)*),* $(,)?) => {
        /// `(ROS type name, Rust path)` of each compiled message type.
        pub fn types() -> Vec<(&'static str, String)> {
            vec![$((
                <horus_ros_msgs::$first $(:: $rest)* as Message>::TYPE_NAME,
                format!("::horus_ros_msgs::{}", stringify!($first $(:: $rest)*).replace(' ', "")),
            )),*]
        }
    };
}

compiled! {
    builtin_interfaces::msg::Time,
    builtin_interfaces::msg::Duration,
    geometry_msgs::msg::Vector3,
    geometry_msgs::msg::Point,
    geometry_msgs::msg::Quaternion,
    geometry_msgs::msg::Pose,
    geometry_msgs::msg::PoseStamped,
    geometry_msgs::msg::Twist,
    geometry_msgs::msg::TwistStamped,
    rcl_interfaces::msg::ParameterType,
    rcl_interfaces::msg::ParameterValue,
    rcl_interfaces::msg::Parameter,
    rcl_interfaces::msg::FloatingPointRange,
    rcl_interfaces::msg::IntegerRange,
    rcl_interfaces::msg::ParameterDescriptor,
    rcl_interfaces::msg::SetParametersResult,
    rcl_interfaces::msg::ListParametersResult,
    rcl_interfaces::msg::Log,
    rcl_interfaces::msg::ParameterEvent,
    sensor_msgs::msg::LaserScan,
    sensor_msgs::msg::Imu,
    sensor_msgs::msg::JointState,
    service_msgs::msg::ServiceEventInfo,
    std_msgs::msg::String,
    std_msgs::msg::Header,
    std_msgs::msg::Empty,
    std_msgs::msg::Bool,
    std_msgs::msg::Byte,
    std_msgs::msg::Char,
    std_msgs::msg::Int8,
    std_msgs::msg::Int16,
    std_msgs::msg::Int32,
    std_msgs::msg::Int64,
    std_msgs::msg::UInt8,
    std_msgs::msg::UInt16,
    std_msgs::msg::UInt32,
    std_msgs::msg::UInt64,
    std_msgs::msg::Float32,
    std_msgs::msg::Float64,
    type_description_interfaces::msg::FieldType,
    type_description_interfaces::msg::Field,
    type_description_interfaces::msg::IndividualTypeDescription,
    type_description_interfaces::msg::TypeDescription,
    type_description_interfaces::msg::KeyValue,
    type_description_interfaces::msg::TypeSource,
}

/// The Rust path of the compiled type `t`, if horus-ros-msgs has it.
pub fn path(t: &NamedType) -> Option<String> {
    let name = t.to_string();
    types()
        .into_iter()
        .find(|(n, _)| *n == name)
        .map(|(_, p)| p)
}
