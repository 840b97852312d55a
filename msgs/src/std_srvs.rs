//! `std_srvs` (jazzy): `Empty`, `Trigger`, `SetBool` (common_interfaces jazzy `std_srvs/srv/*.srv`).

/// Services.
pub mod srv {
    ros_message! {
        /// Request of `std_srvs/srv/Empty`. Empty structs carry rosidl's placeholder byte.
        #[derive(Copy, Eq, Hash)]
        EmptyRequest = "std_srvs/srv/Empty_Request" {
            /// rosidl's placeholder member (always 0).
            structure_needs_at_least_one_member: u8,
        }
    }

    ros_message! {
        /// Response of `std_srvs/srv/Empty`.
        #[derive(Copy, Eq, Hash)]
        EmptyResponse = "std_srvs/srv/Empty_Response" {
            /// rosidl's placeholder member (always 0).
            structure_needs_at_least_one_member: u8,
        }
    }

    ros_service! {
        /// `std_srvs/srv/Empty`.
        Empty = "std_srvs/srv/Empty", EmptyRequest, EmptyResponse
    }

    ros_message! {
        /// Request of `std_srvs/srv/Trigger`.
        #[derive(Copy, Eq, Hash)]
        TriggerRequest = "std_srvs/srv/Trigger_Request" {
            /// rosidl's placeholder member (always 0).
            structure_needs_at_least_one_member: u8,
        }
    }

    ros_message! {
        /// Response of `std_srvs/srv/Trigger`.
        #[derive(Eq, Hash)]
        TriggerResponse = "std_srvs/srv/Trigger_Response" {
            /// Whether the trigger succeeded.
            success: bool,
            /// Informational message.
            message: String,
        }
    }

    ros_service! {
        /// `std_srvs/srv/Trigger`.
        Trigger = "std_srvs/srv/Trigger", TriggerRequest, TriggerResponse
    }

    ros_message! {
        /// Request of `std_srvs/srv/SetBool`.
        #[derive(Copy, Eq, Hash)]
        SetBoolRequest = "std_srvs/srv/SetBool_Request" {
            /// The value to set.
            data: bool,
        }
    }

    ros_message! {
        /// Response of `std_srvs/srv/SetBool`.
        #[derive(Eq, Hash)]
        SetBoolResponse = "std_srvs/srv/SetBool_Response" {
            /// Whether it succeeded.
            success: bool,
            /// Informational message.
            message: String,
        }
    }

    ros_service! {
        /// `std_srvs/srv/SetBool`.
        SetBool = "std_srvs/srv/SetBool", SetBoolRequest, SetBoolResponse
    }
}
