//! The public [`service!`](crate::service!) macro, and the `const fn` name checks it runs at
//! compile time.
//!
//! The macro expands to paths under `$crate::__private` (`serde`, `horus_ros_msgs`, `pastey`
//! and [`names`]), so a crate that uses it needs no dependency of its own on serde or on the
//! msgs crate.

/// Compile-time checks of ROS names, as rosidl_adapter (jazzy) `parser.py` applies them to
/// `.srv` files. Used by [`service!`](crate::service!); not a stable API.
#[doc(hidden)]
pub mod names {
    /// The ROS package of a [`service!`](crate::service!) defined without one:
    /// `GetMapRegion { … }` is the ROS 2 service type `horus_ros/srv/GetMapRegion`.
    pub const DEFAULT_PACKAGE: &str = "horus_ros";

    /// Start of `name` without a raw identifier's `r#` prefix.
    const fn unraw_start(b: &[u8]) -> usize {
        if b.len() >= 2 && b[0] == b'r' && b[1] == b'#' {
            2
        } else {
            0
        }
    }

    /// A package or field name (`VALID_PACKAGE_NAME_PATTERN` = `VALID_FIELD_NAME_PATTERN`):
    /// `^(?!.*__)(?!.*_$)[a-z][a-z0-9_]*$`. A raw identifier's `r#` prefix is ignored.
    pub const fn is_valid_package_name(name: &str) -> bool {
        let b = name.as_bytes();
        let start = unraw_start(b);
        if b.len() <= start || !b[start].is_ascii_lowercase() || b[b.len() - 1] == b'_' {
            return false;
        }
        let mut i = start;
        while i < b.len() {
            let c = b[i];
            if !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'_') {
                return false;
            }
            if c == b'_' && i + 1 < b.len() && b[i + 1] == b'_' {
                return false;
            }
            i += 1;
        }
        true
    }

    /// A field name: the same rule as a package name.
    pub const fn is_valid_field_name(name: &str) -> bool {
        is_valid_package_name(name)
    }

    /// A message or service name (`VALID_MESSAGE_NAME_PATTERN`): `^[A-Z][A-Za-z0-9]*$`.
    pub const fn is_valid_type_name(name: &str) -> bool {
        let b = name.as_bytes();
        let start = unraw_start(b);
        if b.len() <= start || !b[start].is_ascii_uppercase() {
            return false;
        }
        let mut i = start;
        while i < b.len() {
            if !b[i].is_ascii_alphanumeric() {
                return false;
            }
            i += 1;
        }
        true
    }
}

/// Defines a ROS 2 service type: a unit struct implementing [`horus_ros_msgs::Service`] and its
/// `<Name>Request` / `<Name>Response` structs implementing [`horus_ros_msgs::Message`].
///
/// ```
/// use horus_ros_services::service;
///
/// service! {
///     /// Looks up a region of the map.
///     GetMapRegion {
///         request {
///             x_min: f64,
///             y_min: f64,
///             x_max: f64,
///             y_max: f64,
///             resolution: f64,
///         }
///         response {
///             width: u32,
///             height: u32,
///             data: Vec<u8>,
///             timestamp: u64,
///         }
///     }
/// }
///
/// use horus_ros_msgs::{Message, Service};
/// assert_eq!(<GetMapRegion as Service>::TYPE_NAME, "horus_ros/srv/GetMapRegion");
/// assert_eq!(GetMapRegionRequest::TYPE_NAME, "horus_ros/srv/GetMapRegion_Request");
/// let req = GetMapRegionRequest { resolution: 0.05, ..Default::default() };
/// # let _ = req;
/// ```
///
/// Naming the ROS package gives a type that is the same, on the wire and in its RIHS01 hash, as
/// one rosidl generates from the same `.srv` file, so ROS 2 nodes can call it or serve it:
///
/// ```
/// horus_ros_services::service! {
///     example_interfaces/AddTwoInts {
///         request { a: i64, b: i64 }
///         response { sum: i64 }
///     }
/// }
///
/// use horus_ros_msgs::{Message, Service};
/// assert_eq!(AddTwoInts::TYPE_NAME, "example_interfaces/srv/AddTwoInts");
/// assert_eq!(
///     AddTwoIntsRequest::dds_type_name(),
///     "example_interfaces::srv::dds_::AddTwoInts_Request_"
/// );
/// assert_eq!(
///     AddTwoInts::type_hash(),
///     horus_ros_msgs::example_interfaces::srv::AddTwoInts::type_hash()
/// );
/// ```
///
/// # Grammar
///
/// ```text
/// service! { Definition* }
///
/// Definition := Attribute* Name '{'
///                   Attribute* 'request'  '{' Fields '}'
///                   Attribute* 'response' '{' Fields '}'
///               '}'
/// Name       := Ident                  // package `horus_ros`
///             | Ident '/' Ident        // package / service
///             | Ident '/' 'srv' '/' Ident
/// Fields     := ( Field ( ',' Field )* ','? )?
/// Field      := Attribute* Ident ':' Type ( '=>' Expr )?
/// ```
///
/// - **Generated items** (all `pub`, in the module where the macro is used):
///   `struct Name;` (`Clone, Copy, Debug, Default, PartialEq, Eq`) implementing
///   [`Service`](horus_ros_msgs::Service) with `TYPE_NAME = "pkg/srv/Name"`;
///   `struct NameRequest { pub field: Type, … }` and `struct NameResponse { … }`
///   (`Debug, Clone, PartialEq, Default`, serde `Serialize` / `Deserialize`) implementing
///   [`Message`](horus_ros_msgs::Message) with `TYPE_NAME = "pkg/srv/Name_Request"` /
///   `"pkg/srv/Name_Response"`; DDS type names `pkg::srv::dds_::Name_Request_` /
///   `pkg::srv::dds_::Name_Response_`.
/// - **Attributes**: those before `Name` go on the service struct, those before
///   `request` / `response` on that struct (e.g. `#[derive(Eq, Hash)]`), those before a field
///   on the field. Doc comments are attributes; fields need none (`missing_docs` is allowed on
///   the generated structs, which get a doc line naming their ROS type). Do not derive again
///   the traits listed above, and do not use `#[serde(…)]`: the serde impls are written by the
///   macro (through the serde this crate re-exports, so users need no serde dependency), and
///   field names and order are fixed by the ROS definition.
/// - **Field types**: any [`RosField`](horus_ros_msgs::RosField): `bool`, `i8`…`u64`, `f32`,
///   `f64`, `String`, [`Byte`](horus_ros_msgs::Byte), `Vec<T>`, `[T; N]`, and nested
///   [`Message`](horus_ros_msgs::Message)s such as `horus_ros_msgs::builtin_interfaces::msg::Time`
///   (fields must also be `Default`, so `[T; N]` needs `N <= 32`). Field order is the `.srv`
///   order: it is the wire order and it enters the hash.
/// - **Bounds**: `field: String => |t| t.bounded_string(10)` is `string<=10 field`, and
///   `field: Vec<T> => |t| t.bounded_sequence(5)` is `T[<=5] field`: the closure adjusts the
///   field's [`FieldType`](horus_ros_msgs::FieldType) in the type description (and so the hash);
///   the Rust type and the wire format stay unbounded.
/// - **Empty request or response** (`request {}`): the struct has no fields (write
///   `NameRequest {}`), but on the wire and in the hash it is rosidl's
///   `uint8 structure_needs_at_least_one_member` (always 0), exactly like
///   `horus_ros_msgs::std_srvs::srv::EmptyRequest`.
/// - **Checked at compile time** (a constant that fails to evaluate, with a message naming the
///   bad name), with rosidl_adapter's rules: the package and field names match
///   `^[a-z][a-z0-9_]*$` without `__` or a trailing `_`, and the service name matches
///   `^[A-Z][A-Za-z0-9]*$`. A raw identifier (`r#type`) is the field `type`.
/// - The type description is built from the fields with
///   [`DescriptionBuilder`](horus_ros_msgs::DescriptionBuilder), so the RIHS01 hashes follow
///   rosidl_generator_type_description; computing them does not panic.
/// - Constants and default values of a `.srv` are not part of it: constants do not enter the
///   hash or the wire (add them in an `impl` block), defaults are not hashed (use `Default`).
#[macro_export]
macro_rules! service {
    // ---- internal rules -------------------------------------------------------------------
    // One definition, package known: split the body into request and response.
    (@define [$pkg:ident] [$($meta:tt)*] $name:ident {
        $(#$req_meta:tt)* request { $($req:tt)* }
        $(#$resp_meta:tt)* response { $($resp:tt)* } $(,)?
    }) => {
        $crate::__private::pastey::paste! {
            $crate::service! { @emit
                [$pkg] [$($meta)*] $name [<$name Request>] [<$name Response>]
                [$(#$req_meta)*] { $($req)* }
                [$(#$resp_meta)*] { $($resp)* }
            }
        }
    };
    (@define [$pkg:ident] [$($meta:tt)*] $name:ident { $($body:tt)* }) => {
        ::core::compile_error!(::core::concat!(
            "service!: the body of `", ::core::stringify!($name),
            "` must be `request { field: Type, … } response { field: Type, … }`"
        ));
    };

    // Everything for one service, with the request/response type names pasted.
    (@emit
        [$pkg:ident] [$($meta:tt)*] $name:ident $req:ident $resp:ident
        [$($req_meta:tt)*] { $($req_fields:tt)* }
        [$($resp_meta:tt)*] { $($resp_fields:tt)* }
    ) => {
        $($meta)*
        #[doc = ""]
        #[doc = ::core::concat!(
            "ROS 2 service type `", ::core::stringify!($pkg), "/srv/", ::core::stringify!($name),
            "` (request [`", ::core::stringify!($req), "`], response [`",
            ::core::stringify!($resp), "`])."
        )]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $name;

        impl $crate::__private::horus_ros_msgs::Service for $name {
            type Request = $req;
            type Response = $resp;
            const TYPE_NAME: &'static str =
                ::core::concat!(::core::stringify!($pkg), "/srv/", ::core::stringify!($name));
        }

        const _: () = {
            ::core::assert!(
                $crate::__private::names::is_valid_package_name(::core::stringify!($pkg)),
                ::core::concat!(
                    "service!: `", ::core::stringify!($pkg), "` is not a valid ROS 2 package name ",
                    "(lowercase letters, digits and `_`, starting with a letter, ",
                    "no `__`, not ending with `_`)"
                )
            );
            ::core::assert!(
                $crate::__private::names::is_valid_type_name(::core::stringify!($name)),
                ::core::concat!(
                    "service!: `", ::core::stringify!($name),
                    "` is not a valid ROS 2 service name ",
                    "(letters and digits, starting with an uppercase letter)"
                )
            );
        };

        $crate::service! { @message $req
            [::core::stringify!($pkg), "/srv/", ::core::stringify!($name), "_Request"]
            ["Request of the ROS 2 service type `", ::core::stringify!($pkg), "/srv/",
                ::core::stringify!($name), "`"]
            [$($req_meta)*] { $($req_fields)* } }
        $crate::service! { @message $resp
            [::core::stringify!($pkg), "/srv/", ::core::stringify!($name), "_Response"]
            ["Response of the ROS 2 service type `", ::core::stringify!($pkg), "/srv/",
                ::core::stringify!($name), "`"]
            [$($resp_meta)*] { $($resp_fields)* } }
    };

    // An empty request or response: rosidl's placeholder byte on the wire and in the hash.
    (@message $ty:ident [$($type_name:tt)+] [$($what:tt)+]
        [$($meta:tt)*] { $(,)? }
    ) => {
        $($meta)*
        #[doc = ""]
        #[doc = ::core::concat!(
            $($what)+, " (empty: sent as rosidl's ",
            "`uint8 structure_needs_at_least_one_member`)."
        )]
        #[derive(Debug, Clone, PartialEq, Default)]
        pub struct $ty {}

        impl $crate::__private::serde::Serialize for $ty {
            fn serialize<__S>(&self, serializer: __S) -> ::core::result::Result<__S::Ok, __S::Error>
            where
                __S: $crate::__private::serde::Serializer,
            {
                use $crate::__private::serde::ser::SerializeStruct as _;
                let mut state = serializer.serialize_struct(::core::stringify!($ty), 1)?;
                state.serialize_field(
                    $crate::__private::horus_ros_msgs::description::EMPTY_STRUCTURE_MEMBER,
                    &0u8,
                )?;
                state.end()
            }
        }

        impl<'de> $crate::__private::serde::Deserialize<'de> for $ty {
            fn deserialize<__D>(deserializer: __D) -> ::core::result::Result<Self, __D::Error>
            where
                __D: $crate::__private::serde::Deserializer<'de>,
            {
                use $crate::__private::serde as __horus_ros_serde;
                #[derive(__horus_ros_serde::Deserialize)]
                #[serde(crate = "__horus_ros_serde")]
                #[allow(dead_code)]
                struct $ty {
                    structure_needs_at_least_one_member: u8,
                }
                <$ty as __horus_ros_serde::Deserialize<'de>>::deserialize(deserializer)?;
                ::core::result::Result::Ok(Self {})
            }
        }

        impl $crate::__private::horus_ros_msgs::Message for $ty {
            const TYPE_NAME: &'static str = ::core::concat!($($type_name)+);

            fn type_description() -> $crate::__private::horus_ros_msgs::TypeDescription {
                // `build` adds `uint8 structure_needs_at_least_one_member` to an empty struct.
                $crate::__private::horus_ros_msgs::DescriptionBuilder::new(
                    <Self as $crate::__private::horus_ros_msgs::Message>::TYPE_NAME,
                )
                .build()
            }
        }
    };

    // A request or response with fields.
    (@message $ty:ident [$($type_name:tt)+] [$($what:tt)+]
        [$($meta:tt)*] {
            $( $(#[$fmeta:meta])* $field:ident : $fty:ty $(=> $modify:expr)? ),+ $(,)?
        }
    ) => {
        // Fields need no doc comments (the seed's definitions have none).
        #[allow(missing_docs)]
        $($meta)*
        #[doc = ""]
        #[doc = ::core::concat!($($what)+, ".")]
        #[derive(Debug, Clone, PartialEq, Default)]
        pub struct $ty {
            $(
                $(#[$fmeta])*
                pub $field: $fty,
            )+
        }

        impl $crate::__private::serde::Serialize for $ty {
            fn serialize<__S>(&self, serializer: __S) -> ::core::result::Result<__S::Ok, __S::Error>
            where
                __S: $crate::__private::serde::Serializer,
            {
                use $crate::__private::serde::ser::SerializeStruct as _;
                let mut state = serializer.serialize_struct(
                    ::core::stringify!($ty),
                    [$(::core::stringify!($field)),+].len(),
                )?;
                $(
                    state.serialize_field(
                        ::core::stringify!($field).trim_start_matches("r#"),
                        &self.$field,
                    )?;
                )+
                state.end()
            }
        }

        impl<'de> $crate::__private::serde::Deserialize<'de> for $ty {
            fn deserialize<__D>(deserializer: __D) -> ::core::result::Result<Self, __D::Error>
            where
                __D: $crate::__private::serde::Deserializer<'de>,
            {
                use $crate::__private::serde as __horus_ros_serde;
                // A field-for-field copy that serde derives for (through the re-exported
                // serde: `#[serde(crate)]` takes a string, where `$crate` cannot be written).
                #[derive(__horus_ros_serde::Deserialize)]
                #[serde(crate = "__horus_ros_serde")]
                struct $ty {
                    $( $field: $fty, )+
                }
                let value =
                    <$ty as __horus_ros_serde::Deserialize<'de>>::deserialize(deserializer)?;
                ::core::result::Result::Ok(Self {
                    $( $field: value.$field, )+
                })
            }
        }

        impl $crate::__private::horus_ros_msgs::Message for $ty {
            const TYPE_NAME: &'static str = ::core::concat!($($type_name)+);

            fn type_description() -> $crate::__private::horus_ros_msgs::TypeDescription {
                let builder = $crate::__private::horus_ros_msgs::DescriptionBuilder::new(
                    <Self as $crate::__private::horus_ros_msgs::Message>::TYPE_NAME,
                );
                $(
                    let builder = builder.field_with::<$fty>(
                        ::core::stringify!($field),
                        $crate::service!(@modify $($modify)?),
                    );
                )+
                builder.build()
            }
        }

        const _: () = {
            $(
                ::core::assert!(
                    $crate::__private::names::is_valid_field_name(::core::stringify!($field)),
                    ::core::concat!(
                        "service!: `", ::core::stringify!($field), "` (in `",
                        ::core::stringify!($ty), "`) is not a valid ROS 2 field name ",
                        "(lowercase letters, digits and `_`, starting with a letter, ",
                        "no `__`, not ending with `_`)"
                    )
                );
            )+
        };
    };
    (@message $ty:ident [$($type_name:tt)+] [$($what:tt)+]
        [$($meta:tt)*] { $($other:tt)* }
    ) => {
        ::core::compile_error!(::core::concat!(
            "service!: expected `field: Type` entries separated by commas in `",
            ::core::stringify!($ty), "`"
        ));
    };

    (@modify) => { |t| t };
    (@modify $modify:expr) => { $modify };

    // ---- public rules ---------------------------------------------------------------------
    () => {};
    ($(#$meta:tt)* $pkg:ident / srv / $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::service! { @define [$pkg] [$(#$meta)*] $name { $($body)* } }
        $crate::service! { $($rest)* }
    };
    ($(#$meta:tt)* $pkg:ident / $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::service! { @define [$pkg] [$(#$meta)*] $name { $($body)* } }
        $crate::service! { $($rest)* }
    };
    ($(#$meta:tt)* $name:ident { $($body:tt)* } $($rest:tt)*) => {
        // The package of services defined without one: `DEFAULT_PACKAGE`.
        $crate::service! { @define [horus_ros] [$(#$meta)*] $name { $($body)* } }
        $crate::service! { $($rest)* }
    };
    ($($other:tt)+) => {
        ::core::compile_error!(
            "service!: expected `Name { request { … } response { … } }` or \
             `package/Name { request { … } response { … } }`"
        );
    };
}

/// Defines ROS 2 message types: a struct implementing [`horus_ros_msgs::Message`] per
/// definition, with the same rules as [`service!`](crate::service!) (the same field grammar,
/// name checks, serde impls and type descriptions), so a message declared here has the RIHS01
/// hash rosidl computes for the same `.msg` file.
///
/// ```
/// horus_ros_services::message! {
///     /// Wheel speeds (horus_ros/msg/MotorCommand).
///     MotorCommand { left_rpm: f32, right_rpm: f32 }
///
///     /// Same definition as `std_msgs/msg/Bool`: the same type, the same hash.
///     std_msgs/Bool { data: bool }
/// }
///
/// use horus_ros_msgs::Message;
/// assert_eq!(MotorCommand::TYPE_NAME, "horus_ros/msg/MotorCommand");
/// assert_eq!(Bool::type_hash(), horus_ros_msgs::std_msgs::msg::Bool::type_hash());
/// let zero = MotorCommand::default();
/// # let _ = zero;
/// ```
///
/// # Grammar
///
/// ```text
/// message! { Definition* }
/// Definition := Attribute* Name '{' Fields '}'
/// Name       := Ident | Ident '/' Ident | Ident '/' 'msg' '/' Ident
/// ```
///
/// A definition without a package is in `horus_ros`. Generated: `pub struct Name { pub fields }`
/// (`Debug, Clone, PartialEq, Default`, serde) with `TYPE_NAME = "pkg/msg/Name"` and DDS type
/// `pkg::msg::dds_::Name_`. `Name {}` is rosidl's empty message (one placeholder byte).
/// Constants and `.msg` default values are not part of it (add constants in an `impl`, and
/// a `Default` of your own is not possible: `Default` is derived).
#[macro_export]
macro_rules! message {
    (@define [$pkg:ident] [$($meta:tt)*] $name:ident { $($fields:tt)* }) => {
        const _: () = {
            ::core::assert!(
                $crate::__private::names::is_valid_package_name(::core::stringify!($pkg)),
                ::core::concat!(
                    "message!: `", ::core::stringify!($pkg), "` is not a valid ROS 2 package name ",
                    "(lowercase letters, digits and `_`, starting with a letter, ",
                    "no `__`, not ending with `_`)"
                )
            );
            ::core::assert!(
                $crate::__private::names::is_valid_type_name(::core::stringify!($name)),
                ::core::concat!(
                    "message!: `", ::core::stringify!($name),
                    "` is not a valid ROS 2 message name ",
                    "(letters and digits, starting with an uppercase letter)"
                )
            );
        };
        $crate::service! { @message $name
            [::core::stringify!($pkg), "/msg/", ::core::stringify!($name)]
            ["ROS 2 message type `", ::core::stringify!($pkg), "/msg/",
                ::core::stringify!($name), "`"]
            [$($meta)*] { $($fields)* } }
    };
    () => {};
    ($(#$meta:tt)* $pkg:ident / msg / $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::message! { @define [$pkg] [$(#$meta)*] $name { $($body)* } }
        $crate::message! { $($rest)* }
    };
    ($(#$meta:tt)* $pkg:ident / $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::message! { @define [$pkg] [$(#$meta)*] $name { $($body)* } }
        $crate::message! { $($rest)* }
    };
    ($(#$meta:tt)* $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::message! { @define [horus_ros] [$(#$meta)*] $name { $($body)* } }
        $crate::message! { $($rest)* }
    };
    ($($other:tt)+) => {
        ::core::compile_error!(
            "message!: expected `Name { field: Type, … }` or `package/Name { field: Type, … }`"
        );
    };
}
