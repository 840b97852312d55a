//! What an interface file defines, after parsing: the model of rosidl_parser `definition.py`
//! (`Message`, `Service`, `Action`, members, constants, annotations), which `.msg`/`.srv`/`.action`
//! (through rosidl_adapter's conversion) and `.idl` files both parse into.

use std::fmt;

/// A primitive type of IDL (rosidl_parser `BASIC_TYPES`) as ROS uses it.
///
/// A `.msg` `char` is `UInt8` and `byte` is `Byte` (rosidl_adapter `MSG_TYPE_TO_IDL`); `Char` and
/// `WChar` come only from `.idl` files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Primitive {
    /// `boolean` (`.msg` `bool`).
    Bool,
    /// `octet` (`.msg` `byte`).
    Byte,
    /// IDL `char` (8 bits).
    Char,
    /// IDL `wchar` (16 bits).
    WChar,
    /// `float` (`.msg` `float32`).
    Float32,
    /// `double` (`.msg` `float64`).
    Float64,
    /// `long double` (no ROS message uses it; described, never encoded).
    LongDouble,
    /// `int8`.
    Int8,
    /// `uint8` (also `.msg` `char`).
    UInt8,
    /// `int16`.
    Int16,
    /// `uint16`.
    UInt16,
    /// `int32`.
    Int32,
    /// `uint32`.
    UInt32,
    /// `int64`.
    Int64,
    /// `uint64`.
    UInt64,
}

impl Primitive {
    /// Bits and signedness of an integer type (`Byte`/`Char` are 8-bit unsigned, `WChar` 16).
    pub fn integer(self) -> Option<(u32, bool)> {
        Some(match self {
            Self::Byte | Self::Char | Self::UInt8 => (8, false),
            Self::Int8 => (8, true),
            Self::WChar | Self::UInt16 => (16, false),
            Self::Int16 => (16, true),
            Self::UInt32 => (32, false),
            Self::Int32 => (32, true),
            Self::UInt64 => (64, false),
            Self::Int64 => (64, true),
            Self::Bool | Self::Float32 | Self::Float64 | Self::LongDouble => return None,
        })
    }

    /// The type's name in `.msg` files (`char`/`wchar` as IDL names them).
    pub fn msg_name(self) -> &'static str {
        match self {
            Self::Bool => "bool",
            Self::Byte => "byte",
            Self::Char => "char",
            Self::WChar => "wchar",
            Self::Float32 => "float32",
            Self::Float64 => "float64",
            Self::LongDouble => "long double",
            Self::Int8 => "int8",
            Self::UInt8 => "uint8",
            Self::Int16 => "int16",
            Self::UInt16 => "uint16",
            Self::Int32 => "int32",
            Self::UInt32 => "uint32",
            Self::Int64 => "int64",
            Self::UInt64 => "uint64",
        }
    }
}

/// A type named by package, namespace and name: `pkg/msg/Name`, `pkg/srv/Name_Request`,
/// `pkg/action/Name_Goal` (rosidl_parser `NamespacedType` with two namespaces).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NamedType {
    /// The package (`geometry_msgs`).
    pub package: String,
    /// `msg`, `srv` or `action`.
    pub namespace: String,
    /// The type's own name (`Point`, `AddTwoInts_Request`).
    pub name: String,
}

impl NamedType {
    /// `package/namespace/name`.
    pub fn new(package: &str, namespace: &str, name: &str) -> Self {
        Self {
            package: package.to_owned(),
            namespace: namespace.to_owned(),
            name: name.to_owned(),
        }
    }

    /// A type of the same package and namespace with `suffix` appended (`Name` → `Name_Request`).
    pub fn with_suffix(&self, suffix: &str) -> Self {
        Self::new(
            &self.package,
            &self.namespace,
            &format!("{}{suffix}", self.name),
        )
    }
}

impl fmt::Display for NamedType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}/{}", self.package, self.namespace, self.name)
    }
}

/// What one value of a field is.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum BaseType {
    /// A primitive.
    Primitive(Primitive),
    /// `string`, or `string<=N` (`Some(N)`).
    String(Option<u64>),
    /// `wstring`, or `wstring<=N`.
    WString(Option<u64>),
    /// A message type.
    Named(NamedType),
}

/// Single value, array or sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Container {
    /// One value.
    Single,
    /// `T[N]`.
    Array(u64),
    /// `T[]`.
    UnboundedSequence,
    /// `T[<=N]`.
    BoundedSequence(u64),
}

/// The type of a field or constant.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct FieldType {
    /// One value's type.
    pub base: BaseType,
    /// How many.
    pub container: Container,
}

impl FieldType {
    /// One value of `base`.
    pub fn single(base: BaseType) -> Self {
        Self {
            base,
            container: Container::Single,
        }
    }
}

/// A literal value as the interface file gives it (after rosidl's parsing: a `.msg` `bool`
/// default `1` is `Bool(true)`).
#[derive(Clone, Debug, PartialEq)]
pub enum Literal {
    /// `true`/`false`.
    Bool(bool),
    /// An integer (every integer type, `byte` and `char`).
    Int(i128),
    /// A floating-point number.
    Float(f64),
    /// A string (escapes resolved).
    String(String),
}

/// A field's default value: one literal, or the elements of an array/sequence.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// For a single value.
    Scalar(Literal),
    /// For an array or sequence.
    Array(Vec<Literal>),
}

/// One field (rosidl_parser `Member`).
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The field's name.
    pub name: String,
    /// Its type.
    pub ty: FieldType,
    /// Its default value (`@default`), if any.
    pub default: Option<Value>,
    /// Its comment lines (`@verbatim (language="comment")`), unit removed.
    pub comment: Vec<String>,
    /// Its unit (`@unit`), from a `[unit]` in a `.msg` comment.
    pub unit: Option<String>,
}

/// A constant (rosidl_parser `Constant`).
#[derive(Clone, Debug, PartialEq)]
pub struct Constant {
    /// The constant's name.
    pub name: String,
    /// Its type: a primitive or (bounded) string, never a container.
    pub ty: BaseType,
    /// Its value.
    pub value: Literal,
    /// Its comment lines.
    pub comment: Vec<String>,
}

/// A message: a struct with fields and constants (rosidl_parser `Message`).
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    /// `pkg/msg/Name` (or a service's/action's part, `pkg/srv/Name_Request`).
    pub name: NamedType,
    /// Fields in order. Empty for a struct without fields: descriptions and code add rosidl's
    /// placeholder member.
    pub fields: Vec<Field>,
    /// Constants in order.
    pub constants: Vec<Constant>,
    /// The message's comment lines (a `.msg` file's leading comment block).
    pub comment: Vec<String>,
}

/// A service: request and response (rosidl_parser `Service`; the `_Event` message is derived).
#[derive(Clone, Debug, PartialEq)]
pub struct Service {
    /// `pkg/srv/Name` (or an action's `pkg/action/Name_SendGoal`).
    pub name: NamedType,
    /// `Name_Request`.
    pub request: Message,
    /// `Name_Response`.
    pub response: Message,
}

/// An action: goal, result and feedback (rosidl_parser `Action`; the services and the feedback
/// message rcl_action uses are derived).
#[derive(Clone, Debug, PartialEq)]
pub struct Action {
    /// `pkg/action/Name`.
    pub name: NamedType,
    /// `Name_Goal`.
    pub goal: Message,
    /// `Name_Result`.
    pub result: Message,
    /// `Name_Feedback`.
    pub feedback: Message,
}

/// What one interface file defines.
#[derive(Clone, Debug, PartialEq)]
pub enum Interface {
    /// A `.msg` (or an `.idl` with one struct in `module msg`).
    Message(Message),
    /// A `.srv`.
    Service(Service),
    /// An `.action`.
    Action(Action),
}

impl Interface {
    /// The interface's type name (`pkg/msg/Name`, `pkg/srv/Name`, `pkg/action/Name`).
    pub fn name(&self) -> &NamedType {
        match self {
            Self::Message(m) => &m.name,
            Self::Service(s) => &s.name,
            Self::Action(a) => &a.name,
        }
    }
}
