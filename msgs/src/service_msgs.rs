//! `service_msgs` (jazzy): `ServiceEventInfo`, carried by every `<service>_Event` message
//! (rcl_interfaces jazzy `service_msgs/msg/ServiceEventInfo.msg`).

/// Messages.
pub mod msg {
    use crate::builtin_interfaces::msg::Time;

    ros_message! {
        /// `service_msgs/msg/ServiceEventInfo`.
        #[derive(Copy, Eq, Hash)]
        ServiceEventInfo = "service_msgs/msg/ServiceEventInfo" {
            /// One of `REQUEST_SENT` … `RESPONSE_RECEIVED`.
            event_type: u8,
            /// When the event happened.
            stamp: Time,
            /// `char[16]`: the client's GID (`char` is `uint8` to rosidl).
            client_gid: [u8; 16],
            /// Request sequence number.
            sequence_number: i64,
        }
    }

    impl ServiceEventInfo {
        /// `uint8 REQUEST_SENT = 0`.
        pub const REQUEST_SENT: u8 = 0;
        /// `uint8 REQUEST_RECEIVED = 1`.
        pub const REQUEST_RECEIVED: u8 = 1;
        /// `uint8 RESPONSE_SENT = 2`.
        pub const RESPONSE_SENT: u8 = 2;
        /// `uint8 RESPONSE_RECEIVED = 3`.
        pub const RESPONSE_RECEIVED: u8 = 3;
    }
}
