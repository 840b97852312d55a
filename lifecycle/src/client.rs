//! [`LifecycleClient`]: drive another node's lifecycle through its services, as ros2lifecycle's
//! `api/__init__.py` (`call_get_states`, `call_get_available_transitions`,
//! `call_get_transition_graph`, `call_change_states`) does.

use std::time::{Duration, Instant};

use horus_ros_msgs::lifecycle_msgs::msg::{self, TransitionDescription};
use horus_ros_msgs::lifecycle_msgs::srv::{
    ChangeState, ChangeStateRequest, GetAvailableStates, GetAvailableTransitions, GetState,
};
use horus_ros_msgs::Service;
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

/// The lifecycle services' names under a node, in rcl's order (`com_interface.c`).
const SERVICES: [&str; 5] = [
    "get_state",
    "change_state",
    "get_available_states",
    "get_available_transitions",
    "get_transition_graph",
];

/// Why a call of a [`LifecycleClient`] failed (the cause is the source).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LifecycleCallError {
    /// The service's client could not be created.
    #[error("could not create a client of {service}")]
    Setup {
        /// The service (`/node/get_state` …).
        service: String,
        /// Why.
        #[source]
        source: SetupError,
    },
    /// The call failed (no server, timeout, transport).
    #[error("calling {service} failed")]
    Call {
        /// The service called.
        service: String,
        /// What went wrong.
        #[source]
        source: ServiceError,
    },
}

impl LifecycleCallError {
    /// The service-level error of a failed call (`None` for a setup error).
    pub fn service_error(&self) -> Option<&ServiceError> {
        match self {
            LifecycleCallError::Call { source, .. } => Some(source),
            LifecycleCallError::Setup { .. } => None,
        }
    }
}

fn setup_failed(service: &str, source: SetupError) -> LifecycleCallError {
    LifecycleCallError::Setup {
        service: service.to_owned(),
        source,
    }
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

    /// Makes the client; each service's client is created on its first use.
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
        Ok(LifecycleClient {
            node,
            target,
            change_state: None,
            get_state: None,
            get_available_states: None,
            get_available_transitions: None,
            get_transition_graph: None,
        })
    }
}

/// Clients of one managed node's five lifecycle services.
///
/// Every call waits (within its timeout) until the service is ready, then calls it.
pub struct LifecycleClient {
    node: Node,
    target: String,
    change_state: Option<ServiceClient<ChangeState>>,
    get_state: Option<ServiceClient<GetState>>,
    get_available_states: Option<ServiceClient<GetAvailableStates>>,
    get_available_transitions: Option<ServiceClient<GetAvailableTransitions>>,
    get_transition_graph: Option<ServiceClient<GetAvailableTransitions>>,
}

/// The client in `slot`, created for `<target>/<service>` on first use.
fn ensure<'a, S: Service>(
    slot: &'a mut Option<ServiceClient<S>>,
    node: &Node,
    name: &str,
) -> Result<&'a mut ServiceClient<S>, SetupError> {
    let client = match slot.take() {
        Some(client) => client,
        None => ServiceClient::<S>::builder()
            .node(node)
            .name(name)
            .build()?,
    };
    Ok(slot.insert(client))
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

    /// Creates the five clients and waits until all five services are ready (woken by graph
    /// changes); false at the timeout.
    pub fn wait_for_services(&mut self, timeout: Duration) -> Result<bool, SetupError> {
        let deadline = Instant::now() + timeout;
        let left = || deadline.saturating_duration_since(Instant::now());
        let [a, b, c, d, e] = SERVICES.map(|s| self.service(s));
        let node = &self.node;
        Ok(
            ensure(&mut self.get_state, node, &a)?.wait_for_service(left())
                && ensure(&mut self.change_state, node, &b)?.wait_for_service(left())
                && ensure(&mut self.get_available_states, node, &c)?.wait_for_service(left())
                && ensure(&mut self.get_available_transitions, node, &d)?.wait_for_service(left())
                && ensure(&mut self.get_transition_graph, node, &e)?.wait_for_service(left()),
        )
    }

    /// `~/get_state`: the node's current state.
    pub fn get_state(&mut self, timeout: Duration) -> Result<msg::State, LifecycleCallError> {
        let service = self.service("get_state");
        ensure(&mut self.get_state, &self.node, &service)
            .map_err(|e| setup_failed(&service, e))?
            .call(Default::default(), timeout)
            .map(|r| r.current_state)
            .map_err(|source| LifecycleCallError::Call { service, source })
    }

    /// `~/change_state`: whether the transition was taken and its callback succeeded.
    pub fn change_state(
        &mut self,
        transition: impl Into<TransitionRequest>,
        timeout: Duration,
    ) -> Result<bool, LifecycleCallError> {
        self.change_state_msg(transition.into().to_msg(), timeout)
    }

    /// `~/change_state` with the `lifecycle_msgs/msg/Transition` as given (ros2lifecycle's
    /// `set` sends the transition description's, id and label).
    pub fn change_state_msg(
        &mut self,
        transition: msg::Transition,
        timeout: Duration,
    ) -> Result<bool, LifecycleCallError> {
        let service = self.service("change_state");
        ensure(&mut self.change_state, &self.node, &service)
            .map_err(|e| setup_failed(&service, e))?
            .call(ChangeStateRequest { transition }, timeout)
            .map(|r| r.success)
            .map_err(|source| LifecycleCallError::Call { service, source })
    }

    /// `~/get_available_states`: every state of the node's state machine.
    pub fn available_states(
        &mut self,
        timeout: Duration,
    ) -> Result<Vec<msg::State>, LifecycleCallError> {
        let service = self.service("get_available_states");
        ensure(&mut self.get_available_states, &self.node, &service)
            .map_err(|e| setup_failed(&service, e))?
            .call(Default::default(), timeout)
            .map(|r| r.available_states)
            .map_err(|source| LifecycleCallError::Call { service, source })
    }

    /// `~/get_available_transitions`: the transitions valid from the current state.
    pub fn available_transitions(
        &mut self,
        timeout: Duration,
    ) -> Result<Vec<TransitionDescription>, LifecycleCallError> {
        let service = self.service("get_available_transitions");
        ensure(&mut self.get_available_transitions, &self.node, &service)
            .map_err(|e| setup_failed(&service, e))?
            .call(Default::default(), timeout)
            .map(|r| r.available_transitions)
            .map_err(|source| LifecycleCallError::Call { service, source })
    }

    /// `~/get_transition_graph`: every transition of the node's state machine.
    pub fn transition_graph(
        &mut self,
        timeout: Duration,
    ) -> Result<Vec<TransitionDescription>, LifecycleCallError> {
        let service = self.service("get_transition_graph");
        ensure(&mut self.get_transition_graph, &self.node, &service)
            .map_err(|e| setup_failed(&service, e))?
            .call(Default::default(), timeout)
            .map(|r| r.available_transitions)
            .map_err(|source| LifecycleCallError::Call { service, source })
    }

    /// `<target>/<name>`.
    fn service(&self, name: &str) -> String {
        format!("{}/{name}", self.target.trim_end_matches('/'))
    }
}
