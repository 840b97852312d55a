//! `sensor_msgs` (jazzy): `LaserScan`, `Imu`, `JointState` (common_interfaces jazzy
//! `sensor_msgs/msg/*.msg`).

/// Messages.
pub mod msg {
    use crate::geometry_msgs::msg::{Quaternion, Vector3};
    use crate::std_msgs::msg::Header;

    ros_message! {
        /// `sensor_msgs/msg/LaserScan`: one scan of a planar laser range finder.
        LaserScan = "sensor_msgs/msg/LaserScan" {
            /// Acquisition time of the first ray, and frame.
            header: Header,
            /// Start angle (rad).
            angle_min: f32,
            /// End angle (rad).
            angle_max: f32,
            /// Angle between measurements (rad).
            angle_increment: f32,
            /// Time between measurements (s).
            time_increment: f32,
            /// Time between scans (s).
            scan_time: f32,
            /// Minimum range (m).
            range_min: f32,
            /// Maximum range (m).
            range_max: f32,
            /// Ranges (m).
            ranges: Vec<f32>,
            /// Intensities (device units; may be empty).
            intensities: Vec<f32>,
        }
    }

    ros_message! {
        /// `sensor_msgs/msg/Imu`: orientation, angular velocity, linear acceleration.
        Imu = "sensor_msgs/msg/Imu" {
            /// Time and frame.
            header: Header,
            /// Orientation.
            orientation: Quaternion,
            /// Row-major covariance about x, y, z.
            orientation_covariance: [f64; 9],
            /// Angular velocity (rad/s).
            angular_velocity: Vector3,
            /// Row-major covariance.
            angular_velocity_covariance: [f64; 9],
            /// Linear acceleration (m/s²).
            linear_acceleration: Vector3,
            /// Row-major covariance.
            linear_acceleration_covariance: [f64; 9],
        }
    }

    ros_message! {
        /// `sensor_msgs/msg/JointState`: the state of a set of joints.
        JointState = "sensor_msgs/msg/JointState" {
            /// Time and frame.
            header: Header,
            /// Joint names.
            name: Vec<std::string::String>,
            /// Positions (rad or m).
            position: Vec<f64>,
            /// Velocities.
            velocity: Vec<f64>,
            /// Efforts.
            effort: Vec<f64>,
        }
    }
}
