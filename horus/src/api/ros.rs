//! The ROS 2 side of scheduled nodes: one context per scheduler, one ROS node per HORUS node,
//! each with the standard node services (parameters from `--ros-args`, `~/get_type_description`)
//! and a `/rosout` publisher, as rclcpp gives every node.

use std::sync::Arc;

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::rcl_interfaces::msg::{Log, ParameterValue};
use horus_ros_rmw::args::LogSeverity;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Context, Node as RosNodeHandle, Publisher};
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

    /// A context from the environment and the process's `--ros-args` (malformed or unknown
    /// ones are an error, with rcl's / rclcpp's message).
    pub(crate) fn from_environment() -> Result<Self, SchedulerError> {
        let context = Context::from_env().map_err(|e| SchedulerError::Ros(e.to_string()))?;
        Ok(Self::new(context))
    }

    /// Creates the ROS node of HORUS node `horus_name` (name and namespace remapped by
    /// `--ros-args`), its node services and its `/rosout` publisher.
    pub(crate) fn attach(&self, horus_name: &str) -> Result<Arc<RosNode>, String> {
        let name = ros_node_name(horus_name)
            .map_err(|e| format!("node '{horus_name}' cannot be a ROS node: {e}"))?;
        let node = self
            .context
            .create_node(&name, "/")
            .map_err(|e| e.to_string())?;
        let services =
            NodeServices::start(&node).map_err(|e| format!("node services of '{name}': {e}"))?;
        let arguments = self.context.arguments();
        // rcl: the logger name is the fully-qualified name with '.' for '/', no leading dot.
        let logger_name = node
            .fully_qualified_name()
            .trim_start_matches('/')
            .replace('/', ".");
        let rosout = if arguments.log_rosout_disabled == Some(true) {
            None
        } else {
            Some(
                node.create_publisher::<Log>("/rosout", &Qos::rosout_default())
                    .map_err(|e| format!("/rosout of '{name}': {e}"))?,
            )
        };
        if rosout.is_some() {
            // rcl registers the type of every publisher it creates for ~/get_type_description.
            services.register_type::<Log>();
        }
        let min_level = match arguments.log_level_for(&logger_name) {
            Some(LogSeverity::Unset) | None => LogLevel::Info,
            Some(LogSeverity::Debug) => LogLevel::Debug,
            Some(LogSeverity::Info) => LogLevel::Info,
            Some(LogSeverity::Warn) => LogLevel::Warn,
            Some(LogSeverity::Error) => LogLevel::Error,
            Some(LogSeverity::Fatal) => LogLevel::Fatal,
        };
        Ok(Arc::new(RosNode {
            rosout,
            services,
            logger_name,
            min_level,
            node,
        }))
    }
}

/// A scheduled node's ROS side.
pub(crate) struct RosNode {
    // Dropped in this order: /rosout, the services, then the node itself.
    rosout: Option<Publisher<Log>>,
    services: NodeServices,
    logger_name: String,
    min_level: LogLevel,
    node: RosNodeHandle,
}

impl RosNode {
    /// The rmw node.
    pub(crate) fn node(&self) -> &RosNodeHandle {
        &self.node
    }

    /// A parameter of this node (`--ros-args -p`, `--params-file`, or set by `ros2 param set`).
    pub(crate) fn parameter(&self, name: &str) -> Option<ParameterValue> {
        self.services.get_parameter(name).ok()
    }

    /// Whether messages at `level` are logged for this node (`--log-level`).
    pub(crate) fn log_enabled(&self, level: LogLevel) -> bool {
        level >= self.min_level
    }

    /// Publishes a log message on `/rosout` (rcl `rcl_logging_rosout_output_handler`).
    pub(crate) fn publish_log(
        &self,
        level: LogLevel,
        file: &str,
        line: u32,
        function: &str,
        args: &std::fmt::Arguments<'_>,
    ) {
        let Some(rosout) = &self.rosout else {
            return;
        };
        let message = Log {
            stamp: Time::now(),
            level: level as u8,
            name: self.logger_name.clone(),
            msg: args.to_string(),
            file: file.to_owned(),
            function: function.to_owned(),
            line,
        };
        if let Err(err) = rosout.publish(message) {
            tracing::debug!("/rosout: {err}");
        }
    }
}
