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

    impl Time {
        /// The system (wall-clock) time now, as rcl's system clock stamps `/rosout` and
        /// `/parameter_events` messages: seconds since the Unix epoch (saturated to `i32`) and
        /// the nanoseconds within that second; zero before the epoch.
        pub fn now() -> Self {
            let since_epoch = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .unwrap_or_default();
            Self {
                sec: i32::try_from(since_epoch.as_secs()).unwrap_or(i32::MAX),
                nanosec: since_epoch.subsec_nanos(),
            }
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
