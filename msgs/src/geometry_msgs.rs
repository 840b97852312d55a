//! `geometry_msgs` (jazzy): `Vector3`, `Point`, `Quaternion`, `Pose`, `PoseStamped`, `Twist`,
//! `TwistStamped` (common_interfaces jazzy `geometry_msgs/msg/*.msg`).

/// Messages.
pub mod msg {
    use crate::std_msgs::msg::Header;
    use crate::{DescriptionBuilder, Message, TypeDescription};

    ros_message! {
        /// `geometry_msgs/msg/Vector3`: a vector in free space.
        #[derive(Copy)]
        Vector3 = "geometry_msgs/msg/Vector3" {
            /// x.
            x: f64,
            /// y.
            y: f64,
            /// z.
            z: f64,
        }
    }

    ros_message! {
        /// `geometry_msgs/msg/Point`: a position in free space.
        #[derive(Copy)]
        Point = "geometry_msgs/msg/Point" {
            /// x.
            x: f64,
            /// y.
            y: f64,
            /// z.
            z: f64,
        }
    }

    /// `geometry_msgs/msg/Quaternion`: an orientation. The `.msg` gives defaults
    /// (`float64 x 0`, …, `float64 w 1`): `Default` is the identity rotation.
    #[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    pub struct Quaternion {
        /// x (default 0).
        pub x: f64,
        /// y (default 0).
        pub y: f64,
        /// z (default 0).
        pub z: f64,
        /// w (default 1).
        pub w: f64,
    }

    impl Default for Quaternion {
        fn default() -> Self {
            Self {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 1.0,
            }
        }
    }

    impl Message for Quaternion {
        const TYPE_NAME: &'static str = "geometry_msgs/msg/Quaternion";

        fn type_description() -> TypeDescription {
            DescriptionBuilder::new(Self::TYPE_NAME)
                .field::<f64>("x")
                .default_value("0")
                .field::<f64>("y")
                .default_value("0")
                .field::<f64>("z")
                .default_value("0")
                .field::<f64>("w")
                .default_value("1")
                .build()
        }
    }

    ros_message! {
        /// `geometry_msgs/msg/Pose`: position and orientation.
        #[derive(Copy)]
        Pose = "geometry_msgs/msg/Pose" {
            /// Position.
            position: Point,
            /// Orientation.
            orientation: Quaternion,
        }
    }

    ros_message! {
        /// `geometry_msgs/msg/PoseStamped`: a pose with a frame and a time.
        PoseStamped = "geometry_msgs/msg/PoseStamped" {
            /// Frame and time.
            header: Header,
            /// The pose.
            pose: Pose,
        }
    }

    ros_message! {
        /// `geometry_msgs/msg/Twist`: linear and angular velocity.
        #[derive(Copy)]
        Twist = "geometry_msgs/msg/Twist" {
            /// Linear velocity (m/s).
            linear: Vector3,
            /// Angular velocity (rad/s).
            angular: Vector3,
        }
    }

    ros_message! {
        /// `geometry_msgs/msg/TwistStamped`: a twist with a frame and a time.
        TwistStamped = "geometry_msgs/msg/TwistStamped" {
            /// Frame and time.
            header: Header,
            /// The twist.
            twist: Twist,
        }
    }
}
