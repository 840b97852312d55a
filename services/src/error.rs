//! Errors: [`ServiceError`] for calls (the seed API's four cases) with [`TransportError`] for
//! their communication failures (and the raw traits' operations), [`SetupError`] for creating
//! servers and clients, and [`Error`] joining both for `?` in applications.

use horus_ros_graph::GraphStartError;
use horus_ros_rmw::names::{ExpandError, TopicNameError};
use horus_ros_rmw::service::ConventionError;
use horus_ros_rmw::{ContextError, EndpointError, NodeError};

/// Why a service call failed: exactly the seed API's four cases, matched exhaustively by
/// applications (`Timeout`, `ServiceFailed(msg)`, `NoServer`, `Transport(cause)`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
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
    /// The request or reply could not be encoded, sent, received or decoded, no server on the
    /// graph can be spoken to, or every server the request went to left before answering
    /// ([`TransportError::ServerGone`]): the communication failed. Retried by
    /// `call_resilient`.
    #[error("service transport error: {0}")]
    Transport(TransportError),
}

impl ServiceError {
    /// Whether `call_resilient` retries after this error (Timeout and Transport).
    pub fn is_transient(&self) -> bool {
        matches!(self, Self::Timeout | Self::Transport(_))
    }
}

/// Why the communication of a service operation failed: the cause of
/// [`ServiceError::Transport`], and the error of the raw service traits
/// ([`ServiceClientTrait`](crate::ServiceClientTrait),
/// [`ServiceServerTrait`](crate::ServiceServerTrait)).
///
/// `Timeout`, `NoServer` and `ServiceFailed` are the raw traits' forms of the
/// [`ServiceError`] variants of the same names (into which they convert); a
/// [`ServiceError::Transport`] never holds them.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TransportError {
    /// The operation did not complete in time (also what the deprecated blocking calls return).
    #[error("the service operation timed out")]
    Timeout,
    /// The backend cannot do this (e.g. no graph introspection).
    #[error("the operation is not supported by this backend")]
    Unsupported,
    /// No server became ready to take a queued request within the client's send timeout.
    #[error("no server is available for this service")]
    NoServer,
    /// A message could not be serialized, or a payload is not valid CDR for its type (the CDR
    /// encoder's message: its error is not `Clone`).
    #[error("serialization failed: {0}")]
    Serialization(String),
    /// A received payload could not be deserialized (the CDR decoder's message).
    #[error("deserialization failed: {0}")]
    Deserialization(String),
    /// The caller's buffer is too small; nothing was consumed, retry with `needed` bytes.
    #[error("buffer too small: {needed} bytes needed, {capacity} available")]
    BufferTooSmall {
        /// Bytes the payload needs.
        needed: usize,
        /// Bytes the buffer has.
        capacity: usize,
    },
    /// `send_reply` was given a sequence number of no outstanding request (never received,
    /// already answered, or evicted).
    #[error("no outstanding request has sequence number {0}")]
    UnknownRequest(i64),
    /// A horus-ros server's handler failed and it sent an error reply instead of a response.
    #[error("the service handler failed: {0}")]
    ServiceFailed(String),
    /// The DDS layer failed to send the request or reply (its message: the DDS error is not
    /// `Clone`).
    #[error("sending failed: {0}")]
    Send(String),
    /// Every server the request went to left the graph before answering: at once when it left
    /// gracefully (its endpoints were withdrawn), at its participant's lease expiry when it died
    /// (e.g. was killed). The request is lost; nobody will answer it. Retried by
    /// `call_resilient` like every [`ServiceError::Transport`] (a retry waits for a server
    /// again, and gives `NoServer` if none comes).
    #[error("the server left the graph before answering")]
    ServerGone,
    /// Every server of the service on the graph follows a service convention this context's
    /// backend cannot speak (e.g. a Fast DDS peer seen from the Cyclone DDS backend).
    #[error("no server of {service} can be called: {cause}")]
    NoUsableServer {
        /// The service name.
        service: String,
        /// Why (the last server looked at).
        cause: ConventionError,
    },
    /// The call had already completed (its future or pending response was used again).
    #[error("the call has already completed")]
    CallCompleted,
}

impl From<TransportError> for ServiceError {
    fn from(e: TransportError) -> Self {
        match e {
            TransportError::Timeout => Self::Timeout,
            TransportError::NoServer => Self::NoServer,
            TransportError::ServiceFailed(message) => Self::ServiceFailed(message),
            other => Self::Transport(other),
        }
    }
}

impl From<ServiceError> for TransportError {
    fn from(e: ServiceError) -> Self {
        match e {
            ServiceError::Timeout => Self::Timeout,
            ServiceError::NoServer => Self::NoServer,
            ServiceError::ServiceFailed(message) => Self::ServiceFailed(message),
            ServiceError::Transport(cause) => cause,
        }
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
