//! Errors: [`ServiceError`] for calls (the seed API's four cases), [`SetupError`] for creating
//! servers and clients, and [`Error`] joining both for `?` in applications.

use horus_ros_graph::GraphStartError;
use horus_ros_rmw::names::{ExpandError, TopicNameError};
use horus_ros_rmw::{ContextError, EndpointError, NodeError};

/// Why a service call failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ServiceError {
    /// No reply within the timeout (the server was there but did not answer in time).
    /// Retried by `call_resilient`.
    #[error("the service call timed out")]
    Timeout,
    /// The server's handler returned `Err(message)` (or panicked). Not retried.
    #[error("the service handler failed: {0}")]
    ServiceFailed(String),
    /// No server of this service and type is on the graph. Not retried.
    #[error("no server is available for this service")]
    NoServer,
    /// The request or reply could not be encoded, sent, received or decoded. Retried by
    /// `call_resilient`.
    #[error("service transport error: {0}")]
    Transport(String),
    /// Every server the request went to left the graph before answering: at once when it left
    /// gracefully (its endpoints were withdrawn), at its participant's lease expiry when it died
    /// (e.g. was killed). The request is lost; nobody will answer it. Retried by
    /// `call_resilient` (a retry waits for a server again, and gives `NoServer` if none comes).
    #[error("the server left the graph before answering")]
    ServerGone,
}

impl ServiceError {
    /// Whether `call_resilient` retries after this error (Timeout, Transport and ServerGone).
    pub fn is_transient(&self) -> bool {
        matches!(self, Self::Timeout | Self::Transport(_) | Self::ServerGone)
    }
}

/// Why a service server or client could not be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SetupError {
    /// The default context could not be created from the environment.
    #[error(transparent)]
    Context(#[from] ContextError),
    /// The default node could not be created.
    #[error(transparent)]
    Node(#[from] NodeError),
    /// The service name is not a valid ROS name.
    #[error("invalid service name '{name}': {cause}")]
    InvalidName {
        /// The name given.
        name: String,
        /// Why it is invalid.
        cause: ExpandError,
    },
    /// The DDS reader or writer could not be created.
    #[error(transparent)]
    Endpoint(#[from] EndpointError),
    /// The graph of the node's context could not be followed.
    #[error(transparent)]
    Graph(#[from] GraphStartError),
    /// The wait set taking the context's responses could not be made, or the client's
    /// response reader not attached to it.
    #[error(transparent)]
    WaitSet(#[from] horus_ros_rmw::WaitSetError),
    /// The server thread could not be started.
    #[error("could not start the service thread: {0}")]
    Thread(std::io::Error),
    /// The service's introspection topic (`<service>/_service_event`) is not a valid topic name.
    #[error("invalid service event topic '{name}': {cause}")]
    InvalidEventTopic {
        /// The topic name.
        name: String,
        /// Why it is invalid.
        cause: TopicNameError,
    },
    /// Introspection was asked of a client whose service type is known only by name (its
    /// `_Event` message cannot be built).
    #[error("service introspection needs a compiled service type")]
    IntrospectionUnsupported,
    /// A server with an async handler was built outside a tokio runtime and given no runtime
    /// handle (`AsyncServiceServerBuilder::runtime`).
    #[error("an async service server needs a tokio runtime (build it inside one, or pass a handle): {0}")]
    NoAsyncRuntime(String),
    /// The builder was given no request handler.
    #[error("a service server needs a request handler: call .on_request(..) before .build()")]
    NoHandler,
}

/// Any horus-ros services error, for `?` in applications.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A call failed.
    #[error(transparent)]
    Service(#[from] ServiceError),
    /// A server or client could not be created.
    #[error(transparent)]
    Setup(#[from] SetupError),
}

/// `Result` with [`Error`] as the default error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl From<ContextError> for Error {
    fn from(e: ContextError) -> Self {
        Self::Setup(e.into())
    }
}

impl From<NodeError> for Error {
    fn from(e: NodeError) -> Self {
        Self::Setup(e.into())
    }
}

// The message shows the cause, so it is no `source()` (not `#[from]`).
impl From<std::io::Error> for SetupError {
    fn from(e: std::io::Error) -> Self {
        Self::Thread(e)
    }
}
