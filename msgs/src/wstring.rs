//! [`WString`]: a ROS `wstring` (IDL `wstring`, C++ `std::u16string`)
//! (CDR layout in [`WString`]'s docs).

use std::fmt;
use std::ops::Deref;

use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeSeq;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A ROS `wstring`: text that travels as UTF-16 code units. A `wstring<=N` bound counts UTF-16
/// units ([`WString::utf16_len`]).
///
/// On the wire (plain CDR, XCDR1) a `wstring` is a `uint32` count of UTF-16 code units, then each
/// unit widened to a 4-byte `uint32`, with no terminator. Both Jazzy RMWs write it so:
/// rosidl_typesupport_fastrtps_c and _cpp (`serialization_helpers.hpp`, `cdr_serialize(cdr,
/// u16string)`: "We are serializing a uint32_t for interoperability with other DDS-based
/// implementations") and rmw_cyclonedds_cpp (`Serialization.cpp`, `CDR_Legacy`:
/// `serialize_u32(size)`, then each unit as a 4-byte `wchar_t`); checked against rclpy's
/// `serialize_message` in tests/runtime.rs. A reader rejects a unit above `0xFFFF` (Fast DDS's
/// `cdr_deserialize` throws "Character value exceeds maximum value"); this one also rejects
/// unpaired surrogates, which a Rust [`String`] cannot hold.
///
/// A lone `wchar` is different: 2 bytes, aligned to 2 (a `u16` in Rust). The typesupports write
/// `cdr << static_cast<wchar_t>(…)` and Fast CDR's `serialize(wchar_t)` writes a `uint16_t`;
/// rmw_cyclonedds gives `WCHAR` a CDR size of 2.
///
/// In human-readable formats (JSON) a `WString` is a plain string.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct WString(pub String);

impl WString {
    /// The length in UTF-16 code units (what a `wstring<=N` bound and the CDR count measure).
    pub fn utf16_len(&self) -> usize {
        self.0.encode_utf16().count()
    }
}

impl From<String> for WString {
    fn from(s: String) -> Self {
        WString(s)
    }
}

impl From<&str> for WString {
    fn from(s: &str) -> Self {
        WString(s.to_owned())
    }
}

impl From<WString> for String {
    fn from(w: WString) -> Self {
        w.0
    }
}

impl Deref for WString {
    type Target = str;
    fn deref(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for WString {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl Serialize for WString {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if serializer.is_human_readable() {
            return serializer.serialize_str(&self.0);
        }
        let count = self.utf16_len();
        if u32::try_from(count).is_err() {
            return Err(serde::ser::Error::custom(format_args!(
                "wstring of {count} UTF-16 units does not fit a CDR length"
            )));
        }
        // A CDR sequence of uint32: the count, then one 4-byte value per unit.
        let mut seq = serializer.serialize_seq(Some(count))?;
        for unit in self.0.encode_utf16() {
            seq.serialize_element(&u32::from(unit))?;
        }
        seq.end()
    }
}

impl<'de> Deserialize<'de> for WString {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        if deserializer.is_human_readable() {
            return String::deserialize(deserializer).map(WString);
        }
        deserializer.deserialize_seq(Utf16Units)
    }
}

/// Reads a CDR `wstring` body: `uint32` units, each at most `0xFFFF`, decoded as UTF-16.
struct Utf16Units;

/// Units reserved before reading: a count read from the wire is not trusted for allocation.
const MAX_PREALLOCATED_UNITS: usize = 4096;

impl<'de> Visitor<'de> for Utf16Units {
    type Value = WString;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a wstring (a sequence of UTF-16 code units)")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<WString, A::Error> {
        let hint = seq.size_hint().unwrap_or(0).min(MAX_PREALLOCATED_UNITS);
        let mut units = Vec::with_capacity(hint);
        while let Some(unit) = seq.next_element::<u32>()? {
            let unit = u16::try_from(unit).map_err(|_| {
                de::Error::custom(format_args!(
                    "wstring character {unit:#x} exceeds the UTF-16 unit range"
                ))
            })?;
            units.push(unit);
        }
        String::from_utf16(&units)
            .map(WString)
            .map_err(|_| de::Error::custom("wstring is not valid UTF-16 (unpaired surrogate)"))
    }
}
