//! [`RosField`]: how a Rust field type maps to a ROS [`FieldType`], so descriptions can be built
//! generically from struct fields.
//!
//! Mapping follows rosidl_generator_type_description (jazzy) `__init__.py` (`FIELD_VALUE_TYPE_NAMES`,
//! `NESTED_FIELD_TYPE_SUFFIXES`, `serialize_field_type`) after rosidl_adapter's `.msg` → IDL
//! conversion (`MSG_TYPE_TO_IDL`):
//!
//! | `.msg` | IDL | Rust | type id |
//! |---|---|---|---|
//! | `bool` | `boolean` | `bool` | BOOLEAN |
//! | `byte` | `octet` | [`Byte`] | BYTE |
//! | `char` | `uint8` | `u8` | UINT8 (so `char[16]` = `[u8; 16]` = UINT8_ARRAY) |
//! | `int8`…`uint64` | same | `i8`…`u64` | INT8…UINT64 |
//! | `float32`/`float64` | `float`/`double` | `f32`/`f64` | FLOAT/DOUBLE |
//! | `string` | `string` | `String` | STRING |
//! | `wstring` | `wstring` | [`WString`] | WSTRING |
//! | — | `wchar` | `u16` | WCHAR (a `u16` describes itself as UINT16: override the type id) |
//! | `T[]` / `T[N]` | sequence / array | `Vec<T>` / `[T; N]` | +144 / +48 |
//!
//! Bounds (`string<=N`, `T[<=N]`) are not visible in Rust types: apply
//! [`FieldType::bounded_string`] / [`FieldType::bounded_sequence`] in the description.

use serde::{Deserialize, Serialize};

use crate::message::Message;
use crate::type_description_interfaces::msg::{FieldType, IndividualTypeDescription};
use crate::wstring::WString;

/// A Rust type usable as a field of a ROS message.
pub trait RosField {
    /// The field's type as rosidl describes it.
    fn field_type() -> FieldType;
    /// Appends every type this field references (nested messages, recursively); may repeat.
    fn referenced_types(_out: &mut Vec<IndividualTypeDescription>) {}
}

/// Offset of fixed-size arrays in the type-id space (`FIELD_TYPE_*_ARRAY` = base + 48).
const ARRAY_OFFSET: u8 = 48;
/// Offset of bounded sequences (base + 96).
const BOUNDED_SEQUENCE_OFFSET: u8 = 96;
/// Offset of unbounded sequences (base + 144).
const UNBOUNDED_SEQUENCE_OFFSET: u8 = 144;

impl FieldType {
    /// A field type with only its id set.
    pub const fn of(type_id: u8) -> Self {
        Self {
            type_id,
            capacity: 0,
            string_capacity: 0,
            nested_type_name: String::new(),
        }
    }

    /// A nested message type (`FIELD_TYPE_NESTED_TYPE`).
    pub fn nested(type_name: &str) -> Self {
        Self {
            nested_type_name: type_name.to_owned(),
            ..Self::of(Self::FIELD_TYPE_NESTED_TYPE)
        }
    }

    /// Splits the id into (element id, container offset 0/48/96/144).
    fn split_id(&self) -> (u8, u8) {
        match self.type_id {
            145..=192 => (
                self.type_id - UNBOUNDED_SEQUENCE_OFFSET,
                UNBOUNDED_SEQUENCE_OFFSET,
            ),
            97..=144 => (
                self.type_id - BOUNDED_SEQUENCE_OFFSET,
                BOUNDED_SEQUENCE_OFFSET,
            ),
            49..=96 => (self.type_id - ARRAY_OFFSET, ARRAY_OFFSET),
            id => (id, 0),
        }
    }

    /// Makes a string (or string array/sequence) bounded: `string<=n` (`STRING` → `BOUNDED_STRING`,
    /// `string_capacity = n`).
    pub fn bounded_string(mut self, n: u64) -> Self {
        let (elem, offset) = self.split_id();
        if elem == Self::FIELD_TYPE_STRING || elem == Self::FIELD_TYPE_WSTRING {
            self.type_id = elem + 4 + offset;
            self.string_capacity = n;
        }
        self
    }

    /// Makes an unbounded sequence bounded: `T[<=n]` (`capacity = n`).
    pub fn bounded_sequence(mut self, n: u64) -> Self {
        let (elem, offset) = self.split_id();
        if offset == UNBOUNDED_SEQUENCE_OFFSET {
            self.type_id = elem + BOUNDED_SEQUENCE_OFFSET;
            self.capacity = n;
        }
        self
    }

    /// This element type as a container (`offset` 48/144), with a capacity.
    fn container(mut self, offset: u8, capacity: u64) -> Self {
        // Elements are always plain (offset 0) here: ROS has no nested containers.
        self.type_id = self.type_id.saturating_add(offset);
        self.capacity = capacity;
        self
    }
}

macro_rules! primitive_field {
    ($($t:ty => $id:ident),* $(,)?) => {
        $(
            impl RosField for $t {
                fn field_type() -> FieldType {
                    FieldType::of(FieldType::$id)
                }
            }
        )*
    };
}

primitive_field! {
    bool => FIELD_TYPE_BOOLEAN,
    i8 => FIELD_TYPE_INT8,
    u8 => FIELD_TYPE_UINT8,
    i16 => FIELD_TYPE_INT16,
    u16 => FIELD_TYPE_UINT16,
    i32 => FIELD_TYPE_INT32,
    u32 => FIELD_TYPE_UINT32,
    i64 => FIELD_TYPE_INT64,
    u64 => FIELD_TYPE_UINT64,
    f32 => FIELD_TYPE_FLOAT,
    f64 => FIELD_TYPE_DOUBLE,
    String => FIELD_TYPE_STRING,
    WString => FIELD_TYPE_WSTRING,
    Byte => FIELD_TYPE_BYTE,
}

/// A ROS `byte` (IDL `octet`): one byte on the wire like `u8`, but described as `FIELD_TYPE_BYTE`
/// (so `byte[]` hashes differently from `uint8[]`). ROS `char` is `u8` (rosidl maps it to `uint8`).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize,
)]
#[serde(transparent)]
pub struct Byte(pub u8);

impl From<u8> for Byte {
    fn from(b: u8) -> Self {
        Byte(b)
    }
}

impl From<Byte> for u8 {
    fn from(b: Byte) -> Self {
        b.0
    }
}

impl<T: RosField> RosField for Vec<T> {
    fn field_type() -> FieldType {
        T::field_type().container(UNBOUNDED_SEQUENCE_OFFSET, 0)
    }
    fn referenced_types(out: &mut Vec<IndividualTypeDescription>) {
        T::referenced_types(out)
    }
}

impl<T: RosField, const N: usize> RosField for [T; N] {
    fn field_type() -> FieldType {
        T::field_type().container(ARRAY_OFFSET, N as u64)
    }
    fn referenced_types(out: &mut Vec<IndividualTypeDescription>) {
        T::referenced_types(out)
    }
}

impl<T: Message> RosField for T {
    fn field_type() -> FieldType {
        FieldType::nested(T::TYPE_NAME)
    }
    fn referenced_types(out: &mut Vec<IndividualTypeDescription>) {
        let d = T::type_description();
        out.push(d.type_description);
        out.extend(d.referenced_type_descriptions);
    }
}
