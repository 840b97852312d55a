//! `example_interfaces` (jazzy): `srv/AddTwoInts` (example_interfaces jazzy `srv/AddTwoInts.srv`).

/// Services.
pub mod srv {
    ros_message! {
        /// Request of `example_interfaces/srv/AddTwoInts`.
        #[derive(Copy, Eq, Hash)]
        AddTwoIntsRequest = "example_interfaces/srv/AddTwoInts_Request" {
            /// First addend.
            a: i64,
            /// Second addend.
            b: i64,
        }
    }

    ros_message! {
        /// Response of `example_interfaces/srv/AddTwoInts`.
        #[derive(Copy, Eq, Hash)]
        AddTwoIntsResponse = "example_interfaces/srv/AddTwoInts_Response" {
            /// `a + b`.
            sum: i64,
        }
    }

    ros_service! {
        /// `example_interfaces/srv/AddTwoInts`.
        AddTwoInts = "example_interfaces/srv/AddTwoInts", AddTwoIntsRequest, AddTwoIntsResponse
    }
}

/// Every interface of this package: ROS type name and type description.
pub const TYPES: &[(&str, crate::DescribeFn)] = &[(
    "example_interfaces/srv/AddTwoInts",
    <srv::AddTwoInts as crate::Service>::type_description,
)];
