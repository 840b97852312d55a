//! [`LifecycleClient`]: drive another node's lifecycle through its services, as ros2lifecycle's
//! `api/__init__.py` (`call_get_states`, `call_get_available_transitions`,
//! `call_get_transition_graph`, `call_change_states`) does.

use std::time::{Duration, Instant};

use horus_ros_msgs::lifecycle_msgs::msg::{self, TransitionDescription};
use horus_ros_msgs::lifecycle_msgs::srv::{
    ChangeState, ChangeStateRequest, GetAvailableStates, GetAvailableTransitions, GetState,
};
use horus_ros_rmw::Node;
use horus_ros_services::{EndpointBuilder, ServiceClient, ServiceError, SetupError};

use crate::state_machine::Transition;

/// The transition a [`LifecycleClient::change_state`] asks for: by id, or by label (a label
/// takes precedence over the id on the server, as rclcpp's and rclpy's `on_change_state`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TransitionRequest {
    /// By id (`lifecycle_msgs/msg/Transition` constants).
    Id(u8),
    /// By label (`"configure"`, `"shutdown"` …), looked up among the current state's.
    Label(String),
}

impl TransitionRequest {
    /// The request's `lifecycle_msgs/msg/Transition`.
    pub fn to_msg(&self) -> msg::Transition {
        match self {
            TransitionRequest::Id(id) => msg::Transition {
                id: *id,
                label: String::new(),
            },
            TransitionRequest::Label(label) => msg::Transition {
                id: 0,
                label: label.clone(),
            },
        }
    }
}

impl From<Transition> for TransitionRequest {
    fn from(t: Transition) -> Self {
        TransitionRequest::Id(t.id())
    }
}

impl From<u8> for TransitionRequest {
    fn from(id: u8) -> Self {
        TransitionRequest::Id(id)
    }
}

impl From<&str> for TransitionRequest {
    fn from(label: &str) -> Self {
        TransitionRequest::Label(label.to_owned())
    }
}

/// Why a call of a [`LifecycleClient`] failed (the service error is the source).
#[derive(Debug, thiserror::Error)]
#[error("calling {service} failed")]
pub struct LifecycleCallError {
    /// The service called (`/node/get_state` …).
    pub service: String,
    /// What went wrong.
    #[source]
    pub source: ServiceError,
}

/// Builds a [`LifecycleClient`]: `LifecycleClient::builder().node(&n).target("/talker").build()`.
#[derive(Debug, Default)]
pub struct LifecycleClientBuilder {
    node: Option<Node>,
    target: String,
}

impl LifecycleClientBuilder {
    /// The node the clients belong to (default: horus-ros-services' process default node).
    pub fn node(mut self, node: &Node) -> Self {
        self.node = Some(node.clone());
        self
    }

    /// The fully qualified name of the managed node (`/talker`; a missing leading `/` is added,
    /// as ros2node's `get_absolute_node_name`).
    pub fn target(mut self, node_name: impl Into<String>) -> Self {
        self.target = node_name.into();
        self
    }

    /// Creates the five clients.
    pub fn build(self) -> Result<LifecycleClient, SetupError> {
        let target = if self.target.starts_with('/') {
            self.target
        } else {
            format!("/{}", self.target)
        };
        let node = match self.node {
            Some(n) => n,
            None => horus_ros_services::default_node()?,
        };
        let name = |service: &str| {
            if target == "/" {
                format!("/{service}")
            } else {
                format!("{target}/{service}")
            }
        };
        Ok(LifecycleClient {
            change_state: ServiceClient::builder()
                .node(&node)
                .name(name("change_state"))
                .build()?,
            get_state: ServiceClient::builder()
                .node(&node)
                .name(name("get_state"))
                .build()?,
            get_available_states: ServiceClient::builder()
                .node(&node)
                .name(name("get_available_states"))
                .build()?,
            get_available_transitions: ServiceClient::builder()
                .node(&node)
                .name(name("get_available_transitions"))
                .build()?,
            get_transition_graph: ServiceClient::builder()
                .node(&node)
                .name(name("get_transition_graph"))
                .build()?,
            target,
        })
    }
}

/// Clients of one managed node's five lifecycle services.
///
/// Every call waits (within its timeout) until the service is ready, then calls it.
pub struct LifecycleClient {
    target: String,
    change_state: ServiceClient<ChangeState>,
    get_state: ServiceClient<GetState>,
    get_available_states: ServiceClient<GetAvailableStates>,
    get_available_transitions: ServiceClient<GetAvailableTransitions>,
    get_transition_graph: ServiceClient<GetAvailableTransitions>,
}

impl std::fmt::Debug for LifecycleClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LifecycleClient")
            .field("target", &self.target)
            .finish_non_exhaustive()
    }
}

impl LifecycleClient {
    /// A builder (see [`LifecycleClientBuilder`]).
    pub fn builder() -> LifecycleClientBuilder {
        LifecycleClientBuilder::default()
    }

    /// The managed node's fully qualified name.
    pub fn target(&self) -> &str {
        &self.target
    }

    /// Waits until all five services are ready (woken by graph changes); false at the timeout.
    pub fn wait_for_services(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        let left = || deadline.saturating_duration_since(Instant::now());
        self.get_state.wait_for_service(left())
            && self.change_state.wait_for_service(left())
            && self.get_available_states.wait_for_service(left())
            && self.get_available_transitions.wait_for_service(left())
            && self.get_transition_graph.wait_for_service(left())
    }

    /// `~/get_state`: the node's current state.
    pub fn get_state(&mut self, timeout: Duration) -> Result<msg::State, LifecycleCallError> {
        let service = self.service("get_state");
        self.get_state
            .call(Default::default(), timeout)
            .map(|r| r.current_state)
            .map_err(|source| LifecycleCallError { service, source })
    }

    /// `~/change_state`: whether the transition was taken and its callback succeeded.
    pub fn change_state(
        &mut self,
        transition: impl Into<TransitionRequest>,
        timeout: Duration,
    ) -> Result<bool, LifecycleCallError> {
        let service = self.service("change_state");
        let request = ChangeStateRequest {
            transition: transition.into().to_msg(),
        };
        self.change_state
            .call(request, timeout)
            .map(|r| r.success)
            .map_err(|source| LifecycleCallError { service, source })
    }

    /// `~/get_available_states`: every state of the node's state machine.
    pub fn available_states(
        &mut self,
        timeout: Duration,
    ) -> Result<Vec<msg::State>, LifecycleCallError> {
        let service = self.service("get_available_states");
        self.get_available_states
            .call(Default::default(), timeout)
            .map(|r| r.available_states)
            .map_err(|source| LifecycleCallError { service, source })
    }

    /// `~/get_available_transitions`: the transitions valid from the current state.
    pub fn available_transitions(
        &mut self,
        timeout: Duration,
    ) -> Result<Vec<TransitionDescription>, LifecycleCallError> {
        let service = self.service("get_available_transitions");
        self.get_available_transitions
            .call(Default::default(), timeout)
            .map(|r| r.available_transitions)
            .map_err(|source| LifecycleCallError { service, source })
    }

    /// `~/get_transition_graph`: every transition of the node's state machine.
    pub fn transition_graph(
        &mut self,
        timeout: Duration,
    ) -> Result<Vec<TransitionDescription>, LifecycleCallError> {
        let service = self.service("get_transition_graph");
        self.get_transition_graph
            .call(Default::default(), timeout)
            .map(|r| r.available_transitions)
            .map_err(|source| LifecycleCallError { service, source })
    }

    fn service(&self, name: &str) -> String {
        format!("{}/{name}", self.target.trim_end_matches('/'))
    }
}
