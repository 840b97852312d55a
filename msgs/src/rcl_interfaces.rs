//! `rcl_interfaces` (jazzy): the parameter services every node offers and the messages they
//! use (rcl_interfaces jazzy `rcl_interfaces/msg/*.msg`, `srv/*Parameter*.srv`).

/// Messages.
pub mod msg {
    use crate::field::Byte;

    ros_message! {
        /// `rcl_interfaces/msg/ParameterType`: only constants (the struct has rosidl's placeholder).
        #[derive(Copy, Eq, Hash)]
        ParameterType = "rcl_interfaces/msg/ParameterType" {
            /// rosidl's placeholder member (always 0).
            structure_needs_at_least_one_member: u8,
        }
    }

    impl ParameterType {
        /// `PARAMETER_NOT_SET = 0`: not a valid parameter.
        pub const PARAMETER_NOT_SET: u8 = 0;
        /// `PARAMETER_BOOL = 1`.
        pub const PARAMETER_BOOL: u8 = 1;
        /// `PARAMETER_INTEGER = 2`.
        pub const PARAMETER_INTEGER: u8 = 2;
        /// `PARAMETER_DOUBLE = 3`.
        pub const PARAMETER_DOUBLE: u8 = 3;
        /// `PARAMETER_STRING = 4`.
        pub const PARAMETER_STRING: u8 = 4;
        /// `PARAMETER_BYTE_ARRAY = 5`.
        pub const PARAMETER_BYTE_ARRAY: u8 = 5;
        /// `PARAMETER_BOOL_ARRAY = 6`.
        pub const PARAMETER_BOOL_ARRAY: u8 = 6;
        /// `PARAMETER_INTEGER_ARRAY = 7`.
        pub const PARAMETER_INTEGER_ARRAY: u8 = 7;
        /// `PARAMETER_DOUBLE_ARRAY = 8`.
        pub const PARAMETER_DOUBLE_ARRAY: u8 = 8;
        /// `PARAMETER_STRING_ARRAY = 9`.
        pub const PARAMETER_STRING_ARRAY: u8 = 9;
    }

    ros_message! {
        /// `rcl_interfaces/msg/ParameterValue`: a variant; `type` tells which field is valid.
        ParameterValue = "rcl_interfaces/msg/ParameterValue" {
            /// A `ParameterType::PARAMETER_*` constant.
            r#type: u8,
            /// Boolean value.
            bool_value: bool,
            /// Integer value.
            integer_value: i64,
            /// Double value.
            double_value: f64,
            /// String value.
            string_value: String,
            /// `byte[]` value.
            byte_array_value: Vec<Byte>,
            /// `bool[]` value.
            bool_array_value: Vec<bool>,
            /// `int64[]` value.
            integer_array_value: Vec<i64>,
            /// `float64[]` value.
            double_array_value: Vec<f64>,
            /// `string[]` value.
            string_array_value: Vec<String>,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/Parameter`: a name and a value.
        Parameter = "rcl_interfaces/msg/Parameter" {
            /// Full parameter name.
            name: String,
            /// The value.
            value: ParameterValue,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/FloatingPointRange`.
        #[derive(Copy)]
        FloatingPointRange = "rcl_interfaces/msg/FloatingPointRange" {
            /// Start (inclusive).
            from_value: f64,
            /// End (inclusive).
            to_value: f64,
            /// Step magnitude; 0 = continuous.
            step: f64,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/IntegerRange`.
        #[derive(Copy, Eq, Hash)]
        IntegerRange = "rcl_interfaces/msg/IntegerRange" {
            /// Start (inclusive).
            from_value: i64,
            /// End (inclusive).
            to_value: i64,
            /// Step; 0 = continuous.
            step: u64,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/ParameterDescriptor`.
        ParameterDescriptor = "rcl_interfaces/msg/ParameterDescriptor" {
            /// Parameter name.
            name: String,
            /// A `ParameterType::PARAMETER_*` constant.
            r#type: u8,
            /// Description.
            description: String,
            /// Plain-English constraints.
            additional_constraints: String,
            /// Cannot change after initialization (default false).
            read_only: bool = "False",
            /// May change type (default false).
            dynamic_typing: bool = "False",
            /// `FloatingPointRange[<=1]`.
            floating_point_range: Vec<FloatingPointRange> => |t| t.bounded_sequence(1),
            /// `IntegerRange[<=1]`.
            integer_range: Vec<IntegerRange> => |t| t.bounded_sequence(1),
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/SetParametersResult`.
        #[derive(Eq, Hash)]
        SetParametersResult = "rcl_interfaces/msg/SetParametersResult" {
            /// Whether the parameter was set.
            successful: bool,
            /// Why not (for logging / UIs).
            reason: String,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/ListParametersResult`.
        #[derive(Eq, Hash)]
        ListParametersResult = "rcl_interfaces/msg/ListParametersResult" {
            /// Parameter names found.
            names: Vec<String>,
            /// Prefixes found.
            prefixes: Vec<String>,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/Log`: a log message, as every node publishes it on `/rosout`.
        Log = "rcl_interfaces/msg/Log" {
            /// When it was logged.
            stamp: crate::builtin_interfaces::msg::Time,
            /// Severity (one of the constants).
            level: u8,
            /// The logger name (`ns.node`).
            name: String,
            /// The message.
            msg: String,
            /// Source file.
            file: String,
            /// Function.
            function: String,
            /// Line.
            line: u32,
        }
    }

    ros_message! {
        /// `rcl_interfaces/msg/ParameterEvent`: what one change did to a node's parameters, as
        /// every rclcpp node publishes it on `/parameter_events`. A name is in one list only.
        ParameterEvent = "rcl_interfaces/msg/ParameterEvent" {
            /// When the change happened.
            stamp: crate::builtin_interfaces::msg::Time,
            /// The node's fully-qualified name.
            node: String,
            /// Parameters declared by the change.
            new_parameters: Vec<Parameter>,
            /// Parameters whose value changed.
            changed_parameters: Vec<Parameter>,
            /// Parameters undeclared by the change.
            deleted_parameters: Vec<Parameter>,
        }
    }

    impl Log {
        /// `DEBUG = 10`.
        pub const DEBUG: u8 = 10;
        /// `INFO = 20`.
        pub const INFO: u8 = 20;
        /// `WARN = 30`.
        pub const WARN: u8 = 30;
        /// `ERROR = 40`.
        pub const ERROR: u8 = 40;
        /// `FATAL = 50`.
        pub const FATAL: u8 = 50;
    }
}

/// Services.
pub mod srv {
    use super::msg::{
        ListParametersResult, Parameter, ParameterDescriptor, ParameterValue, SetParametersResult,
    };

    ros_message! {
        /// Request of `rcl_interfaces/srv/ListParameters`.
        #[derive(Eq, Hash)]
        ListParametersRequest = "rcl_interfaces/srv/ListParameters_Request" {
            /// Prefixes to list under.
            prefixes: Vec<String>,
            /// Relative depth; `DEPTH_RECURSIVE` (0) = unlimited.
            depth: u64,
        }
    }

    impl ListParametersRequest {
        /// `uint64 DEPTH_RECURSIVE=0`.
        pub const DEPTH_RECURSIVE: u64 = 0;
    }

    ros_message! {
        /// Response of `rcl_interfaces/srv/ListParameters`.
        #[derive(Eq, Hash)]
        ListParametersResponse = "rcl_interfaces/srv/ListParameters_Response" {
            /// Names and prefixes found.
            result: ListParametersResult,
        }
    }

    ros_service! {
        /// `rcl_interfaces/srv/ListParameters`.
        ListParameters = "rcl_interfaces/srv/ListParameters",
        ListParametersRequest, ListParametersResponse
    }

    ros_message! {
        /// Request of `rcl_interfaces/srv/GetParameters`.
        #[derive(Eq, Hash)]
        GetParametersRequest = "rcl_interfaces/srv/GetParameters_Request" {
            /// Names to get.
            names: Vec<String>,
        }
    }

    ros_message! {
        /// Response of `rcl_interfaces/srv/GetParameters`.
        GetParametersResponse = "rcl_interfaces/srv/GetParameters_Response" {
            /// Values in request order (`PARAMETER_NOT_SET` if unset).
            values: Vec<ParameterValue>,
        }
    }

    ros_service! {
        /// `rcl_interfaces/srv/GetParameters`.
        GetParameters = "rcl_interfaces/srv/GetParameters",
        GetParametersRequest, GetParametersResponse
    }

    ros_message! {
        /// Request of `rcl_interfaces/srv/GetParameterTypes`.
        #[derive(Eq, Hash)]
        GetParameterTypesRequest = "rcl_interfaces/srv/GetParameterTypes_Request" {
            /// Names to query.
            names: Vec<String>,
        }
    }

    ros_message! {
        /// Response of `rcl_interfaces/srv/GetParameterTypes`.
        #[derive(Eq, Hash)]
        GetParameterTypesResponse = "rcl_interfaces/srv/GetParameterTypes_Response" {
            /// `ParameterType` constants in request order.
            types: Vec<u8>,
        }
    }

    ros_service! {
        /// `rcl_interfaces/srv/GetParameterTypes`.
        GetParameterTypes = "rcl_interfaces/srv/GetParameterTypes",
        GetParameterTypesRequest, GetParameterTypesResponse
    }

    ros_message! {
        /// Request of `rcl_interfaces/srv/SetParameters`.
        SetParametersRequest = "rcl_interfaces/srv/SetParameters_Request" {
            /// Parameters to set.
            parameters: Vec<Parameter>,
        }
    }

    ros_message! {
        /// Response of `rcl_interfaces/srv/SetParameters`.
        #[derive(Eq, Hash)]
        SetParametersResponse = "rcl_interfaces/srv/SetParameters_Response" {
            /// One result per parameter.
            results: Vec<SetParametersResult>,
        }
    }

    ros_service! {
        /// `rcl_interfaces/srv/SetParameters`.
        SetParameters = "rcl_interfaces/srv/SetParameters",
        SetParametersRequest, SetParametersResponse
    }

    ros_message! {
        /// Request of `rcl_interfaces/srv/SetParametersAtomically`.
        SetParametersAtomicallyRequest = "rcl_interfaces/srv/SetParametersAtomically_Request" {
            /// Parameters to set, all or none.
            parameters: Vec<Parameter>,
        }
    }

    ros_message! {
        /// Response of `rcl_interfaces/srv/SetParametersAtomically`.
        #[derive(Eq, Hash)]
        SetParametersAtomicallyResponse = "rcl_interfaces/srv/SetParametersAtomically_Response" {
            /// The single result.
            result: SetParametersResult,
        }
    }

    ros_service! {
        /// `rcl_interfaces/srv/SetParametersAtomically`.
        SetParametersAtomically = "rcl_interfaces/srv/SetParametersAtomically",
        SetParametersAtomicallyRequest, SetParametersAtomicallyResponse
    }

    ros_message! {
        /// Request of `rcl_interfaces/srv/DescribeParameters`.
        #[derive(Eq, Hash)]
        DescribeParametersRequest = "rcl_interfaces/srv/DescribeParameters_Request" {
            /// Names to describe.
            names: Vec<String>,
        }
    }

    ros_message! {
        /// Response of `rcl_interfaces/srv/DescribeParameters`.
        DescribeParametersResponse = "rcl_interfaces/srv/DescribeParameters_Response" {
            /// Descriptors in request order.
            descriptors: Vec<ParameterDescriptor>,
        }
    }

    ros_service! {
        /// `rcl_interfaces/srv/DescribeParameters`.
        DescribeParameters = "rcl_interfaces/srv/DescribeParameters",
        DescribeParametersRequest, DescribeParametersResponse
    }
}
