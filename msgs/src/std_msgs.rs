//! `std_msgs` (jazzy): `String`, `Bool`, the numeric types, `Header`, `Empty` (common_interfaces
//! jazzy `std_msgs/msg/*.msg`).

/// Messages.
pub mod msg {
    ros_message! {
        /// `std_msgs/msg/String`: `string data`.
        #[derive(Eq, Hash)]
        String = "std_msgs/msg/String" {
            /// The text.
            data: std::string::String,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Header`: standard metadata for stamped data.
        Header = "std_msgs/msg/Header" {
            /// Acquisition time.
            stamp: crate::builtin_interfaces::msg::Time,
            /// Coordinate frame.
            frame_id: std::string::String,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Empty` (rosidl's placeholder member on the wire).
        #[derive(Copy, Eq, Hash)]
        Empty = "std_msgs/msg/Empty" {
            /// rosidl's placeholder member (always 0).
            structure_needs_at_least_one_member: u8,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Bool`: `bool data`.
        #[derive(Copy, Eq, Hash)]
        Bool = "std_msgs/msg/Bool" {
            /// The value.
            data: bool,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Byte`: `byte data`.
        #[derive(Copy, Eq, Hash)]
        Byte = "std_msgs/msg/Byte" {
            /// The value.
            data: crate::field::Byte,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Char`: `char data`.
        #[derive(Copy, Eq, Hash)]
        Char = "std_msgs/msg/Char" {
            /// The value.
            data: u8,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Int8`: `int8 data`.
        #[derive(Copy, Eq, Hash)]
        Int8 = "std_msgs/msg/Int8" {
            /// The value.
            data: i8,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Int16`: `int16 data`.
        #[derive(Copy, Eq, Hash)]
        Int16 = "std_msgs/msg/Int16" {
            /// The value.
            data: i16,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Int32`: `int32 data`.
        #[derive(Copy, Eq, Hash)]
        Int32 = "std_msgs/msg/Int32" {
            /// The value.
            data: i32,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Int64`: `int64 data`.
        #[derive(Copy, Eq, Hash)]
        Int64 = "std_msgs/msg/Int64" {
            /// The value.
            data: i64,
        }
    }

    ros_message! {
        /// `std_msgs/msg/UInt8`: `uint8 data`.
        #[derive(Copy, Eq, Hash)]
        UInt8 = "std_msgs/msg/UInt8" {
            /// The value.
            data: u8,
        }
    }

    ros_message! {
        /// `std_msgs/msg/UInt16`: `uint16 data`.
        #[derive(Copy, Eq, Hash)]
        UInt16 = "std_msgs/msg/UInt16" {
            /// The value.
            data: u16,
        }
    }

    ros_message! {
        /// `std_msgs/msg/UInt32`: `uint32 data`.
        #[derive(Copy, Eq, Hash)]
        UInt32 = "std_msgs/msg/UInt32" {
            /// The value.
            data: u32,
        }
    }

    ros_message! {
        /// `std_msgs/msg/UInt64`: `uint64 data`.
        #[derive(Copy, Eq, Hash)]
        UInt64 = "std_msgs/msg/UInt64" {
            /// The value.
            data: u64,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Float32`: `float32 data`.
        #[derive(Copy)]
        Float32 = "std_msgs/msg/Float32" {
            /// The value.
            data: f32,
        }
    }

    ros_message! {
        /// `std_msgs/msg/Float64`: `float64 data`.
        #[derive(Copy)]
        Float64 = "std_msgs/msg/Float64" {
            /// The value.
            data: f64,
        }
    }
}
