//! `builtin_interfaces` (jazzy): `Time` and `Duration` (rcl_interfaces jazzy
//! `builtin_interfaces/msg/Time.msg`, `Duration.msg`).

/// Messages.
pub mod msg {
    ros_message! {
        /// `builtin_interfaces/msg/Time`: ROS time.
        #[derive(Copy, Eq, Hash, PartialOrd, Ord)]
        Time = "builtin_interfaces/msg/Time" {
            /// Seconds.
            sec: i32,
            /// Nanoseconds in `[0, 1e9)`.
            nanosec: u32,
        }
    }

    ros_message! {
        /// `builtin_interfaces/msg/Duration`: a period of ROS time.
        #[derive(Copy, Eq, Hash, PartialOrd, Ord)]
        Duration = "builtin_interfaces/msg/Duration" {
            /// Seconds.
            sec: i32,
            /// Nanoseconds in `[0, 1e9)`.
            nanosec: u32,
        }
    }
}
