//! horus-ros lifecycle: managed nodes as rclcpp_lifecycle and rclpy.lifecycle draw them,
//! wire-compatible with ROS 2 Jazzy (`ros2 lifecycle` drives them, and they drive rclpy's).
//!
//! ```no_run
//! use horus_ros_lifecycle::{CallbackReturn, LifecycleCallbacks, LifecycleNode, State};
//! use horus_ros_rmw::Context;
//!
//! struct Camera;
//!
//! impl LifecycleCallbacks for Camera {
//!     fn on_configure(&mut self, _previous: State) -> CallbackReturn {
//!         // open the device…
//!         CallbackReturn::Success
//!     }
//! }
//!
//! let context = Context::from_env()?;
//! let node = context.create_node("camera", "/")?;
//! let camera = LifecycleNode::builder().node(&node).callbacks(Camera).build()?;
//! // `ros2 lifecycle set /camera configure` does the same through `/camera/change_state`.
//! assert_eq!(camera.configure()?, State::Inactive);
//! assert_eq!(camera.activate()?, State::Active);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! - [`StateMachine`], [`State`], [`Transition`], [`CallbackReturn`]: rcl_lifecycle's default
//!   state machine (`default_state_machine.c`), ids, labels and order included.
//! - [`LifecycleNode`]: a node with the services `~/change_state`, `~/get_state`,
//!   `~/get_available_states`, `~/get_available_transitions`, `~/get_transition_graph` and the
//!   topic `~/transition_event` (rcl_lifecycle's `com_interface.c`), calling the
//!   [`LifecycleCallbacks`] as rclcpp_lifecycle does; [`LifecyclePublisher`]s publish only
//!   while it is active.
//! - [`LifecycleClient`]: drives another node's lifecycle through those services.

mod client;
mod node;
mod publisher;
pub mod state_machine;

pub use client::{LifecycleCallError, LifecycleClient, LifecycleClientBuilder, TransitionRequest};
pub use node::{
    transition_event_qos, LifecycleCallbacks, LifecycleNode, LifecycleNodeBuilder, TransitionError,
    TransitionOutcome, SERVICE_NAMES, TRANSITION_EVENT_TOPIC,
};
pub use publisher::LifecyclePublisher;
pub use state_machine::{CallbackReturn, State, StateMachine, Transition, TriggerError};

pub use horus_ros_msgs::lifecycle_msgs;
