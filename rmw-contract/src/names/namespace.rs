//! Validated ROS 2 node namespaces.
//!
//! Rules and messages follow rmw `src/validate_namespace.c` and
//! `include/rmw/validate_namespace.h` (ros2/rmw, jazzy): `/` alone is valid,
//! anything else must pass the full-topic-name rules, then a tighter length.

use super::macros::impl_validated_name;
use super::topic_name::{validate_full_topic_name, TopicNameError, TOPIC_NAME_MAX_LENGTH};

/// Longest valid namespace in bytes: rmw `RMW_NAMESPACE_MAX_LENGTH` =
/// `RMW_TOPIC_MAX_NAME_LENGTH - 2` = 245 (2 kept for the shortest topic `/X`).
pub const NAMESPACE_MAX_LENGTH: usize = TOPIC_NAME_MAX_LENGTH - 2;

/// Why a string is not a valid namespace (rmw `RMW_NAMESPACE_INVALID_*`).
/// Indices are byte offsets, as rmw's `invalid_index`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NamespaceError {
    /// `RMW_NAMESPACE_INVALID_IS_EMPTY_STRING`.
    #[error("namespace must not be empty")]
    Empty,
    /// `RMW_NAMESPACE_INVALID_NOT_ABSOLUTE` (rmw reports index 0).
    #[error("namespace must be absolute, it must lead with a '/'")]
    NotAbsolute,
    /// `RMW_NAMESPACE_INVALID_ENDS_WITH_FORWARD_SLASH`.
    #[error("namespace must not end with a '/', unless only a '/' (index {index})")]
    EndsWithForwardSlash {
        /// Offset of the trailing `/`.
        index: usize,
    },
    /// `RMW_NAMESPACE_INVALID_CONTAINS_UNALLOWED_CHARACTERS`.
    #[error(
        "namespace must not contain characters other than alphanumerics, '_', or '/' \
         (index {index})"
    )]
    InvalidCharacter {
        /// Offset of the first offending byte.
        index: usize,
    },
    /// `RMW_NAMESPACE_INVALID_CONTAINS_REPEATED_FORWARD_SLASH`.
    #[error("namespace must not contain repeated '/' (index {index})")]
    RepeatedForwardSlash {
        /// Offset of the second `/`.
        index: usize,
    },
    /// `RMW_NAMESPACE_INVALID_NAME_TOKEN_STARTS_WITH_NUMBER`.
    #[error("namespace must not have a token that starts with a number (index {index})")]
    TokenStartsWithNumber {
        /// Offset of the digit.
        index: usize,
    },
    /// `RMW_NAMESPACE_INVALID_TOO_LONG`, checked last as in rmw.
    #[error("namespace should not exceed '{NAMESPACE_MAX_LENGTH}' (length {length})")]
    TooLong {
        /// Length of the input in bytes.
        length: usize,
    },
}

impl NamespaceError {
    /// The `invalid_index` rmw reports for this error.
    pub fn invalid_index(&self) -> usize {
        match self {
            Self::Empty | Self::NotAbsolute => 0,
            Self::EndsWithForwardSlash { index }
            | Self::InvalidCharacter { index }
            | Self::RepeatedForwardSlash { index }
            | Self::TokenStartsWithNumber { index } => *index,
            Self::TooLong { .. } => NAMESPACE_MAX_LENGTH - 1,
        }
    }
}

/// Checks `namespace` against `rmw_validate_namespace`: `/`, or a valid
/// full topic name of at most 245 bytes.
pub fn validate_namespace(namespace: &str) -> Result<(), NamespaceError> {
    if namespace == "/" {
        return Ok(());
    }
    match validate_full_topic_name(namespace) {
        // rmw ignores the topic's own (looser) length limit here.
        Ok(()) | Err(TopicNameError::TooLong { .. }) => {}
        Err(TopicNameError::Empty) => return Err(NamespaceError::Empty),
        Err(TopicNameError::NotAbsolute) => return Err(NamespaceError::NotAbsolute),
        Err(TopicNameError::EndsWithForwardSlash { index }) => {
            return Err(NamespaceError::EndsWithForwardSlash { index })
        }
        Err(TopicNameError::InvalidCharacter { index }) => {
            return Err(NamespaceError::InvalidCharacter { index })
        }
        Err(TopicNameError::RepeatedForwardSlash { index }) => {
            return Err(NamespaceError::RepeatedForwardSlash { index })
        }
        Err(TopicNameError::TokenStartsWithNumber { index }) => {
            return Err(NamespaceError::TokenStartsWithNumber { index })
        }
    }
    if namespace.len() > NAMESPACE_MAX_LENGTH {
        return Err(NamespaceError::TooLong {
            length: namespace.len(),
        });
    }
    Ok(())
}

/// A node namespace valid per `rmw_validate_namespace`, e.g. `/` or `/robot1`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Namespace(String);

impl Namespace {
    /// Validates `namespace` and wraps it.
    pub fn new(namespace: &str) -> Result<Self, NamespaceError> {
        validate_namespace(namespace)?;
        Ok(Self(namespace.to_owned()))
    }

    /// The root namespace `/`.
    pub fn root() -> Self {
        Self("/".to_owned())
    }

    /// Whether this is the root namespace `/`.
    pub fn is_root(&self) -> bool {
        self.0 == "/"
    }

    /// Whether any `/`-token of the namespace starts with `_`.
    pub fn is_hidden(&self) -> bool {
        super::hidden::is_hidden_name(&self.0)
    }
}

impl Default for Namespace {
    fn default() -> Self {
        Self::root()
    }
}

impl_validated_name!(Namespace, NamespaceError);
