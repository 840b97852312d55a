//! Helpers for tests against independent DDS implementations.
//!
//! The peers are Python programs (`peers/`): small DDS participants on the Eclipse Cyclone DDS
//! Python binding, and real ROS 2 Jazzy nodes on rclpy ([`rclpy`]), run with the interpreter
//! named by `HORUS_ROS_INTEROP_PYTHON` (set by `scripts/test` to the private virtual environment
//! that `scripts/setup` creates), else `python3`.

pub mod rclpy;

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// The Python interpreter that has the `cyclonedds` package and the ROS 2 wheels.
pub fn python() -> PathBuf {
    horus_ros_test_support::jazzy::python()
}

pub use horus_ros_test_support::line_reader;

/// Calls the macro `$then` with every message type compiled into horus-ros-msgs, as paths (the
/// list the hash tests check: `rclpy_hashes.rs` against the Jazzy wheels, `rihs_rosbags.rs`
/// against rosbags).
#[macro_export]
macro_rules! compiled_message_types {
    ($then:ident) => {
        $then![
            horus_ros_msgs::builtin_interfaces::msg::Time,
            horus_ros_msgs::builtin_interfaces::msg::Duration,
            horus_ros_msgs::geometry_msgs::msg::Vector3,
            horus_ros_msgs::geometry_msgs::msg::Point,
            horus_ros_msgs::geometry_msgs::msg::Quaternion,
            horus_ros_msgs::geometry_msgs::msg::Pose,
            horus_ros_msgs::geometry_msgs::msg::PoseStamped,
            horus_ros_msgs::geometry_msgs::msg::Twist,
            horus_ros_msgs::geometry_msgs::msg::TwistStamped,
            horus_ros_msgs::rcl_interfaces::msg::ParameterType,
            horus_ros_msgs::rcl_interfaces::msg::ParameterValue,
            horus_ros_msgs::rcl_interfaces::msg::Parameter,
            horus_ros_msgs::rcl_interfaces::msg::FloatingPointRange,
            horus_ros_msgs::rcl_interfaces::msg::IntegerRange,
            horus_ros_msgs::rcl_interfaces::msg::ParameterDescriptor,
            horus_ros_msgs::rcl_interfaces::msg::SetParametersResult,
            horus_ros_msgs::rcl_interfaces::msg::ListParametersResult,
            horus_ros_msgs::rcl_interfaces::msg::Log,
            horus_ros_msgs::rcl_interfaces::msg::ParameterEvent,
            horus_ros_msgs::rmw_dds_common::Gid,
            horus_ros_msgs::rmw_dds_common::NodeEntitiesInfo,
            horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo,
            horus_ros_msgs::sensor_msgs::msg::LaserScan,
            horus_ros_msgs::sensor_msgs::msg::Imu,
            horus_ros_msgs::sensor_msgs::msg::JointState,
            horus_ros_msgs::service_msgs::msg::ServiceEventInfo,
            horus_ros_msgs::std_msgs::msg::String,
            horus_ros_msgs::std_msgs::msg::Header,
            horus_ros_msgs::std_msgs::msg::Empty,
            horus_ros_msgs::std_msgs::msg::Bool,
            horus_ros_msgs::std_msgs::msg::Byte,
            horus_ros_msgs::std_msgs::msg::Char,
            horus_ros_msgs::std_msgs::msg::Int8,
            horus_ros_msgs::std_msgs::msg::Int16,
            horus_ros_msgs::std_msgs::msg::Int32,
            horus_ros_msgs::std_msgs::msg::Int64,
            horus_ros_msgs::std_msgs::msg::UInt8,
            horus_ros_msgs::std_msgs::msg::UInt16,
            horus_ros_msgs::std_msgs::msg::UInt32,
            horus_ros_msgs::std_msgs::msg::UInt64,
            horus_ros_msgs::std_msgs::msg::Float32,
            horus_ros_msgs::std_msgs::msg::Float64,
            horus_ros_msgs::type_description_interfaces::msg::FieldType,
            horus_ros_msgs::type_description_interfaces::msg::Field,
            horus_ros_msgs::type_description_interfaces::msg::IndividualTypeDescription,
            horus_ros_msgs::type_description_interfaces::msg::TypeDescription,
            horus_ros_msgs::type_description_interfaces::msg::KeyValue,
            horus_ros_msgs::type_description_interfaces::msg::TypeSource,
        ]
    };
}

/// The path of a peer script in `interop-tests/peers/`.
pub fn peer_script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("peers")
        .join(name)
}

/// What a finished peer printed.
#[derive(Debug)]
pub struct PeerOutput {
    /// Exit status code (`None` if killed at the deadline).
    pub code: Option<i32>,
    /// Everything it printed on stdout.
    pub stdout: String,
    /// Everything it printed on stderr.
    pub stderr: String,
}

/// A running peer process; killed when dropped.
#[derive(Debug)]
pub struct Peer {
    child: Child,
}

impl Peer {
    /// Starts `script` (in `peers/`) with `args`, capturing its output.
    pub fn start(script: &str, args: &[String]) -> std::io::Result<Self> {
        let child = Command::new(python())
            .arg(peer_script(script))
            .args(args)
            .env("CYCLONEDDS_URI", cyclone_config())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        Ok(Self { child })
    }

    /// The peer's standard output, line by line as it is printed (read by a thread of its own);
    /// `None` if already taken. [`wait`](Self::wait) then reports no standard output.
    pub fn stdout_lines(&mut self) -> Option<std::sync::mpsc::Receiver<String>> {
        Some(line_reader(self.child.stdout.take()?))
    }

    /// Waits for the peer to exit, at most `limit` (woken by its exit); kills it past that. Its
    /// output is read while it runs.
    pub fn wait(mut self, limit: Duration) -> std::io::Result<PeerOutput> {
        let out = horus_ros_test_support::wait_with_output(&mut self.child, limit)?;
        Ok(PeerOutput {
            code: out.code(),
            stdout: out.stdout,
            stderr: out.stderr,
        })
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Cyclone DDS configuration for the peers: loopback only, with multicast (the test namespace
/// routes multicast to `lo`), so they never use another interface.
pub fn cyclone_config() -> String {
    "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
     <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
     <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>"
        .to_owned()
}
