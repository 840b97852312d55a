//! [`Error`]: what a node's `init` / `shutdown` and the scheduler's `run` return.
//!
//! A node's own failures can be of any error type (`SerialPort::open(..)?` works in `init`), so
//! [`Error`] wraps any `std::error::Error` as `Box<dyn Error>` does; the scheduler's own failures
//! are typed ([`BuildError`], [`SchedulerError`], [`TopicError`](crate::TopicError),
//! [`RosArgsError`](crate::RosArgsError)) and can be recovered with [`Error::downcast_ref`].

use std::fmt;

/// The error of a node's lifecycle methods and of the scheduler: any error, boxed.
pub struct Error(Box<dyn std::error::Error + Send + Sync + 'static>);

/// `Result` with [`Error`] by default.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// A configuration problem reported by a node (see [`Error::config`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("configuration error: {0}")]
pub struct ConfigError(pub String);

/// A plain message (see [`Error::msg`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct MessageError(pub String);

impl Error {
    /// A configuration error (a port that cannot be opened, a calibration file missing, …).
    pub fn config(message: impl Into<String>) -> Self {
        Self(Box::new(ConfigError(message.into())))
    }

    /// An error that is only a message.
    pub fn msg(message: impl Into<String>) -> Self {
        Self(Box::new(MessageError(message.into())))
    }

    /// The wrapped error, if it is a `T`.
    pub fn downcast_ref<T: std::error::Error + 'static>(&self) -> Option<&T> {
        self.0.downcast_ref::<T>()
    }

    /// The wrapped error.
    pub fn as_error(&self) -> &(dyn std::error::Error + Send + Sync + 'static) {
        &*self.0
    }
}

impl<E: std::error::Error + Send + Sync + 'static> From<E> for Error {
    fn from(error: E) -> Self {
        Self(Box::new(error))
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The chain: an error shows its cause in its message or returns it as `source()`, never
        // both (this workspace's errors show theirs), so each link is printed once.
        write!(f, "{}", self.0)?;
        let mut source = self.0.source();
        while let Some(s) = source {
            write!(f, ": {s}")?;
            source = s.source();
        }
        Ok(())
    }
}

impl fmt::Debug for Error {
    // `fn main() -> Result<()>` prints the Debug form: make it the readable chain.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// Why [`NodeBuilder::build`](crate::NodeBuilder::build) refused a node.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// Another node of this scheduler already has this name.
    #[error(
        "a node named '{0}' is already registered with this scheduler (node names must be unique)"
    )]
    DuplicateName(String),
    /// The node's name cannot be a ROS node name, even after mapping.
    #[error("node name '{name}' cannot be mapped to a ROS node name: {reason}")]
    InvalidName {
        /// The name.
        name: String,
        /// The ROS rule the mapped name breaks.
        reason: horus_ros_rmw::names::NodeNameError,
    },
    /// A rate of zero (or not finite) was given.
    #[error("node '{name}': the rate must be a positive, finite frequency (got {hz} Hz)")]
    InvalidRate {
        /// The node.
        name: String,
        /// The rate given.
        hz: f64,
    },
    /// The scheduler has already started: nodes are registered before `run`/`tick_once`.
    #[error("node '{0}': nodes must be added before the scheduler starts")]
    AlreadyStarted(String),
}

/// Why [`Scheduler::run`](crate::Scheduler::run) or
/// [`Scheduler::tick_once`](crate::Scheduler::tick_once) stopped with an error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SchedulerError {
    /// A node's `init` failed and its failure policy made it fatal.
    #[error("node '{node}' failed to initialize: {error}")]
    InitFailed {
        /// The node.
        node: String,
        /// Its error or panic message.
        error: String,
    },
    /// A node's `tick` panicked and its failure policy made it fatal.
    #[error("node '{node}' failed: {error}")]
    NodeFailed {
        /// The node.
        node: String,
        /// The panic message.
        error: String,
    },
    /// A node restarted as often as its policy allows and failed again.
    #[error("node '{node}' failed after {restarts} restarts: {error}")]
    RestartsExhausted {
        /// The node.
        node: String,
        /// How many restarts were made.
        restarts: u32,
        /// The last error.
        error: String,
    },
    /// A node missed its deadline with `Miss::Stop`.
    #[error(
        "node '{node}' missed its deadline ({late_ms:.3} ms late) and its policy is Miss::Stop"
    )]
    DeadlineMissed {
        /// The node.
        node: String,
        /// How late it completed, in ms past the deadline.
        late_ms: f64,
    },
    /// The ROS 2 side could not be set up (context, node, `--ros-args`).
    #[error("ROS 2 setup failed: {0}")]
    Ros(String),
}

#[cfg(test)]
mod chain_tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("inner")]
    struct Inner;

    /// This workspace's way: the message shows the cause, which is no `source()`.
    #[derive(Debug, thiserror::Error)]
    #[error("outer: {0}")]
    struct Says(Inner);

    /// The other way: the cause is only the `source()`.
    #[derive(Debug, thiserror::Error)]
    #[error("outer")]
    struct Keeps(#[source] Inner);

    #[test]
    fn the_chain_names_each_cause_once() {
        assert_eq!(Error::from(Says(Inner)).to_string(), "outer: inner");
        assert_eq!(Error::from(Keeps(Inner)).to_string(), "outer: inner");
    }
}
