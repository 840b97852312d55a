//! Every message type horus-ros defines has the RIHS01 hash that an independent implementation
//! computes: rosbags (`peers/rosbags_rihs.py`), from its own ROS 2 Jazzy message definitions and
//! its own REP-2011 hashing. (msgs/tests/hashes.rs checks them against hashes published by ROS 2
//! builds; services are not in rosbags' store and are checked there only.)

use std::collections::BTreeMap;
use std::io::Write;
use std::process::{Command, Stdio};

use horus_ros_msgs::{
    builtin_interfaces, geometry_msgs, rcl_interfaces, rmw_dds_common, sensor_msgs, service_msgs,
    std_msgs, type_description_interfaces, Message,
};

/// `(type name, our RIHS01 string)` of each listed type.
macro_rules! ours {
    ($($t:ty),* $(,)?) => {
        vec![$((<$t as Message>::TYPE_NAME, <$t as Message>::type_hash().to_string())),*]
    };
}

#[test]
fn every_message_type_hashes_as_rosbags_jazzy_store() {
    let ours: Vec<(&str, String)> = ours![
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
        rmw_dds_common::Gid,
        rmw_dds_common::NodeEntitiesInfo,
        rmw_dds_common::ParticipantEntitiesInfo,
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
    ];

    let mut child = Command::new(interop_tests::python())
        .arg(interop_tests::peer_script("rosbags_rihs.py"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run the rosbags script");
    {
        let mut stdin = child.stdin.take().expect("stdin");
        for (name, _) in &ours {
            writeln!(stdin, "{name}").expect("write a type name");
        }
    }
    let out = child.wait_with_output().expect("rosbags script output");
    assert!(
        out.status.success(),
        "{}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs: BTreeMap<String, String> = String::from_utf8(out.stdout)
        .expect("UTF-8")
        .lines()
        .filter_map(|l| l.split_once(' '))
        .map(|(name, hash)| (name.to_owned(), hash.to_owned()))
        .collect();
    let differing: Vec<String> = ours
        .iter()
        .filter(|(name, hash)| theirs.get(*name) != Some(hash))
        .map(|(name, hash)| format!("{name}: ours {hash}, rosbags {:?}", theirs.get(*name)))
        .collect();
    assert!(differing.is_empty(), "{differing:#?}");
    assert_eq!(theirs.len(), ours.len(), "{theirs:#?}");
}
