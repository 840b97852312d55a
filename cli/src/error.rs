//! [`CliError`]: a message for stderr and an exit status.

/// A failed command: what to print on stderr and the exit status (1 like ros2cli's failures;
/// clap itself exits 2 on usage errors).
#[derive(Debug)]
pub struct CliError {
    /// The message (one clear line).
    pub message: String,
    /// The exit status.
    pub code: u8,
}

impl CliError {
    /// A failure with exit status 1.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            code: 1,
        }
    }
}

impl<E: std::error::Error> From<E> for CliError {
    fn from(e: E) -> Self {
        Self::new(e.to_string())
    }
}
