//! What a node can reach from its own `init`, `tick` and `shutdown`: its ROS node, its
//! parameters, and services served or called without blocking the tick.
//!
//! ```no_run
//! use horus::prelude::*;
//! use horus::msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsResponse};
//!
//! struct Adder { server: Option<horus::current::ServiceQueue<AddTwoInts>> }
//!
//! impl Node for Adder {
//!     fn init(&mut self) -> Result<()> {
//!         self.server = Some(horus::current::serve::<AddTwoInts>("add_two_ints")?);
//!         Ok(())
//!     }
//!     fn tick(&mut self) {
//!         if let Some(server) = &self.server {
//!             while let Some(request) = server.try_recv() {
//!                 let sum = request.request().a + request.request().b;
//!                 request.respond(AddTwoIntsResponse { sum });
//!             }
//!         }
//!     }
//! }
//! ```

use std::sync::mpsc;
use std::time::Duration;

use horus_ros_msgs::rcl_interfaces::msg::{ParameterType, ParameterValue};
use horus_ros_msgs::Service;
use horus_ros_rmw::Node as RosNode;
use horus_ros_services::{AsyncServiceClient, ServiceClient, ServiceServer, ServiceServerBuilder};

use crate::api::runtime::current;

/// Why something of the current node could not be reached or created.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CurrentNodeError {
    /// Not called from a scheduled node's `init`, `tick` or `shutdown`.
    #[error("not called from a scheduled node (init, tick or shutdown)")]
    NoNode,
    /// The node's scheduler runs without ROS.
    #[error("node '{0}' has no ROS side (its scheduler runs without ROS)")]
    NoRos(String),
    /// The service server or client could not be created.
    #[error("{0}")]
    Setup(String),
}

/// The HORUS name of the node running on this thread.
pub fn name() -> Option<String> {
    current().map(|r| r.name.clone())
}

/// The ROS node of the node running on this thread.
pub fn ros_node() -> Result<RosNode, CurrentNodeError> {
    let runtime = current().ok_or(CurrentNodeError::NoNode)?;
    let ros = runtime
        .ros()
        .ok_or_else(|| CurrentNodeError::NoRos(runtime.name.clone()))?;
    Ok(ros.node().clone())
}

/// A parameter of the current node (given with `--ros-args -p name:=value` or in a
/// `--params-file`, or set with `ros2 param set`).
pub fn parameter(name: &str) -> Option<ParameterValue> {
    current()?.ros()?.parameter(name)
}

/// A Rust value a parameter can hold.
pub trait FromParameter: Sized {
    /// The value, if the parameter has this type.
    fn from_parameter(value: &ParameterValue) -> Option<Self>;
}

impl FromParameter for bool {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        (v.r#type == ParameterType::PARAMETER_BOOL).then_some(v.bool_value)
    }
}

impl FromParameter for i64 {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        (v.r#type == ParameterType::PARAMETER_INTEGER).then_some(v.integer_value)
    }
}

impl FromParameter for f64 {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        match v.r#type {
            ParameterType::PARAMETER_DOUBLE => Some(v.double_value),
            // rclcpp refuses this; a robot program usually means it.
            ParameterType::PARAMETER_INTEGER => Some(v.integer_value as f64),
            _ => None,
        }
    }
}

impl FromParameter for String {
    fn from_parameter(v: &ParameterValue) -> Option<Self> {
        (v.r#type == ParameterType::PARAMETER_STRING).then(|| v.string_value.clone())
    }
}

/// The current node's parameter `name` as a `T`, or `default` when it is not set or not a `T`.
pub fn parameter_or<T: FromParameter>(name: &str, default: T) -> T {
    parameter(name)
        .and_then(|v| T::from_parameter(&v))
        .unwrap_or(default)
}

/// A non-blocking client of service `name` (relative names resolve under the current node):
/// `call_async` in one tick, `PendingResponse::check` in the next ones.
pub fn client<S: Service>(name: &str) -> Result<AsyncServiceClient<S>, CurrentNodeError> {
    let node = ros_node()?;
    ServiceClient::<S>::builder()
        .node(&node)
        .name(name)
        .build_async()
        .map_err(|e| CurrentNodeError::Setup(e.to_string()))
}

/// How long a request waits for a tick to answer it before the server gives up on it.
pub const SERVE_TIMEOUT: Duration = Duration::from_secs(10);

/// Serves service `name` under the current node; requests are answered from `tick` (see
/// [`ServiceQueue`]).
pub fn serve<S: Service>(name: &str) -> Result<ServiceQueue<S>, CurrentNodeError> {
    let node = ros_node()?;
    let (tx, rx) = mpsc::channel::<PendingRequest<S>>();
    let server = ServiceServerBuilder::<S>::new()
        .node(&node)
        .name(name)
        .on_request(move |request| {
            let (reply, response) = mpsc::sync_channel(1);
            tx.send(PendingRequest { request, reply })
                .map_err(|_| "the serving node has stopped".to_owned())?;
            response
                .recv_timeout(SERVE_TIMEOUT)
                .map_err(|_| "the serving node did not answer".to_owned())
        })
        .build()
        .map_err(|e| CurrentNodeError::Setup(e.to_string()))?;
    Ok(ServiceQueue {
        _server: server,
        requests: rx,
    })
}

/// A service served from `tick`: the server's thread hands each request over and waits for the
/// node's answer; `tick` takes requests with [`try_recv`](Self::try_recv) (never blocks) and
/// answers them with [`PendingRequest::respond`].
pub struct ServiceQueue<S: Service> {
    _server: ServiceServer<S>,
    requests: mpsc::Receiver<PendingRequest<S>>,
}

impl<S: Service> std::fmt::Debug for ServiceQueue<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServiceQueue")
            .field("service", &S::TYPE_NAME)
            .finish()
    }
}

impl<S: Service> ServiceQueue<S> {
    /// The next request waiting for an answer, if any.
    pub fn try_recv(&self) -> Option<PendingRequest<S>> {
        self.requests.try_recv().ok()
    }
}

/// A request waiting for the node's answer.
pub struct PendingRequest<S: Service> {
    request: S::Request,
    reply: mpsc::SyncSender<S::Response>,
}

impl<S: Service> PendingRequest<S> {
    /// The request.
    pub fn request(&self) -> &S::Request {
        &self.request
    }

    /// Sends the response.
    pub fn respond(self, response: S::Response) {
        let _ = self.reply.try_send(response);
    }
}
