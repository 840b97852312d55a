//! How HORUS names become ROS 2 names.
//!
//! - **Topics**: HORUS writes hierarchy with dots (`motor.cmd`); ROS with slashes. A HORUS
//!   topic name maps to the ROS name with every `.` replaced by `/` (`motor.cmd` →
//!   `motor/cmd`, relative, so it lands under the node's namespace: `/motor/cmd`, or
//!   `/robot1/motor/cmd` with `-r __ns:=/robot1`). A name that is a ROS name already maps to
//!   itself. The result must pass rcl's topic name validation (`rcl_validate_topic_name`), else
//!   [`Topic::new`](crate::Topic::new) fails with [`TopicError::Unmappable`](crate::TopicError)
//!   naming the rule broken.
//! - **Nodes**: a HORUS node name maps to the ROS node name with `.`, `-` and spaces replaced
//!   by `_`; what is left must be a valid ROS node name (letters, digits, `_`, not starting with
//!   a digit), else [`build`](crate::NodeBuilder::build) fails.

use horus_ros_rmw::names::{
    validate_unexpanded_name, ExpandError, Namespace, NodeName, NodeNameError, TopicName,
    UnexpandedNameError,
};

/// The ROS rule a mapped topic name breaks.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TopicNameError {
    /// Not a valid topic name as written (rcl `rcl_validate_topic_name`).
    #[error(transparent)]
    Invalid(#[from] UnexpandedNameError),
    /// Valid as written, but not once expanded (e.g. `//`).
    #[error(transparent)]
    Expanded(#[from] ExpandError),
}

/// The ROS topic name of a HORUS topic name (see the module documentation).
pub fn ros_topic_name(horus_name: &str) -> Result<String, TopicNameError> {
    let mapped = horus_name.replace('.', "/");
    validate_unexpanded_name(&mapped)?;
    // The expanded form must be a valid full name too (no `//`): checked under a placeholder
    // node; the real node and namespace are applied when the topic is used.
    if let Ok(node) = NodeName::new("n") {
        TopicName::expand(&mapped, &node, &Namespace::root())?;
    }
    Ok(mapped)
}

/// The ROS node name of a HORUS node name (see the module documentation).
pub fn ros_node_name(horus_name: &str) -> Result<String, NodeNameError> {
    let mapped: String = horus_name
        .chars()
        .map(|c| if matches!(c, '.' | '-' | ' ') { '_' } else { c })
        .collect();
    NodeName::new(&mapped)?;
    Ok(mapped)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topic_names() {
        assert_eq!(ros_topic_name("motor.cmd").as_deref(), Ok("motor/cmd"));
        assert_eq!(ros_topic_name("cmd_vel").as_deref(), Ok("cmd_vel"));
        assert_eq!(ros_topic_name("/robot.scan").as_deref(), Ok("/robot/scan"));
        assert_eq!(ros_topic_name("~/status").as_deref(), Ok("~/status"));
        assert!(ros_topic_name("motor-cmd").is_err());
        assert!(ros_topic_name("1scan").is_err());
        assert!(ros_topic_name("a..b").is_err(), "empty segment");
        assert!(ros_topic_name("").is_err());
        assert!(ros_topic_name("scan.").is_err());
    }

    #[test]
    fn node_names() {
        assert_eq!(
            ros_node_name("motor_controller").as_deref(),
            Ok("motor_controller")
        );
        assert_eq!(ros_node_name("ImuReader").as_deref(), Ok("ImuReader"));
        assert_eq!(ros_node_name("arm.left").as_deref(), Ok("arm_left"));
        assert_eq!(ros_node_name("lidar-front").as_deref(), Ok("lidar_front"));
        assert!(ros_node_name("2lidar").is_err());
        assert!(ros_node_name("Wrap<Inner>").is_err());
        assert!(ros_node_name("").is_err());
    }
}
