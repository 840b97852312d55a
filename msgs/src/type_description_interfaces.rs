//! `type_description_interfaces` (jazzy): the messages that describe ROS types, and the
//! `GetTypeDescription` service. Layouts from rcl_interfaces (jazzy)
//! `type_description_interfaces/msg/*.msg`, `srv/GetTypeDescription.srv`.

/// Messages.
pub mod msg {
    ros_message! {
        /// `type_description_interfaces/msg/FieldType`: the type of a field.
        FieldType = "type_description_interfaces/msg/FieldType" {
            /// One of the `FIELD_TYPE_*` constants.
            type_id: u8 = "0",
            /// Array size or bounded-sequence maximum; 0 otherwise.
            capacity: u64,
            /// Maximum (bounded) or fixed length of strings; 0 otherwise.
            string_capacity: u64,
            /// `string<=255`: the nested type's name (`pkg/msg/Name`), or empty.
            nested_type_name: String => |t| t.bounded_string(255),
        }
    }

    /// Type-id constants (`FieldType.msg`).
    impl FieldType {
        /// `FIELD_TYPE_NOT_SET`.
        pub const FIELD_TYPE_NOT_SET: u8 = 0;
        /// `FIELD_TYPE_NESTED_TYPE`.
        pub const FIELD_TYPE_NESTED_TYPE: u8 = 1;
        /// `FIELD_TYPE_INT8`.
        pub const FIELD_TYPE_INT8: u8 = 2;
        /// `FIELD_TYPE_UINT8`.
        pub const FIELD_TYPE_UINT8: u8 = 3;
        /// `FIELD_TYPE_INT16`.
        pub const FIELD_TYPE_INT16: u8 = 4;
        /// `FIELD_TYPE_UINT16`.
        pub const FIELD_TYPE_UINT16: u8 = 5;
        /// `FIELD_TYPE_INT32`.
        pub const FIELD_TYPE_INT32: u8 = 6;
        /// `FIELD_TYPE_UINT32`.
        pub const FIELD_TYPE_UINT32: u8 = 7;
        /// `FIELD_TYPE_INT64`.
        pub const FIELD_TYPE_INT64: u8 = 8;
        /// `FIELD_TYPE_UINT64`.
        pub const FIELD_TYPE_UINT64: u8 = 9;
        /// `FIELD_TYPE_FLOAT`.
        pub const FIELD_TYPE_FLOAT: u8 = 10;
        /// `FIELD_TYPE_DOUBLE`.
        pub const FIELD_TYPE_DOUBLE: u8 = 11;
        /// `FIELD_TYPE_LONG_DOUBLE`.
        pub const FIELD_TYPE_LONG_DOUBLE: u8 = 12;
        /// `FIELD_TYPE_CHAR`.
        pub const FIELD_TYPE_CHAR: u8 = 13;
        /// `FIELD_TYPE_WCHAR`.
        pub const FIELD_TYPE_WCHAR: u8 = 14;
        /// `FIELD_TYPE_BOOLEAN`.
        pub const FIELD_TYPE_BOOLEAN: u8 = 15;
        /// `FIELD_TYPE_BYTE`.
        pub const FIELD_TYPE_BYTE: u8 = 16;
        /// `FIELD_TYPE_STRING`.
        pub const FIELD_TYPE_STRING: u8 = 17;
        /// `FIELD_TYPE_WSTRING`.
        pub const FIELD_TYPE_WSTRING: u8 = 18;
        /// `FIELD_TYPE_FIXED_STRING`.
        pub const FIELD_TYPE_FIXED_STRING: u8 = 19;
        /// `FIELD_TYPE_FIXED_WSTRING`.
        pub const FIELD_TYPE_FIXED_WSTRING: u8 = 20;
        /// `FIELD_TYPE_BOUNDED_STRING`.
        pub const FIELD_TYPE_BOUNDED_STRING: u8 = 21;
        /// `FIELD_TYPE_BOUNDED_WSTRING`.
        pub const FIELD_TYPE_BOUNDED_WSTRING: u8 = 22;
        /// `FIELD_TYPE_NESTED_TYPE_ARRAY`.
        pub const FIELD_TYPE_NESTED_TYPE_ARRAY: u8 = 49;
        /// `FIELD_TYPE_INT8_ARRAY`.
        pub const FIELD_TYPE_INT8_ARRAY: u8 = 50;
        /// `FIELD_TYPE_UINT8_ARRAY`.
        pub const FIELD_TYPE_UINT8_ARRAY: u8 = 51;
        /// `FIELD_TYPE_INT16_ARRAY`.
        pub const FIELD_TYPE_INT16_ARRAY: u8 = 52;
        /// `FIELD_TYPE_UINT16_ARRAY`.
        pub const FIELD_TYPE_UINT16_ARRAY: u8 = 53;
        /// `FIELD_TYPE_INT32_ARRAY`.
        pub const FIELD_TYPE_INT32_ARRAY: u8 = 54;
        /// `FIELD_TYPE_UINT32_ARRAY`.
        pub const FIELD_TYPE_UINT32_ARRAY: u8 = 55;
        /// `FIELD_TYPE_INT64_ARRAY`.
        pub const FIELD_TYPE_INT64_ARRAY: u8 = 56;
        /// `FIELD_TYPE_UINT64_ARRAY`.
        pub const FIELD_TYPE_UINT64_ARRAY: u8 = 57;
        /// `FIELD_TYPE_FLOAT_ARRAY`.
        pub const FIELD_TYPE_FLOAT_ARRAY: u8 = 58;
        /// `FIELD_TYPE_DOUBLE_ARRAY`.
        pub const FIELD_TYPE_DOUBLE_ARRAY: u8 = 59;
        /// `FIELD_TYPE_LONG_DOUBLE_ARRAY`.
        pub const FIELD_TYPE_LONG_DOUBLE_ARRAY: u8 = 60;
        /// `FIELD_TYPE_CHAR_ARRAY`.
        pub const FIELD_TYPE_CHAR_ARRAY: u8 = 61;
        /// `FIELD_TYPE_WCHAR_ARRAY`.
        pub const FIELD_TYPE_WCHAR_ARRAY: u8 = 62;
        /// `FIELD_TYPE_BOOLEAN_ARRAY`.
        pub const FIELD_TYPE_BOOLEAN_ARRAY: u8 = 63;
        /// `FIELD_TYPE_BYTE_ARRAY`.
        pub const FIELD_TYPE_BYTE_ARRAY: u8 = 64;
        /// `FIELD_TYPE_STRING_ARRAY`.
        pub const FIELD_TYPE_STRING_ARRAY: u8 = 65;
        /// `FIELD_TYPE_WSTRING_ARRAY`.
        pub const FIELD_TYPE_WSTRING_ARRAY: u8 = 66;
        /// `FIELD_TYPE_FIXED_STRING_ARRAY`.
        pub const FIELD_TYPE_FIXED_STRING_ARRAY: u8 = 67;
        /// `FIELD_TYPE_FIXED_WSTRING_ARRAY`.
        pub const FIELD_TYPE_FIXED_WSTRING_ARRAY: u8 = 68;
        /// `FIELD_TYPE_BOUNDED_STRING_ARRAY`.
        pub const FIELD_TYPE_BOUNDED_STRING_ARRAY: u8 = 69;
        /// `FIELD_TYPE_BOUNDED_WSTRING_ARRAY`.
        pub const FIELD_TYPE_BOUNDED_WSTRING_ARRAY: u8 = 70;
        /// `FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE: u8 = 97;
        /// `FIELD_TYPE_INT8_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT8_BOUNDED_SEQUENCE: u8 = 98;
        /// `FIELD_TYPE_UINT8_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT8_BOUNDED_SEQUENCE: u8 = 99;
        /// `FIELD_TYPE_INT16_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT16_BOUNDED_SEQUENCE: u8 = 100;
        /// `FIELD_TYPE_UINT16_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT16_BOUNDED_SEQUENCE: u8 = 101;
        /// `FIELD_TYPE_INT32_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT32_BOUNDED_SEQUENCE: u8 = 102;
        /// `FIELD_TYPE_UINT32_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT32_BOUNDED_SEQUENCE: u8 = 103;
        /// `FIELD_TYPE_INT64_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT64_BOUNDED_SEQUENCE: u8 = 104;
        /// `FIELD_TYPE_UINT64_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT64_BOUNDED_SEQUENCE: u8 = 105;
        /// `FIELD_TYPE_FLOAT_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_FLOAT_BOUNDED_SEQUENCE: u8 = 106;
        /// `FIELD_TYPE_DOUBLE_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_DOUBLE_BOUNDED_SEQUENCE: u8 = 107;
        /// `FIELD_TYPE_LONG_DOUBLE_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_LONG_DOUBLE_BOUNDED_SEQUENCE: u8 = 108;
        /// `FIELD_TYPE_CHAR_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_CHAR_BOUNDED_SEQUENCE: u8 = 109;
        /// `FIELD_TYPE_WCHAR_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_WCHAR_BOUNDED_SEQUENCE: u8 = 110;
        /// `FIELD_TYPE_BOOLEAN_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BOOLEAN_BOUNDED_SEQUENCE: u8 = 111;
        /// `FIELD_TYPE_BYTE_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BYTE_BOUNDED_SEQUENCE: u8 = 112;
        /// `FIELD_TYPE_STRING_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_STRING_BOUNDED_SEQUENCE: u8 = 113;
        /// `FIELD_TYPE_WSTRING_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_WSTRING_BOUNDED_SEQUENCE: u8 = 114;
        /// `FIELD_TYPE_FIXED_STRING_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_FIXED_STRING_BOUNDED_SEQUENCE: u8 = 115;
        /// `FIELD_TYPE_FIXED_WSTRING_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_FIXED_WSTRING_BOUNDED_SEQUENCE: u8 = 116;
        /// `FIELD_TYPE_BOUNDED_STRING_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BOUNDED_STRING_BOUNDED_SEQUENCE: u8 = 117;
        /// `FIELD_TYPE_BOUNDED_WSTRING_BOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BOUNDED_WSTRING_BOUNDED_SEQUENCE: u8 = 118;
        /// `FIELD_TYPE_NESTED_TYPE_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_NESTED_TYPE_UNBOUNDED_SEQUENCE: u8 = 145;
        /// `FIELD_TYPE_INT8_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT8_UNBOUNDED_SEQUENCE: u8 = 146;
        /// `FIELD_TYPE_UINT8_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT8_UNBOUNDED_SEQUENCE: u8 = 147;
        /// `FIELD_TYPE_INT16_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT16_UNBOUNDED_SEQUENCE: u8 = 148;
        /// `FIELD_TYPE_UINT16_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT16_UNBOUNDED_SEQUENCE: u8 = 149;
        /// `FIELD_TYPE_INT32_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT32_UNBOUNDED_SEQUENCE: u8 = 150;
        /// `FIELD_TYPE_UINT32_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT32_UNBOUNDED_SEQUENCE: u8 = 151;
        /// `FIELD_TYPE_INT64_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_INT64_UNBOUNDED_SEQUENCE: u8 = 152;
        /// `FIELD_TYPE_UINT64_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_UINT64_UNBOUNDED_SEQUENCE: u8 = 153;
        /// `FIELD_TYPE_FLOAT_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_FLOAT_UNBOUNDED_SEQUENCE: u8 = 154;
        /// `FIELD_TYPE_DOUBLE_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_DOUBLE_UNBOUNDED_SEQUENCE: u8 = 155;
        /// `FIELD_TYPE_LONG_DOUBLE_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_LONG_DOUBLE_UNBOUNDED_SEQUENCE: u8 = 156;
        /// `FIELD_TYPE_CHAR_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_CHAR_UNBOUNDED_SEQUENCE: u8 = 157;
        /// `FIELD_TYPE_WCHAR_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_WCHAR_UNBOUNDED_SEQUENCE: u8 = 158;
        /// `FIELD_TYPE_BOOLEAN_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BOOLEAN_UNBOUNDED_SEQUENCE: u8 = 159;
        /// `FIELD_TYPE_BYTE_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BYTE_UNBOUNDED_SEQUENCE: u8 = 160;
        /// `FIELD_TYPE_STRING_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_STRING_UNBOUNDED_SEQUENCE: u8 = 161;
        /// `FIELD_TYPE_WSTRING_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_WSTRING_UNBOUNDED_SEQUENCE: u8 = 162;
        /// `FIELD_TYPE_FIXED_STRING_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_FIXED_STRING_UNBOUNDED_SEQUENCE: u8 = 163;
        /// `FIELD_TYPE_FIXED_WSTRING_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_FIXED_WSTRING_UNBOUNDED_SEQUENCE: u8 = 164;
        /// `FIELD_TYPE_BOUNDED_STRING_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BOUNDED_STRING_UNBOUNDED_SEQUENCE: u8 = 165;
        /// `FIELD_TYPE_BOUNDED_WSTRING_UNBOUNDED_SEQUENCE`.
        pub const FIELD_TYPE_BOUNDED_WSTRING_UNBOUNDED_SEQUENCE: u8 = 166;
    }

    ros_message! {
        /// `type_description_interfaces/msg/Field`: one field of a type.
        Field = "type_description_interfaces/msg/Field" {
            /// Field name.
            name: String,
            /// Field type.
            r#type: FieldType,
            /// Default value as written in the source file (empty if none).
            default_value: String,
        }
    }

    ros_message! {
        /// `type_description_interfaces/msg/IndividualTypeDescription`: one type without the
        /// types it references.
        IndividualTypeDescription = "type_description_interfaces/msg/IndividualTypeDescription" {
            /// `string<=255`: `pkg/msg/Name`.
            type_name: String => |t| t.bounded_string(255),
            /// The fields, in definition order.
            fields: Vec<Field>,
        }
    }

    ros_message! {
        /// `type_description_interfaces/msg/TypeDescription`: a type and every type it
        /// references (recursively), the latter sorted by name.
        TypeDescription = "type_description_interfaces/msg/TypeDescription" {
            /// The type itself.
            type_description: IndividualTypeDescription,
            /// All referenced types.
            referenced_type_descriptions: Vec<IndividualTypeDescription>,
        }
    }

    ros_message! {
        /// `type_description_interfaces/msg/KeyValue`: an application-specific key-value pair.
        KeyValue = "type_description_interfaces/msg/KeyValue" {
            /// Key.
            key: String,
            /// Value.
            value: String,
        }
    }

    ros_message! {
        /// `type_description_interfaces/msg/TypeSource`: the source text of an interface.
        TypeSource = "type_description_interfaces/msg/TypeSource" {
            /// `PACKAGE/NAMESPACE/TYPENAME`.
            type_name: String,
            /// `idl`, `msg`, `srv`, `action`, `dynamic` or `implicit`.
            encoding: String,
            /// The file contents (empty for `dynamic` / `implicit`).
            raw_file_contents: String,
        }
    }

    impl TypeDescription {
        /// The RIHS01 hash of this description (REP-2011).
        pub fn compute_type_hash(&self) -> crate::TypeHash {
            crate::rihs::rihs01(self)
        }
    }
}

/// Services.
pub mod srv {
    use super::msg::{KeyValue, TypeDescription, TypeSource};

    ros_message! {
        /// Request of `type_description_interfaces/srv/GetTypeDescription`.
        GetTypeDescriptionRequest = "type_description_interfaces/srv/GetTypeDescription_Request" {
            /// `PACKAGE/NAMESPACE/TYPENAME`.
            type_name: String,
            /// REP-2011 RIHS hash string (`RIHS01_…`).
            type_hash: String,
            /// Whether to return the source files too (default `true`).
            include_type_sources: bool = "True",
        }
    }

    ros_message! {
        /// Response of `type_description_interfaces/srv/GetTypeDescription`.
        GetTypeDescriptionResponse = "type_description_interfaces/srv/GetTypeDescription_Response" {
            /// True if the description is available.
            successful: bool,
            /// Why not, when `successful` is false.
            failure_reason: String,
            /// The description.
            type_description: TypeDescription,
            /// Sources of the type and of every type it depends on.
            type_sources: Vec<TypeSource>,
            /// Extra information.
            extra_information: Vec<KeyValue>,
        }
    }

    ros_service! {
        /// `type_description_interfaces/srv/GetTypeDescription`.
        GetTypeDescription = "type_description_interfaces/srv/GetTypeDescription",
        GetTypeDescriptionRequest, GetTypeDescriptionResponse
    }
}
