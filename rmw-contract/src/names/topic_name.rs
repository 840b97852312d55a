//! Fully-qualified ROS 2 topic names.
//!
//! Rules and messages follow rmw `src/validate_full_topic_name.c` and
//! `include/rmw/validate_full_topic_name.h` (ros2/rmw, jazzy).

use super::macros::impl_validated_name;

/// Longest DDS topic name the RMW implementations accept (rmw's "impl
/// constraint" 255; Fast DDS stores topic names in a `string_255`).
pub const DDS_TOPIC_NAME_MAX_LENGTH: usize = 255;

/// Longest valid fully-qualified topic or service name in bytes:
/// rmw `RMW_TOPIC_MAX_NAME_LENGTH` = 255 minus 8 reserved for prefixes = 247.
pub const TOPIC_NAME_MAX_LENGTH: usize = DDS_TOPIC_NAME_MAX_LENGTH - 8;

/// Why a string is not a valid fully-qualified topic (or service) name
/// (rmw `RMW_TOPIC_INVALID_*`). Indices are byte offsets, as rmw's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TopicNameError {
    /// `RMW_TOPIC_INVALID_IS_EMPTY_STRING`.
    #[error("topic name must not be empty")]
    Empty,
    /// `RMW_TOPIC_INVALID_NOT_ABSOLUTE` (rmw reports index 0).
    #[error("topic name must be absolute, it must lead with a '/'")]
    NotAbsolute,
    /// `RMW_TOPIC_INVALID_ENDS_WITH_FORWARD_SLASH`; also catches `/` alone.
    #[error("topic name must not end with a '/' (index {index})")]
    EndsWithForwardSlash {
        /// Offset of the trailing `/`.
        index: usize,
    },
    /// `RMW_TOPIC_INVALID_CONTAINS_UNALLOWED_CHARACTERS`.
    #[error(
        "topic name must not contain characters other than alphanumerics, '_', or '/' \
         (index {index})"
    )]
    InvalidCharacter {
        /// Offset of the first offending byte.
        index: usize,
    },
    /// `RMW_TOPIC_INVALID_CONTAINS_REPEATED_FORWARD_SLASH`.
    #[error("topic name must not contain repeated '/' (index {index})")]
    RepeatedForwardSlash {
        /// Offset of the second `/`.
        index: usize,
    },
    /// `RMW_TOPIC_INVALID_NAME_TOKEN_STARTS_WITH_NUMBER`.
    #[error("topic name must not have a token that starts with a number (index {index})")]
    TokenStartsWithNumber {
        /// Offset of the digit.
        index: usize,
    },
    /// `RMW_TOPIC_INVALID_TOO_LONG`, checked last as in rmw.
    #[error("topic length should not exceed '{TOPIC_NAME_MAX_LENGTH}' (length {length})")]
    TooLong {
        /// Length of the input in bytes.
        length: usize,
    },
}

impl TopicNameError {
    /// The `invalid_index` rmw reports for this error.
    pub fn invalid_index(&self) -> usize {
        match self {
            Self::Empty | Self::NotAbsolute => 0,
            Self::EndsWithForwardSlash { index }
            | Self::InvalidCharacter { index }
            | Self::RepeatedForwardSlash { index }
            | Self::TokenStartsWithNumber { index } => *index,
            Self::TooLong { .. } => TOPIC_NAME_MAX_LENGTH - 1,
        }
    }
}

/// Checks `name` against `rmw_validate_full_topic_name`, in rmw's order:
/// empty, absolute, trailing `/`, characters `[A-Za-z0-9_/]`, `//`, tokens
/// starting with a digit, then length (at most 247 bytes).
pub fn validate_full_topic_name(name: &str) -> Result<(), TopicNameError> {
    let bytes = name.as_bytes();
    let Some(&last) = bytes.last() else {
        return Err(TopicNameError::Empty);
    };
    if bytes[0] != b'/' {
        return Err(TopicNameError::NotAbsolute);
    }
    if last == b'/' {
        return Err(TopicNameError::EndsWithForwardSlash {
            index: bytes.len() - 1,
        });
    }
    if let Some(index) = bytes
        .iter()
        .position(|&b| !(b.is_ascii_alphanumeric() || b == b'_' || b == b'/'))
    {
        return Err(TopicNameError::InvalidCharacter { index });
    }
    for (i, pair) in bytes.windows(2).enumerate() {
        if pair[0] == b'/' {
            if pair[1] == b'/' {
                return Err(TopicNameError::RepeatedForwardSlash { index: i + 1 });
            }
            if pair[1].is_ascii_digit() {
                return Err(TopicNameError::TokenStartsWithNumber { index: i + 1 });
            }
        }
    }
    if bytes.len() > TOPIC_NAME_MAX_LENGTH {
        return Err(TopicNameError::TooLong {
            length: bytes.len(),
        });
    }
    Ok(())
}

/// A fully-qualified topic name valid per `rmw_validate_full_topic_name`,
/// e.g. `/ns/chatter`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TopicName(pub(super) String);

impl TopicName {
    /// Validates `name` (already fully qualified) and wraps it.
    pub fn new(name: &str) -> Result<Self, TopicNameError> {
        validate_full_topic_name(name)?;
        Ok(Self(name.to_owned()))
    }

    /// Whether the name is hidden: any `/`-token starts with `_`.
    pub fn is_hidden(&self) -> bool {
        super::hidden::is_hidden_name(&self.0)
    }
}

impl_validated_name!(TopicName, TopicNameError);
