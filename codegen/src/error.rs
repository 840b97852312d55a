//! Errors of parsing interface files and of generating code from them.

use std::path::PathBuf;

/// Where in which file a parse failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file (or the name given to a string parsed without one).
    pub file: PathBuf,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (in characters).
    pub column: usize,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)
    }
}

/// A malformed interface file: where, and what was expected there.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{location}: {message}")]
pub struct ParseError {
    /// Where.
    pub location: Location,
    /// What was wrong, or what was expected.
    pub message: String,
}

impl ParseError {
    /// An error at `file:line:column`.
    pub fn new(
        file: impl Into<PathBuf>,
        line: usize,
        column: usize,
        message: impl Into<String>,
    ) -> Self {
        Self {
            location: Location {
                file: file.into(),
                line,
                column,
            },
            message: message.into(),
        }
    }
}
