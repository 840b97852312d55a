//! [`TypeHash`]: a REP-2011 type hash (`RIHS01_<64 hex>`).
//!
//! Layout follows rosidl_runtime_c (jazzy) `type_hash.h` (`rosidl_type_hash_t { uint8 version;
//! uint8 value[32]; }`); string form and parsing follow `type_hash.c`
//! (`rosidl_stringify_type_hash`, `rosidl_parse_type_hash_string`).

use std::fmt;
use std::str::FromStr;

/// Size of a RIHS01 hash value in bytes (`ROSIDL_TYPE_HASH_SIZE`).
pub const TYPE_HASH_SIZE: usize = 32;

/// A REP-2011 type hash: a version (1 for RIHS01; 0 = unset) and a 32-byte SHA-256 value.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct TypeHash {
    /// RIHS version; `0` means unset (`ROSIDL_TYPE_HASH_VERSION_UNSET`).
    pub version: u8,
    /// The hash value.
    pub value: [u8; TYPE_HASH_SIZE],
}

/// Why a type hash string could not be parsed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TypeHashError {
    /// The string does not start with `RIHS`.
    #[error("type hash string does not start with RIHS")]
    MissingPrefix,
    /// The two version characters are not hex digits.
    #[error("RIHS version is not a 2-digit hex string")]
    BadVersion,
    /// A version other than 1.
    #[error("unsupported RIHS version {0}")]
    UnsupportedVersion(u8),
    /// The string is not exactly 71 characters long.
    #[error("RIHS01 string must be 71 characters, got {0}")]
    BadLength(usize),
    /// The value contains a non-hex character.
    #[error("type hash value contains a non-hex character")]
    BadHexDigit,
    /// The USER_DATA `typehash` value is not valid UTF-8.
    #[error("type hash in USER_DATA is not valid UTF-8")]
    NotUtf8,
}

const PREFIX: &str = "RIHS01_";
const STRING_LEN: usize = PREFIX.len() + 2 * TYPE_HASH_SIZE;

impl TypeHash {
    /// The unset hash (version 0, all zero), as `rosidl_get_zero_initialized_type_hash`.
    pub const ZERO: TypeHash = TypeHash {
        version: 0,
        value: [0; TYPE_HASH_SIZE],
    };

    /// A RIHS01 hash from its 32-byte value.
    pub const fn rihs01(value: [u8; TYPE_HASH_SIZE]) -> Self {
        Self { version: 1, value }
    }

    /// True unless this is the unset hash (version 0).
    pub const fn is_set(&self) -> bool {
        self.version != 0
    }

    /// Parses `RIHS01_<64 hex>` (as `rosidl_parse_type_hash_string`: hex digits of either case).
    pub fn parse(s: &str) -> Result<Self, TypeHashError> {
        let b = s.as_bytes();
        if b.len() < PREFIX.len() {
            return Err(TypeHashError::BadLength(b.len()));
        }
        if &b[..4] != b"RIHS" {
            return Err(TypeHashError::MissingPrefix);
        }
        let version = match (nibble(b[4]), nibble(b[5])) {
            (Some(h), Some(l)) => (h << 4) | l,
            _ => return Err(TypeHashError::BadVersion),
        };
        if version != 1 {
            return Err(TypeHashError::UnsupportedVersion(version));
        }
        // rosidl_parse_type_hash_string does not check the '_' separator; we do.
        if b.len() != STRING_LEN {
            return Err(TypeHashError::BadLength(b.len()));
        }
        if b[6] != b'_' {
            return Err(TypeHashError::MissingPrefix);
        }
        let mut value = [0u8; TYPE_HASH_SIZE];
        for (i, pair) in b[PREFIX.len()..].chunks_exact(2).enumerate() {
            match (nibble(pair[0]), nibble(pair[1])) {
                (Some(h), Some(l)) => value[i] = (h << 4) | l,
                _ => return Err(TypeHashError::BadHexDigit),
            }
        }
        Ok(Self { version, value })
    }

    /// The USER_DATA entry `typehash=RIHS01_…;`, or an empty string for the unset hash
    /// (rmw_dds_common jazzy `qos.cpp` `encode_type_hash_for_user_data_qos`).
    pub fn to_user_data(&self) -> String {
        if !self.is_set() {
            return String::new();
        }
        format!("typehash={self};")
    }

    /// The value as 64 lower-case hex characters.
    pub fn hex_value(&self) -> String {
        use fmt::Write;
        let mut s = String::with_capacity(2 * TYPE_HASH_SIZE);
        for b in &self.value {
            let _ = write!(s, "{b:02x}");
        }
        s
    }
}

fn nibble(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'a'..=b'f' => Some(c - b'a' + 10),
        b'A'..=b'F' => Some(c - b'A' + 10),
        _ => None,
    }
}

/// `RIHS<version as 2 hex>_<64 lower-case hex>`; `RIHS01_…` for every RIHS01 hash.
impl fmt::Display for TypeHash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "RIHS{:02x}_{}", self.version, self.hex_value())
    }
}

impl fmt::Debug for TypeHash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "TypeHash({self})")
    }
}

impl FromStr for TypeHash {
    type Err = TypeHashError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s)
    }
}

/// Serialized as its RIHS string: ROS messages carry type hashes as `string`
/// (type_description_interfaces/srv/GetTypeDescription `string type_hash`).
impl serde::Serialize for TypeHash {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for TypeHash {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        Self::parse(&s).map_err(serde::de::Error::custom)
    }
}
