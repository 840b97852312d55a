//! Validation of topic/service names as users write them, before expansion.
//!
//! Rules and messages follow rcl `src/rcl/validate_topic_name.c` and
//! `include/rcl/validate_topic_name.h` (ros2/rcl 9.2, jazzy): relative names,
//! a leading `~` and `{substitutions}` are allowed; `//` and length are only
//! checked after expansion.

/// Why a name is not a valid unexpanded topic or service name
/// (rcl `RCL_TOPIC_NAME_INVALID_*`). Indices are byte offsets, as rcl's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum UnexpandedNameError {
    /// `RCL_TOPIC_NAME_INVALID_IS_EMPTY_STRING`.
    #[error("topic name must not be empty string")]
    Empty,
    /// `RCL_TOPIC_NAME_INVALID_ENDS_WITH_FORWARD_SLASH`.
    #[error("topic name must not end with a forward slash (index {index})")]
    EndsWithForwardSlash {
        /// Offset of the trailing `/`.
        index: usize,
    },
    /// `RCL_TOPIC_NAME_INVALID_CONTAINS_UNALLOWED_CHARACTERS`.
    #[error(
        "topic name must not contain characters other than alphanumerics, '_', '~', '{{', or '}}' \
         (index {index})"
    )]
    InvalidCharacter {
        /// Offset of the first offending byte.
        index: usize,
    },
    /// `RCL_TOPIC_NAME_INVALID_NAME_TOKEN_STARTS_WITH_NUMBER`.
    #[error("topic name token must not start with a number (index {index})")]
    TokenStartsWithNumber {
        /// Offset of the digit.
        index: usize,
    },
    /// `RCL_TOPIC_NAME_INVALID_UNMATCHED_CURLY_BRACE`.
    #[error("topic name must not have unmatched (unbalanced) curly braces '{{}}' (index {index})")]
    UnmatchedCurlyBrace {
        /// Offset of the stray `}` or of the unclosed `{`.
        index: usize,
    },
    /// `RCL_TOPIC_NAME_INVALID_MISPLACED_TILDE`.
    #[error("topic name must not have tilde '~' unless it is the first character (index {index})")]
    MisplacedTilde {
        /// Offset of the `~`.
        index: usize,
    },
    /// `RCL_TOPIC_NAME_INVALID_TILDE_NOT_FOLLOWED_BY_FORWARD_SLASH` (index 1).
    #[error("topic name must not have a tilde '~' that is not followed by a forward slash '/'")]
    TildeNotFollowedByForwardSlash,
    /// `RCL_TOPIC_NAME_INVALID_SUBSTITUTION_CONTAINS_UNALLOWED_CHARACTERS`.
    #[error(
        "substitution name must not contain characters other than alphanumerics or '_' \
         (index {index})"
    )]
    SubstitutionInvalidCharacter {
        /// Offset of the offending byte.
        index: usize,
    },
    /// `RCL_TOPIC_NAME_INVALID_SUBSTITUTION_STARTS_WITH_NUMBER`.
    #[error("substitution name must not start with a number (index {index})")]
    SubstitutionStartsWithNumber {
        /// Offset of the digit.
        index: usize,
    },
}

impl UnexpandedNameError {
    /// The `invalid_index` rcl reports for this error.
    pub fn invalid_index(&self) -> usize {
        match self {
            Self::Empty => 0,
            Self::TildeNotFollowedByForwardSlash => 1,
            Self::EndsWithForwardSlash { index }
            | Self::InvalidCharacter { index }
            | Self::TokenStartsWithNumber { index }
            | Self::UnmatchedCurlyBrace { index }
            | Self::MisplacedTilde { index }
            | Self::SubstitutionInvalidCharacter { index }
            | Self::SubstitutionStartsWithNumber { index } => *index,
        }
    }
}

/// Checks `name` against `rcl_validate_topic_name`, in rcl's order. Services
/// use the same rules (rcl `node_resolve_name.c`).
///
/// Like rcl, `~x` (a tilde followed by exactly one character) passes: rcl's
/// token loop skips the last character.
pub fn validate_unexpanded_name(name: &str) -> Result<(), UnexpandedNameError> {
    use UnexpandedNameError as E;
    let bytes = name.as_bytes();
    let Some(&last) = bytes.last() else {
        return Err(E::Empty);
    };
    if bytes[0].is_ascii_digit() {
        return Err(E::TokenStartsWithNumber { index: 0 });
    }
    if last == b'/' {
        return Err(E::EndsWithForwardSlash {
            index: bytes.len() - 1,
        });
    }
    let mut open_brace: Option<usize> = None;
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b if b.is_ascii_alphanumeric() => {
                if b.is_ascii_digit() && open_brace.is_some_and(|open| i == open + 1) {
                    return Err(E::SubstitutionStartsWithNumber { index: i });
                }
            }
            b'_' => {}
            b'/' if open_brace.is_some() => {
                return Err(E::SubstitutionInvalidCharacter { index: i });
            }
            b'/' => {}
            b'~' if i != 0 => return Err(E::MisplacedTilde { index: i }),
            b'~' => {}
            b'{' if open_brace.is_some() => {
                return Err(E::SubstitutionInvalidCharacter { index: i });
            }
            b'{' => open_brace = Some(i),
            b'}' if open_brace.is_none() => return Err(E::UnmatchedCurlyBrace { index: i }),
            b'}' => open_brace = None,
            _ if open_brace.is_some() => {
                return Err(E::SubstitutionInvalidCharacter { index: i });
            }
            _ => return Err(E::InvalidCharacter { index: i }),
        }
    }
    if let Some(index) = open_brace {
        return Err(E::UnmatchedCurlyBrace { index });
    }
    // rcl checks every character but the last.
    for (i, pair) in bytes.windows(2).enumerate() {
        if pair[0] == b'/' {
            if pair[1].is_ascii_digit() {
                return Err(E::TokenStartsWithNumber { index: i + 1 });
            }
        } else if i == 1 && bytes[0] == b'~' {
            return Err(E::TildeNotFollowedByForwardSlash);
        }
    }
    Ok(())
}
