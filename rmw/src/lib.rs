//! horus-ros' rcl layer: contexts, nodes, arguments and endpoints over the backend a context
//! runs on.
//!
//! - [`contract`] (the crate `horus-ros-rmw-contract`): what a backend implements (participant,
//!   writer, reader, wait set, discovery feed); RustDDS, Cyclone DDS and Zenoh implement it, each
//!   in a crate of its own, and nothing here knows which one runs.
//! - [`backend`] (the crate `horus-ros-rmw-implementation`): which backends are built in, and the
//!   one a context runs on ([`Backend`]).
//! - [`Context`]: a participant in one domain, configured from `ROS_DOMAIN_ID`,
//!   `ROS_AUTOMATIC_DISCOVERY_RANGE`, `ROS_STATIC_PEERS` (and the deprecated `ROS_LOCALHOST_ONLY`).
//! - [`Node`]: a named node; nodes and their endpoints are announced on `ros_discovery_info`
//!   exactly as rmw_dds_common does.
//! - [`names`]: ROS name validation, expansion and DDS mangling.
//! - [`qos`]: QoS profiles and their DDS mapping.
//! - [`Gid`]: 16-byte global ids.
//! - [`signal_handler`]: SIGINT and SIGTERM shut contexts down and take their participants off
//!   every peer's graph at once, as rclcpp's and rclpy's signal handlers do.
//! - [`service`]: request/reply (`rmw_send_request`, `rmw_take_request`, `rmw_send_response`,
//!   `rmw_take_response`) in each peer's wire convention.

pub mod args;
pub use horus_ros_rmw_implementation as backend;
pub mod context;
use horus_ros_dds_common as dds;
pub use horus_ros_rmw_contract as contract;
use horus_ros_rmw_contract::dds_error;
pub use horus_ros_rmw_contract::discovery;
use horus_ros_rmw_contract::feed_wait;
#[cfg(feature = "rustdds")]
#[doc(hidden)]
pub mod fuzzing;
pub use horus_ros_rmw_contract::gid;
use horus_ros_rmw_contract::local_sink;
pub use horus_ros_rmw_contract::names;
pub mod node;
pub mod pubsub;
pub use horus_ros_rmw_contract::qos;
pub mod queue;
pub mod raw;

pub mod service;
pub mod signal_handler;
#[cfg(feature = "tokio")]
pub mod stream;
pub mod wait_set;
#[cfg(feature = "zenoh")]
pub use horus_ros_rmw_zenoh as zenoh;

pub use backend::{
    Backend, BackendError, BACKEND_ENV, DEFAULT_RMW_IMPLEMENTATION, RMW_IMPLEMENTATIONS,
    RMW_IMPLEMENTATION_ENV,
};
pub use context::{
    env::{DiscoveryOptions, DiscoveryRange, DomainId},
    Context, ContextBuilder, ContextError, DiscoveryFeed, DiscoveryFeedError, FeedWaker,
    ShutdownFuture,
};
pub use contract::Capabilities;
pub use dds_error::{BackendCause, DdsError};
pub use discovery::{DiscoveredEndpoint, DiscoveredParticipant, DiscoveryEvent, VendorId};
pub use gid::Gid;
pub use node::{Node, NodeError, WeakNode};
pub use pubsub::{EndpointError, PublishError, Publisher, SampleError, Subscription, TakeError};
pub use queue::{DropOldestQueue, Lagged};
pub use raw::{
    unix_time_ns, LoanedSample, RawEndpointSpec, RawReader, RawReaderWaker, RawSample, RawWriter,
    SampleId, ServiceEndpointId, ServiceEndpointRole, WriteLoan,
};
pub use signal_handler::{ShutdownSignal, SignalHandlerOptions};
#[cfg(feature = "tokio")]
pub use stream::SubscriptionStream;
pub use wait_set::{WaitSet, WaitSetError};
