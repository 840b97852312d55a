//! [`EndpointOptions`] and [`EndpointBuilder`]: the settings every service endpoint shares — node,
//! name, QoS, wire convention — and their setters, written once for every builder (in the manner
//! of rclrs's `PrimitiveOptions` / `IntoPrimitiveOptions`, `rclrs/src/node/primitive_options.rs`).

use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Node;

use crate::WireFlavour;

/// The settings every service endpoint has, whatever its kind (typed, async, dynamic or raw;
/// client or server): the node it lives on, its name, the QoS of its request and reply topics,
/// and the wire convention it speaks.
///
/// Every endpoint builder holds one and sets it through the [`EndpointBuilder`] setters. An
/// `EndpointOptions` is itself built with the same setters, so one set can be given to several
/// builders ([`EndpointBuilder::options`]):
///
/// ```no_run
/// use horus_ros_services::prelude::*;
///
/// let node = horus_ros_services::default_node()?;
/// let options = EndpointOptions::default().node(&node).name("/add_two_ints");
/// let _server = ServiceServer::<AddTwoInts>::builder()
///     .options(options.clone())
///     .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
///     .build()?;
/// let _client = ServiceClient::<AddTwoInts>::builder().options(options).build()?;
/// # Ok::<(), horus_ros_services::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct EndpointOptions {
    pub(crate) node: Option<Node>,
    pub(crate) name: Option<String>,
    pub(crate) qos: Qos,
    pub(crate) wire_flavour: Option<WireFlavour>,
}

impl Default for EndpointOptions {
    /// The process's default node, the service type's default name
    /// ([`default_service_name`](crate::default_service_name)), QoS `services_default`, and the
    /// wire convention chosen per peer from its DDS vendor.
    fn default() -> Self {
        Self {
            node: None,
            name: None,
            qos: Qos::services_default(),
            wire_flavour: None,
        }
    }
}

impl EndpointOptions {
    /// The node set with [`EndpointBuilder::node`], if any (layers built on services, such as
    /// actions, create their own topics on it).
    pub fn configured_node(&self) -> Option<&Node> {
        self.node.as_ref()
    }

    /// The name set with [`EndpointBuilder::name`], if any.
    pub fn configured_name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// The QoS of the request and reply topics.
    pub fn configured_qos(&self) -> &Qos {
        &self.qos
    }

    /// The wire convention set with [`EndpointBuilder::wire_flavour`], if any.
    pub fn configured_wire_flavour(&self) -> Option<WireFlavour> {
        self.wire_flavour
    }
}

impl EndpointBuilder for EndpointOptions {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        self
    }
}

/// The setters of [`EndpointOptions`], shared by every endpoint builder of this crate
/// ([`ServiceServerBuilder`](crate::ServiceServerBuilder),
/// [`ServiceClientBuilder`](crate::ServiceClientBuilder),
/// [`DynamicServiceClientBuilder`](crate::DynamicServiceClientBuilder),
/// [`DdsServiceServerBuilder`](crate::DdsServiceServerBuilder),
/// [`DdsServiceClientBuilder`](crate::DdsServiceClientBuilder) and, with feature `tokio`,
/// `AsyncServiceServerBuilder`) and by [`EndpointOptions`] itself. In the
/// [`prelude`](crate::prelude); elsewhere `use horus_ros_services::EndpointBuilder` to call them.
///
/// What is particular to one kind of endpoint (a server's handler, a raw client's send timeout,
/// introspection where it is supported) stays a method of its builder.
pub trait EndpointBuilder: Sized {
    /// The options the setters change.
    fn options_mut(&mut self) -> &mut EndpointOptions;

    /// Creates the endpoint on `node` instead of the process's default node
    /// ([`default_node`](crate::default_node)).
    fn node(mut self, node: &Node) -> Self {
        self.options_mut().node = Some(node.clone());
        self
    }

    /// The service name; relative names, `~` and substitutions expand as in rcl (default: the
    /// service type's name in snake case, [`default_service_name`](crate::default_service_name)).
    fn name(mut self, name: impl Into<String>) -> Self {
        self.options_mut().name = Some(name.into());
        self
    }

    /// The QoS of the endpoint's request and reply topics (default: `services_default`).
    fn qos(mut self, qos: Qos) -> Self {
        self.options_mut().qos = qos;
        self
    }

    /// Speaks this wire convention with every peer instead of choosing per peer from its DDS
    /// vendor: a server answers every client in it, a client calls every server in it.
    fn wire_flavour(mut self, flavour: WireFlavour) -> Self {
        self.options_mut().wire_flavour = Some(flavour);
        self
    }

    /// Replaces all the options at once with `options` (e.g. one set shared by a server and its
    /// clients).
    fn options(mut self, options: EndpointOptions) -> Self {
        *self.options_mut() = options;
        self
    }
}
