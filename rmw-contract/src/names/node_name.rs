//! Validated ROS 2 node names.
//!
//! Rules and messages follow rmw `src/validate_node_name.c` and
//! `include/rmw/validate_node_name.h` (ros2/rmw, jazzy).

use super::macros::impl_validated_name;

/// Longest valid node name in bytes (rmw `RMW_NODE_NAME_MAX_NAME_LENGTH`).
pub const NODE_NAME_MAX_LENGTH: usize = 255;

/// Why a string is not a valid node name (rmw `RMW_NODE_NAME_INVALID_*`).
///
/// Indices are byte offsets into the input, as rmw's `invalid_index`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NodeNameError {
    /// `RMW_NODE_NAME_INVALID_IS_EMPTY_STRING`.
    #[error("node name must not be empty")]
    Empty,
    /// `RMW_NODE_NAME_INVALID_CONTAINS_UNALLOWED_CHARACTERS`.
    #[error(
        "node name must not contain characters other than alphanumerics or '_' (index {index})"
    )]
    InvalidCharacter {
        /// Offset of the first offending byte.
        index: usize,
    },
    /// `RMW_NODE_NAME_INVALID_STARTS_WITH_NUMBER` (rmw reports index 0).
    #[error("node name must not start with a number")]
    StartsWithNumber,
    /// `RMW_NODE_NAME_INVALID_TOO_LONG`, checked last as in rmw.
    #[error("node name length should not exceed '{NODE_NAME_MAX_LENGTH}' (length {length})")]
    TooLong {
        /// Length of the input in bytes.
        length: usize,
    },
}

impl NodeNameError {
    /// The `invalid_index` rmw reports for this error.
    pub fn invalid_index(&self) -> usize {
        match self {
            Self::Empty | Self::StartsWithNumber => 0,
            Self::InvalidCharacter { index } => *index,
            Self::TooLong { .. } => NODE_NAME_MAX_LENGTH - 1,
        }
    }
}

/// Checks `name` against `rmw_validate_node_name`: non-empty, only
/// `[A-Za-z0-9_]`, not starting with a digit, at most 255 bytes.
pub fn validate_node_name(name: &str) -> Result<(), NodeNameError> {
    let bytes = name.as_bytes();
    if bytes.is_empty() {
        return Err(NodeNameError::Empty);
    }
    if let Some(index) = bytes
        .iter()
        .position(|&b| !(b.is_ascii_alphanumeric() || b == b'_'))
    {
        return Err(NodeNameError::InvalidCharacter { index });
    }
    if bytes[0].is_ascii_digit() {
        return Err(NodeNameError::StartsWithNumber);
    }
    if bytes.len() > NODE_NAME_MAX_LENGTH {
        return Err(NodeNameError::TooLong {
            length: bytes.len(),
        });
    }
    Ok(())
}

/// A node name valid per `rmw_validate_node_name`, e.g. `talker`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeName(String);

impl NodeName {
    /// Validates `name` and wraps it.
    pub fn new(name: &str) -> Result<Self, NodeNameError> {
        validate_node_name(name)?;
        Ok(Self(name.to_owned()))
    }

    /// Whether ros2cli hides this node: its name starts with `_`
    /// (ros2cli `ros2node/api` `HIDDEN_NODE_PREFIX`).
    pub fn is_hidden(&self) -> bool {
        self.0.starts_with(super::hidden::HIDDEN_PREFIX)
    }
}

impl_validated_name!(NodeName, NodeNameError);
