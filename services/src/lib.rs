//! horus-ros services: call and serve ROS 2 services from Rust, wire-compatible with ROS 2 Jazzy
//! nodes on rmw_fastrtps_cpp and rmw_cyclonedds_cpp.
//!
//! ```no_run
//! use horus_ros_services::prelude::*;
//!
//! let _server = ServiceServer::<AddTwoInts>::builder()
//!     .name("/add_two_ints")
//!     .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
//!     .build()?;
//! let mut client = ServiceClient::<AddTwoInts>::builder().name("/add_two_ints").build()?;
//! let reply = client.call(AddTwoIntsRequest { a: 2, b: 3 }, Duration::from_secs(1))?;
//! assert_eq!(reply.sum, 5);
//! # Ok::<(), horus_ros_services::Error>(())
//! ```
//!
//! - [`ServiceServer`]: serve from a background thread woken by
//!   requests; handler errors reach horus-ros clients as [`ServiceError::ServiceFailed`], panics
//!   are caught.
//! - [`ServiceClient`]: `call`, `call_resilient`, `call_optional`; [`AsyncServiceClient`] returns
//!   [`PendingResponse`]s that can be checked, waited on or awaited.
//! - [`DynamicServiceClient`]: call a service whose type is known only at run time
//!   ([`ServiceType`], e.g. from a node's `~/get_type_description`) with YAML, JSON or
//!   [`dynamic`] values.
//! - The wire convention (rmw_fastrtps or rmw_cyclonedds) is chosen per peer from its DDS vendor.
//! - Feature `tokio`: `AsyncServiceClient::call` and `wait_for_service_async` as futures,
//!   async handlers (`AsyncServiceServer`, or `ServiceServerBuilder::on_request_async`) run on the
//!   caller's tokio runtime, and the graph's changes as a stream (`horus_ros_graph::Graph::events`).
//!
//! # Builders
//!
//! Every endpoint is made by `Type::builder(..)` and `.build()`, which gives a `Type`:
//!
//! | Endpoint | Builder |
//! |---|---|
//! | [`ServiceServer`] | [`ServiceServer::builder()`](ServiceServer::builder) → [`ServiceServerBuilder`] (also `ServiceServerBuilder::new()`, as the services guide writes it) |
//! | `AsyncServiceServer` (feature `tokio`) | `AsyncServiceServer::builder()` → `AsyncServiceServerBuilder` |
//! | [`ServiceClient`] | [`ServiceClient::builder()`](ServiceClient::builder) → [`ServiceClientBuilder`] |
//! | [`AsyncServiceClient`] | [`AsyncServiceClient::builder()`](AsyncServiceClient::builder) → [`ServiceClientBuilder`]`<S, AsyncServiceClient<S>>` |
//! | [`DynamicServiceClient`] | [`DynamicServiceClient::builder(service_type)`](DynamicServiceClient::builder) → [`DynamicServiceClientBuilder`] |
//! | [`DdsServiceServer`] | [`DdsServiceServer::builder()`](DdsServiceServer::builder) → [`DdsServiceServerBuilder`] |
//! | [`DdsServiceClient`] | [`DdsServiceClient::builder()`](DdsServiceClient::builder) → [`DdsServiceClientBuilder`] |
//!
//! What every endpoint has — node, name, QoS, wire convention — is one [`EndpointOptions`], set
//! on every builder by the same [`EndpointBuilder`] setters (`node`, `name`, `qos`,
//! `wire_flavour`, `options`; in the [`prelude`]). A builder's own methods are what only its
//! endpoint has: a server's handler, introspection, an async server's runtime, a raw client's
//! send timeout. Only a dynamic client takes an argument: its service type, which has no default.
//!
//! # Readiness
//!
//! Every client ([`ServiceClient`], [`AsyncServiceClient`], [`DynamicServiceClient`], and the
//! raw [`ServiceClientTrait`] of the seeds) speaks of its servers in the same words, as rcl and
//! rclcpp draw the line between what the graph knows and what can be called:
//!
//! - `server_available()`: a server of this service and type is **known** — discovered on the
//!   graph with both its endpoints (request reader, reply writer). It may not hear us yet.
//! - `is_server_ready()`: a server is **ready** — known, and matched with this client both ways
//!   (our request writer with its reader, its reply writer with our reader), so neither the
//!   request nor the first reply can be lost (rclcpp `Client::service_is_ready`).
//! - `wait_for_service(timeout)` / `wait_for_service_async(timeout)`: wait until ready, woken by
//!   graph changes (rclcpp `wait_for_service`). `call` waits the same way within its timeout.

#[macro_use]
mod macros;

#[cfg(feature = "tokio")]
mod asynchronous;
mod cdr;
mod client;
mod error;
#[doc(hidden)]
pub mod fuzzing;
mod introspection;
mod naming;
mod node_services;
mod options;
mod raw_traits;
mod retry;
mod runtime;
mod server;
mod server_core;
mod server_wire;

#[cfg(feature = "tokio")]
pub use asynchronous::{
    AsyncServiceServer, AsyncServiceServerBuilder, ServiceCall, WaitForService,
    DEFAULT_MAX_IN_FLIGHT,
};
pub use client::{
    AsyncServiceClient, DynamicCallError, DynamicPart, DynamicServiceClient,
    DynamicServiceClientBuilder, DynamicServiceType, PendingResponse, RawResponse, ServiceClient,
    ServiceClientBuilder,
};
pub use error::{Error, Result, ServiceError, SetupError, TransportError};
pub use horus_ros_rmw::service::{ConventionError, WireFlavour};
pub use introspection::{IntrospectionState, SERVICE_EVENT_TOPIC_POSTFIX};
pub use naming::default_service_name;
pub use node_services::{
    parameter_type_name, NodeServices, NodeServicesOptions, ParameterChange, ParameterError,
    ParameterValueExt, Parameters, TypeRegistry, FAILURE_NOT_IN_USE, FAILURE_PARSE_HASH,
    REASON_ATOMICALLY_NOT_DECLARED,
};
pub use options::{EndpointBuilder, EndpointOptions};
pub use raw_traits::{
    DdsServiceClient, DdsServiceClientBuilder, DdsServiceServer, DdsServiceServerBuilder,
    RosService, ServiceClientTrait, ServiceRequest, ServiceServerTrait,
};
pub use retry::RetryConfig;
pub use runtime::default_node;
pub use server::{ServiceServer, ServiceServerBuilder};

pub use horus_ros_dynamic as dynamic;
pub use horus_ros_dynamic::ServiceType;
pub use horus_ros_msgs::{Message, Service};
pub use horus_ros_rmw::{Context, Node};

/// Everything an application needs, in one import.
pub mod prelude {
    pub use crate::{message, service};
    pub use crate::{
        AsyncServiceClient, EndpointBuilder, EndpointOptions, Error, IntrospectionState,
        PendingResponse, Result, RetryConfig, ServiceClient, ServiceError, ServiceServer,
        ServiceServerBuilder, TransportError, WireFlavour,
    };
    #[cfg(feature = "tokio")]
    pub use crate::{AsyncServiceServer, AsyncServiceServerBuilder, ServiceCall};
    pub use horus_ros_msgs::example_interfaces::srv::{
        AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse,
    };
    pub use horus_ros_msgs::{Message, Service};
    pub use horus_ros_rmw::{Context, Node};
    pub use std::time::Duration;
}

#[doc(hidden)]
pub mod __private {
    pub use crate::macros::names;
    pub use horus_ros_msgs;
    pub use pastey;
    pub use serde;
}
