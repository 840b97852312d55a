//! The async layer (feature `tokio`): calls awaited on the caller's runtime
//! ([`AsyncServiceClient::call`](crate::AsyncServiceClient::call),
//! [`AsyncServiceClient::wait_for_service_async`](crate::AsyncServiceClient::wait_for_service_async)),
//! servers whose handlers are futures run on the caller's runtime
//! ([`AsyncServiceServer::builder`](crate::AsyncServiceServer::builder)),
//! and the graph's changes as a stream (`horus_ros_graph::Graph::events`).
//!
//! Every wake-up is an event: a reply routed to a call wakes its task's waker, a graph change
//! wakes the calls waiting for a server, a request wakes the server's reader thread (which hands
//! it to the runtime). Deadlines are tokio timers of the call itself. Nothing here runs unless the
//! feature is on and used: the blocking API does not change.

mod client;
mod graph_wake;
mod server;

pub use client::{ServiceCall, WaitForService};
pub use server::{AsyncServiceServer, AsyncServiceServerBuilder, DEFAULT_MAX_IN_FLIGHT};
