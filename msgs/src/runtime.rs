//! Support for generated message structs: bound checks at encode ([`Bounded`]), fixed arrays of
//! any length ([`mod@array`], [`default_array`]).
//!
//! A generated struct derives `Deserialize` and implements `Serialize` by hand, wrapping every
//! field in a [`Bounded`] so that `string<=N`, `wstring<=N` and `T[<=N]` are checked while the
//! message is encoded:
//!
//! ```
//! use horus_ros_msgs::runtime::Bounded;
//! use serde::ser::{Serialize, SerializeStruct, Serializer};
//!
//! /// `string<=8 name` and `int32[<=2] values`.
//! struct Named {
//!     name: String,
//!     values: Vec<i32>,
//! }
//!
//! impl Serialize for Named {
//!     fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
//!         let mut s = serializer.serialize_struct("Named", 2)?;
//!         s.serialize_field("name", &Bounded::new(&self.name, "name", Some(8), None))?;
//!         s.serialize_field("values", &Bounded::new(&self.values, "values", None, Some(2)))?;
//!         s.end()
//!     }
//! }
//!
//! let long = Named { name: "much too long".into(), values: vec![] };
//! let err = horus_ros_msgs::cdr::to_cdr(&long).unwrap_err();
//! assert_eq!(err.to_string(), "field 'name': string of 13 bytes exceeds its bound of 8 bytes");
//! ```
//!
//! The checks are those of rosidl's C++ types (rosidl_runtime_cpp `BoundedVector` and the
//! `BoundedBasicString` of `std::string` / `std::u16string`, which count `size()`): a `string<=N`
//! holds at most N UTF-8 bytes, a `wstring<=N` at most N UTF-16 units, a `T[<=N]` at most N
//! elements (rosidl_typesupport_fastrtps_cpp `msg__type_support.cpp.em` throws "array size exceeds
//! upper bound" for the last).
//!
//! A violation makes the serializer fail with `S::Error::custom(…)` and leaves a typed
//! [`BoundError`] in a thread-local slot, with the path of the field (`poses[2].header.frame_id`)
//! completed as the error travels up through enclosing [`Bounded`] values. [`crate::cdr::to_cdr`]
//! and [`crate::cdr::to_cdr_body`] turn it into [`CdrError::BoundExceeded`]; other encoders can
//! fetch it with [`take_bound_error`].
//!
//! [`CdrError::BoundExceeded`]: crate::cdr::CdrError::BoundExceeded

use std::cell::RefCell;
use std::fmt;

use serde::ser::{SerializeSeq, SerializeTuple};
use serde::{Serialize, Serializer};

use crate::field::Byte;
use crate::message::Message;
use crate::wstring::WString;

/// Which bound a value exceeded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BoundKind {
    /// `string<=N`: the length is in UTF-8 bytes.
    String,
    /// `wstring<=N`: the length is in UTF-16 code units.
    WString,
    /// `T[<=N]`: the length is in elements.
    Sequence,
}

impl BoundKind {
    /// What the length counts: `bytes`, `UTF-16 units` or `elements`.
    pub fn unit(self) -> &'static str {
        match self {
            BoundKind::String => "bytes",
            BoundKind::WString => "UTF-16 units",
            BoundKind::Sequence => "elements",
        }
    }
}

impl fmt::Display for BoundKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BoundKind::String => "string",
            BoundKind::WString => "wstring",
            BoundKind::Sequence => "sequence",
        })
    }
}

/// A bounded field holds more than its bound allows; the message is not encoded.
#[derive(Clone, Debug, PartialEq, Eq, Hash, thiserror::Error)]
#[error("field '{field}': {kind} of {length} {} exceeds its bound of {bound} {}", kind.unit(), kind.unit())]
pub struct BoundError {
    /// The field's path from the encoded message: `name`, `names[3]`, `poses[2].header.frame_id`.
    pub field: String,
    /// Which bound.
    pub kind: BoundKind,
    /// The bound (`N` of `string<=N`, `wstring<=N`, `T[<=N]`).
    pub bound: u64,
    /// The value's length, in the bound's unit ([`BoundKind::unit`]).
    pub length: u64,
}

thread_local! {
    /// The bound violation of the encode in progress on this thread, if any.
    static PENDING: RefCell<Option<BoundError>> = const { RefCell::new(None) };
}

/// Takes (and clears) the [`BoundError`] left by the last failed encode on this thread.
///
/// [`crate::cdr::to_cdr`] and [`crate::cdr::to_cdr_body`] call it themselves; an encoder that
/// serializes with another serde serializer calls it before encoding (to drop a stale one) and
/// after a failure.
pub fn take_bound_error() -> Option<BoundError> {
    PENDING.with_borrow_mut(Option::take)
}

/// One step of a field path.
enum Segment<'a> {
    /// A field name.
    Name(&'a str),
    /// An element index.
    Index(usize),
}

/// Puts `segment` in front of the pending error's path (no-op without one).
fn prefix_pending(segment: Segment<'_>) {
    PENDING.with_borrow_mut(|pending| {
        if let Some(err) = pending {
            let rest = std::mem::take(&mut err.field);
            let sep = if rest.is_empty() || rest.starts_with('[') {
                ""
            } else {
                "."
            };
            err.field = match segment {
                Segment::Name(name) => format!("{name}{sep}{rest}"),
                Segment::Index(i) => format!("[{i}]{sep}{rest}"),
            };
        }
    });
}

/// A field value with its bounds, serialized with checks (see the [module docs](self)).
///
/// Elements of a `Vec<T>` / `[T; N]` are serialized as `Bounded<T>` with the same string bound
/// and no sequence bound (a `string<=5[<=3]` checks every string against 5).
pub struct Bounded<'a, T: ?Sized> {
    /// The value.
    value: &'a T,
    /// The field name (for errors).
    field: &'static str,
    /// `N` of `string<=N` / `wstring<=N` (of the value or of its elements).
    string_bound: Option<u64>,
    /// `N` of `T[<=N]`.
    sequence_bound: Option<u64>,
    /// An element of a sequence or array: its container names the path, not this value.
    element: bool,
}

impl<'a, T: ?Sized> Bounded<'a, T> {
    /// Wraps field `field`'s value with its bounds: `string_bound` for `string<=N` /
    /// `wstring<=N` (also of a sequence's or array's elements), `sequence_bound` for `T[<=N]`.
    pub fn new(
        value: &'a T,
        field: &'static str,
        string_bound: Option<u64>,
        sequence_bound: Option<u64>,
    ) -> Self {
        Self {
            value,
            field,
            string_bound,
            sequence_bound,
            element: false,
        }
    }

    /// An element of this container's value.
    fn element<E: ?Sized>(&self, value: &'a E) -> Bounded<'a, E> {
        Bounded {
            value,
            field: self.field,
            string_bound: self.string_bound,
            sequence_bound: None,
            element: true,
        }
    }

    /// Records a violation and returns the serializer's error for it.
    fn exceeded<E: serde::ser::Error>(&self, kind: BoundKind, bound: u64, length: usize) -> E {
        let mut err = BoundError {
            field: self.field.to_owned(),
            kind,
            bound,
            length: u64::try_from(length).unwrap_or(u64::MAX),
        };
        let serializer_error = E::custom(&err);
        // The path is built while the error travels up (see `finish`).
        err.field.clear();
        PENDING.set(Some(err));
        serializer_error
    }

    /// Checks `length` (in `kind`'s unit) against `bound`.
    fn check<E: serde::ser::Error>(
        &self,
        kind: BoundKind,
        bound: Option<u64>,
        length: usize,
    ) -> Result<(), E> {
        match bound {
            Some(bound) if u64::try_from(length).map_or(true, |len| len > bound) => {
                Err(self.exceeded(kind, bound, length))
            }
            _ => Ok(()),
        }
    }

    /// Adds this field's name to the path of a violation found inside it.
    fn finish<R, E>(&self, result: Result<R, E>) -> Result<R, E> {
        if result.is_err() && !self.element {
            prefix_pending(Segment::Name(self.field));
        }
        result
    }

    /// Serializes `items` as elements (`Bounded<E>`), naming the failing element's index.
    fn elements<E, Err>(
        &self,
        items: &'a [E],
        mut put: impl FnMut(&Bounded<'a, E>) -> Result<(), Err>,
    ) -> Result<(), Err> {
        for (i, item) in items.iter().enumerate() {
            if let Err(e) = put(&self.element(item)) {
                prefix_pending(Segment::Index(i));
                return Err(e);
            }
        }
        Ok(())
    }

    /// The same field (name, bounds, place) viewed as another type (`String` as `str`).
    fn view<U: ?Sized>(&self, value: &'a U) -> Bounded<'a, U> {
        Bounded {
            value,
            field: self.field,
            string_bound: self.string_bound,
            sequence_bound: self.sequence_bound,
            element: self.element,
        }
    }
}

impl<T: ?Sized> Clone for Bounded<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: ?Sized> Copy for Bounded<'_, T> {}

impl<T: ?Sized + fmt::Debug> fmt::Debug for Bounded<'_, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Bounded")
            .field("value", &self.value)
            .field("field", &self.field)
            .field("string_bound", &self.string_bound)
            .field("sequence_bound", &self.sequence_bound)
            .finish()
    }
}

/// Plain values: no bound applies.
macro_rules! unbounded {
    ($($t:ty),* $(,)?) => {
        $(
            impl Serialize for Bounded<'_, $t> {
                fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                    self.value.serialize(serializer)
                }
            }
        )*
    };
}

unbounded!(bool, i8, u8, i16, u16, i32, u32, i64, u64, f32, f64, Byte);

impl Serialize for Bounded<'_, str> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let result = self
            .check(BoundKind::String, self.string_bound, self.value.len())
            .and_then(|()| serializer.serialize_str(self.value));
        self.finish(result)
    }
}

impl Serialize for Bounded<'_, String> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.view(self.value.as_str()).serialize(serializer)
    }
}

impl Serialize for Bounded<'_, WString> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        // Counting UTF-16 units walks the text: only for a bounded wstring.
        let checked = match self.string_bound {
            Some(_) => self.check(
                BoundKind::WString,
                self.string_bound,
                self.value.utf16_len(),
            ),
            None => Ok(()),
        };
        let result = checked.and_then(|()| self.value.serialize(serializer));
        self.finish(result)
    }
}

/// A nested message: its own `Serialize` checks its fields.
impl<M: Message> Serialize for Bounded<'_, M> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let result = self.value.serialize(serializer);
        self.finish(result)
    }
}

/// A sequence (`T[]`, `T[<=N]`): `uint32` count, then the elements.
impl<'a, T> Serialize for Bounded<'a, [T]>
where
    Bounded<'a, T>: Serialize,
{
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let result = self
            .check(BoundKind::Sequence, self.sequence_bound, self.value.len())
            .and_then(|()| serializer.serialize_seq(Some(self.value.len())))
            .and_then(|mut seq| {
                self.elements(self.value, |e| seq.serialize_element(e))?;
                seq.end()
            });
        self.finish(result)
    }
}

/// A sequence (`T[]`, `T[<=N]`): `uint32` count, then the elements.
impl<'a, T> Serialize for Bounded<'a, Vec<T>>
where
    Bounded<'a, T>: Serialize,
{
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.view(self.value.as_slice()).serialize(serializer)
    }
}

/// A fixed array (`T[N]`, any `N`): the `N` elements, no count.
impl<'a, T, const N: usize> Serialize for Bounded<'a, [T; N]>
where
    Bounded<'a, T>: Serialize,
{
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let result = serializer.serialize_tuple(N).and_then(|mut tuple| {
            self.elements(self.value.as_slice(), |e| tuple.serialize_element(e))?;
            tuple.end()
        });
        self.finish(result)
    }
}

/// `uint8[]` / `char[]` sequences (Rust `Vec<u8>`) as one block of bytes: CDR's
/// `sequence<octet>` is a 4-aligned `u32` length and the bytes, which serde's `bytes` calls give
/// at once (a memory copy) where a sequence of `u8` goes element by element (a 6 MB image:
/// milliseconds). The same bytes on the wire either way.
pub mod bytes {
    use serde::{Deserialize, Deserializer};

    /// `value` serialized as bytes.
    pub fn as_bytes(value: &[u8]) -> &serde_bytes::Bytes {
        serde_bytes::Bytes::new(value)
    }

    /// Deserializes bytes (or, from formats without them, a sequence of `u8`).
    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<u8>, D::Error> {
        serde_bytes::ByteBuf::deserialize(deserializer).map(serde_bytes::ByteBuf::into_vec)
    }
}

/// `#[serde(with = "::horus_ros_msgs::runtime::array")]` for `[T; N]` of any `N` (serde's own
/// impls stop at 32): a fixed array is a tuple of `N` elements (no count in CDR).
pub mod array {
    use std::fmt;
    use std::marker::PhantomData;

    use serde::de::{self, Deserialize, Deserializer, SeqAccess, Visitor};
    use serde::ser::{Serialize, SerializeTuple, Serializer};

    /// Serializes `value` as a tuple of `N` elements.
    pub fn serialize<S, T, const N: usize>(value: &[T; N], serializer: S) -> Result<S::Ok, S::Error>
    where
        S: Serializer,
        T: Serialize,
    {
        let mut tuple = serializer.serialize_tuple(N)?;
        for item in value {
            tuple.serialize_element(item)?;
        }
        tuple.end()
    }

    /// Deserializes a tuple of exactly `N` elements.
    pub fn deserialize<'de, D, T, const N: usize>(deserializer: D) -> Result<[T; N], D::Error>
    where
        D: Deserializer<'de>,
        T: Deserialize<'de>,
    {
        deserializer.deserialize_tuple(N, ArrayVisitor(PhantomData))
    }

    /// Collects `N` elements.
    struct ArrayVisitor<T, const N: usize>(PhantomData<T>);

    impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for ArrayVisitor<T, N> {
        type Value = [T; N];

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "an array of {N} elements")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[T; N], A::Error> {
            let mut items = Vec::with_capacity(N);
            for i in 0..N {
                match seq.next_element()? {
                    Some(item) => items.push(item),
                    None => return Err(de::Error::invalid_length(i, &self)),
                }
            }
            items
                .try_into()
                .map_err(|_| de::Error::invalid_length(N, &self))
        }
    }
}

/// `[T::default(); N]` for any `N` (for `Default` of structs with long arrays).
pub fn default_array<T: Default, const N: usize>() -> [T; N] {
    std::array::from_fn(|_| T::default())
}
