//! HORUS nodes and scheduler on ROS 2.
//!
//! A robot program is a set of [`Node`]s run by a [`Scheduler`]: `init` once (lazily), `tick`
//! at each node's rate with budget, deadline and watchdog checks, `shutdown` at exit (Ctrl+C,
//! SIGTERM, [`Scheduler::stop`]) — every call wrapped in `catch_unwind` and routed through the
//! node's [`FailurePolicy`].
//!
//! Every scheduled node is also a ROS 2 node of one context (one DDS participant) per
//! scheduler: listed on `ros_discovery_info` with its topics and services, serving the
//! standard node services (parameters, `~/get_type_description`), logging to `/rosout`. Its
//! [`Topic`]s are ROS topics (`rt/…`, ROS type names, RIHS01 hashes), so `ros2 node list`,
//! `ros2 topic echo` and `ros2 service call` work on it as on an rclcpp node. The process
//! accepts `--ros-args` as every rclcpp executable does.
//!
//! ```no_run
//! use horus::prelude::*;
//!
//! struct Talker { chatter: Topic<StringMsg>, count: u64 }
//!
//! impl Node for Talker {
//!     fn name(&self) -> &str { "talker" }
//!     fn tick(&mut self) {
//!         self.count += 1;
//!         self.chatter.send(StringMsg { data: format!("Hello World: {}", self.count) });
//!     }
//! }
//!
//! fn main() -> Result<()> {
//!     let mut sched = Scheduler::new().tick_rate(1_u64.hz());
//!     sched.add(Talker { chatter: Topic::new("chatter")?, count: 0 }).build()?;
//!     sched.run()
//! }
//! ```

mod api;

/// The README's Rust examples, compiled and run as doctests (the services example calls its
/// own server; the scheduler example, which runs until Ctrl+C, is compiled only).
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;

/// The code blocks of the services guide (seed 000), visible lines exactly as the guide writes
/// them, compiled as doctests (those that need a live server compiled only).
#[cfg(doctest)]
#[doc = include_str!("../docs/seed_000_services.md")]
pub mod seed_000_services {}

/// The code blocks of the Node API reference (seed 002), visible lines exactly as the reference
/// writes them, compiled as doctests (the programs that run until Ctrl+C compiled only).
#[cfg(doctest)]
#[doc = include_str!("../docs/seed_002_node_api.md")]
pub mod seed_002_node_api {}

pub use api::clock::{timestamp_now, Clock, ManualClock, StopHandle, SystemClock};
pub use api::current;
pub use api::error::{BuildError, ConfigError, Error, MessageError, Result, SchedulerError};
pub use api::log::LogLevel;
pub use api::managed::{Managed, DEFAULT_TRANSITION_TIMEOUT};
pub use api::metrics::{NodeMetrics, NodeTiming, TimingReport};
pub use api::names;
pub use api::node::{Node, NodeHealthState, NodeState, TopicMetadata};
pub use api::policy::{FailurePolicy, Miss};
pub use api::scheduler::{NodeBuilder, Scheduler, DEFAULT_TICK_RATE_HZ, SHUTDOWN_TIMEOUT};
#[cfg(feature = "tokio")]
pub use api::topic::TopicStream;
pub use api::topic::{Topic, TopicError, DROP_FLUSH_TIMEOUT};
pub use api::units::{Frequency, Units};
#[cfg(feature = "tokio")]
pub use horus_ros_rmw::stream::Lagged;

pub use horus_ros_msgs::{Message, Service};

/// Managed (lifecycle) nodes: horus-ros-lifecycle, which [`Managed`] is built on (its
/// `LifecycleClient` drives any managed node).
pub use horus_ros_lifecycle as lifecycle;
pub use horus_ros_services::{message, service};

/// ROS 2 message and service types (the packages of `horus-ros-msgs`).
pub mod msgs {
    pub use horus_ros_msgs::*;
}

/// The ROS 2 layer under the nodes: contexts, rmw nodes, names, QoS.
pub mod ros {
    pub use horus_ros_rmw::args::{Arguments, ArgumentsError};
    pub use horus_ros_rmw::qos::Qos;
    pub use horus_ros_rmw::{Context, Node as RosNode};
    pub use horus_ros_services::{
        AsyncServiceClient, EndpointBuilder, EndpointOptions, NodeServices, PendingResponse,
        ServiceClient, ServiceServer, ServiceServerBuilder, SetupError,
    };
}

/// ROS 2 actions (`horus-ros-actions`): servers and clients as rcl_action draws them; from a
/// node's `tick`, [`current::action_server`] and [`current::action_client`].
pub mod actions {
    pub use horus_ros_actions::*;
}

/// Everything a robot program needs, in one import.
pub mod prelude {
    pub use crate::{
        hlog, message, node, service, FailurePolicy, Frequency, Miss, Node, NodeHealthState,
        NodeMetrics, NodeState, Result, Scheduler, Topic, TopicMetadata, Units,
    };
    pub use crate::{Error, Message};
    // Services, as the services guide (seed 000) uses them.
    pub use horus_ros_msgs::builtin_interfaces::msg::Time;
    pub use horus_ros_msgs::geometry_msgs::msg::{
        Point, Pose, PoseStamped, Quaternion, Twist, TwistStamped, Vector3,
    };
    pub use horus_ros_msgs::sensor_msgs::msg::{Imu, JointState, LaserScan};
    pub use horus_ros_msgs::std_msgs::msg::{
        Bool, Float32, Float64, Header, Int16, Int32, Int64, Int8, String as StringMsg, UInt16,
        UInt32, UInt64, UInt8,
    };
    pub use horus_ros_services::{
        AsyncServiceClient, EndpointBuilder, PendingResponse, RetryConfig, ServiceClient,
        ServiceError, ServiceServer, ServiceServerBuilder, TransportError,
    };
    pub use std::time::Duration;
}

#[doc(hidden)]
pub mod __private {
    pub use crate::api::log::log;
    pub use crate::api::macros::snake_case;
}
