//! [`NodeServices`]: the services every Jazzy rclcpp/rclpy node offers, so that `ros2 param
//! list/get/set/describe/dump` and `ros2 service call …/get_type_description` work on a horus-ros
//! node.
//!
//! Under the node's fully-qualified name (`/ns/node/…`):
//!
//! | service | type | QoS |
//! |---|---|---|
//! | `~/describe_parameters` | `rcl_interfaces/srv/DescribeParameters` | `parameters` |
//! | `~/get_parameter_types` | `rcl_interfaces/srv/GetParameterTypes` | `parameters` |
//! | `~/get_parameters` | `rcl_interfaces/srv/GetParameters` | `parameters` |
//! | `~/list_parameters` | `rcl_interfaces/srv/ListParameters` | `parameters` |
//! | `~/set_parameters` | `rcl_interfaces/srv/SetParameters` | `parameters` |
//! | `~/set_parameters_atomically` | `rcl_interfaces/srv/SetParametersAtomically` | `parameters` |
//! | `~/get_type_description` | `type_description_interfaces/srv/GetTypeDescription` | `services_default` |
//!
//! (rclcpp 28 `ParameterService` uses `rclcpp::ParametersQoS()` = `rmw_qos_profile_parameters`;
//! rcl 9.2 `rcl_node_type_description_service_init` uses the default service options.)
//!
//! The parameter services answer from a [`Parameters`] store with rclcpp's semantics, the type
//! description service from a [`TypeRegistry`] with rcl's.

mod types;

pub use horus_ros_parameters::{
    type_name as parameter_type_name, ParameterChange, ParameterError, ParameterValueExt,
    Parameters,
};
pub use types::{TypeRegistry, FAILURE_NOT_IN_USE, FAILURE_PARSE_HASH};

use std::sync::{Arc, Weak};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::rcl_interfaces::msg::SetParametersResult;
use horus_ros_msgs::rcl_interfaces::msg::{
    ListParametersResult, Parameter, ParameterDescriptor, ParameterEvent, ParameterValue,
};
use horus_ros_msgs::rcl_interfaces::srv::{
    DescribeParameters, DescribeParametersResponse, GetParameterTypes, GetParameterTypesResponse,
    GetParameters, GetParametersResponse, ListParameters, ListParametersResponse, SetParameters,
    SetParametersAtomically, SetParametersAtomicallyResponse, SetParametersResponse,
};
use horus_ros_msgs::type_description_interfaces::srv::GetTypeDescription;
use horus_ros_msgs::{Message, Service, TypeHash};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Node, Publisher};

use crate::{EndpointBuilder, ServiceServer, ServiceServerBuilder, SetupError};

/// The reason rclcpp's `~/set_parameters_atomically` gives when a parameter is not declared.
pub const REASON_ATOMICALLY_NOT_DECLARED: &str =
    "One or more parameters were not declared before setting";

/// How [`NodeServices::start_with`] sets up the store.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeServicesOptions {
    /// rclcpp's `allow_undeclared_parameters` (default false): setting an undeclared parameter
    /// declares it, dynamically typed; getting, typing or describing one answers
    /// `PARAMETER_NOT_SET` / a default descriptor instead of an empty response.
    pub allow_undeclared_parameters: bool,
    /// Declare `use_sim_time` (bool, false), as every ROS node's time source does (default true).
    pub declare_use_sim_time: bool,
    /// Declare `start_type_description_service` (bool, true, read-only), as every rclcpp node
    /// does (default true).
    pub declare_start_type_description_service: bool,
    /// rclcpp's `start_parameter_event_publisher` (default true): publish a
    /// `rcl_interfaces/msg/ParameterEvent` on `/parameter_events` (QoS `parameter_events`) for
    /// every change of the store ([`ParameterChange`]), from before the first declaration on.
    pub start_parameter_event_publisher: bool,
}

impl Default for NodeServicesOptions {
    fn default() -> Self {
        Self {
            allow_undeclared_parameters: false,
            declare_use_sim_time: true,
            declare_start_type_description_service: true,
            start_parameter_event_publisher: true,
        }
    }
}

/// The services every Jazzy rclcpp/rclpy node offers, so that `ros2 param
/// list/get/set/describe/dump` and `ros2 service call …/get_type_description` work on a horus-ros
/// node, served from background threads.
///
/// Under the node's fully-qualified name (`/ns/node/…`):
///
/// | service | type | QoS |
/// |---|---|---|
/// | `~/describe_parameters` | `rcl_interfaces/srv/DescribeParameters` | `parameters` |
/// | `~/get_parameter_types` | `rcl_interfaces/srv/GetParameterTypes` | `parameters` |
/// | `~/get_parameters` | `rcl_interfaces/srv/GetParameters` | `parameters` |
/// | `~/list_parameters` | `rcl_interfaces/srv/ListParameters` | `parameters` |
/// | `~/set_parameters` | `rcl_interfaces/srv/SetParameters` | `parameters` |
/// | `~/set_parameters_atomically` | `rcl_interfaces/srv/SetParametersAtomically` | `parameters` |
/// | `~/get_type_description` | `type_description_interfaces/srv/GetTypeDescription` | `services_default` |
///
/// (rclcpp 28 `ParameterService` uses `rclcpp::ParametersQoS()` = `rmw_qos_profile_parameters`;
/// rcl 9.2 `rcl_node_type_description_service_init` uses the default service options.)
///
/// The parameter services answer from a [`Parameters`] store with rclcpp's semantics, the type
/// description service from a [`TypeRegistry`] with rcl's.
///
/// With [`NodeServicesOptions::start_parameter_event_publisher`] (the default), it also
/// publishes the store's changes on `/parameter_events`, as rclcpp's `NodeParameters`.
///
/// Dropping it stops the services (each server thread is joined) and the event publisher.
#[must_use = "the node's services are served only while this is held"]
pub struct NodeServices {
    parameters: Parameters,
    /// `/parameter_events`; the store's change listener holds it weakly, so that it goes with
    /// the services even while the application keeps a handle of the store.
    _events: Option<Arc<Publisher<ParameterEvent>>>,
    types: TypeRegistry,
    node_name: String,
    describe: ServiceServer<DescribeParameters>,
    get_types: ServiceServer<GetParameterTypes>,
    get: ServiceServer<GetParameters>,
    list: ServiceServer<ListParameters>,
    set: ServiceServer<SetParameters>,
    set_atomically: ServiceServer<SetParametersAtomically>,
    type_description: ServiceServer<GetTypeDescription>,
}

impl std::fmt::Debug for NodeServices {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NodeServices")
            .field("node", &self.node_name)
            .field("parameters", &self.parameters.names())
            .finish()
    }
}

impl NodeServices {
    /// Starts the seven services on `node` with [default options](NodeServicesOptions).
    pub fn start(node: &Node) -> Result<Self, SetupError> {
        Self::start_with(node, NodeServicesOptions::default())
    }

    /// Starts the seven services on `node`.
    pub fn start_with(node: &Node, options: NodeServicesOptions) -> Result<Self, SetupError> {
        let parameters = Parameters::new(options.allow_undeclared_parameters);
        let types = TypeRegistry::new();
        // rclcpp creates the publisher before any declaration, so the node's own declarations
        // (use_sim_time, the overrides) are published too.
        let events = if options.start_parameter_event_publisher {
            let publisher = Arc::new(node.create_publisher::<ParameterEvent>(
                "/parameter_events",
                &Qos::parameter_events(),
            )?);
            // rcl registers the type of every publisher it creates for ~/get_type_description.
            types.register_type::<ParameterEvent>();
            let weak = Arc::downgrade(&publisher);
            let node_name = node.fully_qualified_name();
            parameters.on_change(move |change| publish_event(&weak, &node_name, change));
            Some(publisher)
        } else {
            None
        };
        if options.declare_use_sim_time {
            // Cannot fail on an empty store.
            let _ = parameters.declare(
                "use_sim_time",
                ParameterValue::from_bool(false),
                ParameterDescriptor::default(),
            );
        }
        if options.declare_start_type_description_service {
            let _ = parameters.declare(
                "start_type_description_service",
                ParameterValue::from_bool(true),
                ParameterDescriptor {
                    description: "Start the ~/get_type_description service for this node."
                        .to_owned(),
                    read_only: true,
                    ..ParameterDescriptor::default()
                },
            );
        }
        // The parameters the process was given for this node (`-p`, `--params-file`), declared
        // as rclcpp does with `automatically_declare_parameters_from_overrides`, so that
        // `ros2 param get` sees them.
        for (name, value) in node
            .context()
            .arguments()
            .parameters_for(&node.fully_qualified_name())
        {
            let result = if parameters.get(&name).is_ok() {
                parameters.set(&name, value).map(|_| ())
            } else {
                parameters
                    .declare(&name, value, ParameterDescriptor::default())
                    .map(|_| ())
            };
            if let Err(err) = result {
                tracing::warn!(
                    node = %node.fully_qualified_name(),
                    "parameter override '{name}' not applied: {err}"
                );
            }
        }
        let qos = Qos::parameters();

        let p = parameters.clone();
        let describe = server::<DescribeParameters>(node, "~/describe_parameters", qos, &types)
            .on_request(move |req| {
                Ok(DescribeParametersResponse {
                    descriptors: p.describe_many(&req.names),
                })
            })
            .build()?;
        let p = parameters.clone();
        let get_types = server::<GetParameterTypes>(node, "~/get_parameter_types", qos, &types)
            .on_request(move |req| {
                Ok(GetParameterTypesResponse {
                    types: p.types_many(&req.names),
                })
            })
            .build()?;
        let p = parameters.clone();
        let get = server::<GetParameters>(node, "~/get_parameters", qos, &types)
            .on_request(move |req| {
                Ok(GetParametersResponse {
                    values: p.get_many(&req.names),
                })
            })
            .build()?;
        let p = parameters.clone();
        let list = server::<ListParameters>(node, "~/list_parameters", qos, &types)
            .on_request(move |req| {
                Ok(ListParametersResponse {
                    result: p.list(&req.prefixes, req.depth),
                })
            })
            .build()?;
        let p = parameters.clone();
        let set = server::<SetParameters>(node, "~/set_parameters", qos, &types)
            .on_request(move |req| {
                // One by one, each atomically, as rclcpp's ParameterService.
                let results = req
                    .parameters
                    .into_iter()
                    .map(|param| match p.set_atomically_result(&[param]) {
                        Ok(result) => result,
                        Err(not_declared) => SetParametersResult {
                            successful: false,
                            reason: not_declared.reason(),
                        },
                    })
                    .collect();
                Ok(SetParametersResponse { results })
            })
            .build()?;
        let p = parameters.clone();
        let set_atomically =
            server::<SetParametersAtomically>(node, "~/set_parameters_atomically", qos, &types)
                .on_request(move |req| {
                    let result = p
                        .set_atomically_result(&req.parameters)
                        .unwrap_or_else(|_| SetParametersResult {
                            successful: false,
                            reason: REASON_ATOMICALLY_NOT_DECLARED.to_owned(),
                        });
                    Ok(SetParametersAtomicallyResponse { result })
                })
                .build()?;
        let t = types.clone();
        let type_description = server::<GetTypeDescription>(
            node,
            "~/get_type_description",
            Qos::services_default(),
            &types,
        )
        .on_request(move |req| Ok(t.handle_request(&req)))
        .build()?;

        let node_services = Self {
            parameters,
            _events: events,
            types,
            node_name: node.fully_qualified_name(),
            describe,
            get_types,
            get,
            list,
            set,
            set_atomically,
            type_description,
        };
        tracing::debug!(node = %node_services.node_name, "node services started");
        Ok(node_services)
    }

    /// The parameter store the services answer from (a shared handle: clone it freely).
    pub fn parameters(&self) -> &Parameters {
        &self.parameters
    }

    /// The type registry `~/get_type_description` answers from (a shared handle).
    pub fn types(&self) -> &TypeRegistry {
        &self.types
    }

    /// The fully-qualified name of the node served.
    pub fn node_name(&self) -> &str {
        &self.node_name
    }

    /// The fully-qualified names of the seven services.
    pub fn service_names(&self) -> Vec<ServiceName> {
        vec![
            self.describe.name().clone(),
            self.get_types.name().clone(),
            self.get.name().clone(),
            self.list.name().clone(),
            self.set.name().clone(),
            self.set_atomically.name().clone(),
            self.type_description.name().clone(),
        ]
    }

    /// Declares a parameter: [`Parameters::declare`].
    pub fn declare_parameter(
        &self,
        name: &str,
        value: ParameterValue,
        descriptor: ParameterDescriptor,
    ) -> Result<ParameterValue, ParameterError> {
        self.parameters.declare(name, value, descriptor)
    }

    /// A parameter's value: [`Parameters::get`].
    pub fn get_parameter(&self, name: &str) -> Result<ParameterValue, ParameterError> {
        self.parameters.get(name)
    }

    /// Sets a parameter: [`Parameters::set`].
    pub fn set_parameter(&self, name: &str, value: ParameterValue) -> Result<(), ParameterError> {
        self.parameters.set(name, value)
    }

    /// Sets parameters all or none: [`Parameters::set_atomically`].
    pub fn set_parameters_atomically(
        &self,
        parameters: &[Parameter],
    ) -> Result<(), ParameterError> {
        self.parameters.set_atomically(parameters)
    }

    /// Undeclares a parameter: [`Parameters::undeclare`].
    pub fn undeclare_parameter(&self, name: &str) -> Result<(), ParameterError> {
        self.parameters.undeclare(name)
    }

    /// Lists parameters: [`Parameters::list`].
    pub fn list_parameters(&self, prefixes: &[String], depth: u64) -> ListParametersResult {
        self.parameters.list(prefixes, depth)
    }

    /// Registers a message type for `~/get_type_description`: [`TypeRegistry::register_type`].
    pub fn register_type<M: Message>(&self) -> TypeHash {
        self.types.register_type::<M>()
    }

    /// Registers a service type for `~/get_type_description`:
    /// [`TypeRegistry::register_service`].
    pub fn register_service<S: Service>(&self) -> TypeHash {
        self.types.register_service::<S>()
    }
}

/// rclcpp's `events_publisher_->publish(parameter_event)`, stamped with the system time (the
/// node clock without `use_sim_time`).
fn publish_event(
    publisher: &Weak<Publisher<ParameterEvent>>,
    node_name: &str,
    change: &ParameterChange,
) {
    let Some(publisher) = publisher.upgrade() else {
        return;
    };
    let event = ParameterEvent {
        stamp: Time::now(),
        node: node_name.to_owned(),
        new_parameters: change.new_parameters.clone(),
        changed_parameters: change.changed_parameters.clone(),
        deleted_parameters: change.deleted_parameters.clone(),
    };
    if let Err(err) = publisher.publish(event) {
        tracing::debug!(node = %node_name, "/parameter_events: {err}");
    }
}

/// A server builder for one of the node's services, registering its type as rcl does for every
/// service it creates.
fn server<S: Service>(
    node: &Node,
    name: &str,
    qos: Qos,
    types: &TypeRegistry,
) -> ServiceServerBuilder<S> {
    types.register_service::<S>();
    ServiceServer::<S>::builder().node(node).name(name).qos(qos)
}
