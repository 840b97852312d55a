//! [`DynamicServiceClient`]: calls a service whose type is known only at run time (by name, DDS
//! type names and hashes), sending and receiving CDR bodies the caller encodes and decodes —
//! how `horus-ros service call` reaches services of packages it was not built with.

use std::time::{Duration, Instant};

use horus_ros_msgs::TypeHash;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node};

use super::codec::{Raw, RawReply};
use super::core::{ClientCore, ClientOptions};
use super::responses::Membership;
use crate::naming::ServiceTopics;
use crate::runtime::Runtime;
use crate::WireFlavour;
use crate::{ServiceError, SetupError};

/// One side of a service type: its DDS type name and RIHS01 hash.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DynamicPart {
    /// The DDS type name (`pkg::srv::dds_::Name_Request_`).
    pub dds_type_name: String,
    /// The RIHS01 hash of the part (`pkg/srv/Name_Request`).
    pub type_hash: TypeHash,
}

/// Builds a [`DynamicServiceClient`].
#[must_use = "a builder does nothing until .build() is called"]
#[derive(Clone, Debug)]
pub struct DynamicServiceClientBuilder {
    options: ClientOptions,
    service_type: String,
    request: DynamicPart,
    response: DynamicPart,
}

impl DynamicServiceClientBuilder {
    /// Calls from `node` instead of the process's default node.
    pub fn node(mut self, node: &Node) -> Self {
        self.options.node = Some(node.clone());
        self
    }

    /// The QoS of the request writer and reply reader (default: `services_default`).
    pub fn qos(mut self, qos: Qos) -> Self {
        self.options.qos = qos;
        self
    }

    /// Uses this wire convention instead of the one of the server found.
    pub fn wire_flavour(mut self, flavour: WireFlavour) -> Self {
        self.options.flavour = Some(flavour);
        self
    }

    /// Creates the request writer and reply reader.
    pub fn build(self) -> Result<DynamicServiceClient, SetupError> {
        let runtime = Runtime::for_node(self.options.node.as_ref())?;
        let name = self.options.name.clone().unwrap_or_default();
        let topics = ServiceTopics::resolve_parts(
            &runtime.node,
            &name,
            &self.options.qos,
            horus_ros_rmw::ServiceEndpointRole::Client,
            (self.request.dds_type_name, self.request.type_hash),
            (self.response.dds_type_name, self.response.type_hash),
        )?;
        let codec = Raw {
            service_type: self.service_type,
        };
        let (core, responses) =
            ClientCore::with_codec(runtime, topics, codec, &self.options)?.join_responses()?;
        Ok(DynamicServiceClient { core, responses })
    }
}

/// A client for a service type known at run time; behaves like
/// [`ServiceClient`](crate::ServiceClient) (same server choice, wire conventions and errors).
pub struct DynamicServiceClient {
    core: std::sync::Arc<ClientCore<Raw>>,
    responses: Membership,
}

impl std::fmt::Debug for DynamicServiceClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DynamicServiceClient")
            .field("name", self.core.name())
            .finish()
    }
}

impl DynamicServiceClient {
    /// A builder for the service `name` of type `service_type` (`pkg/srv/Name`) whose request
    /// and response are `request` and `response`.
    pub fn builder(
        name: impl Into<String>,
        service_type: impl Into<String>,
        request: DynamicPart,
        response: DynamicPart,
    ) -> DynamicServiceClientBuilder {
        DynamicServiceClientBuilder {
            options: ClientOptions {
                name: Some(name.into()),
                ..ClientOptions::default()
            },
            service_type: service_type.into(),
            request,
            response,
        }
    }

    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        self.core.name()
    }

    /// The GIDs of the request writer and the reply reader.
    pub fn gids(&self) -> (Gid, Gid) {
        self.core.gids()
    }

    /// Whether a server of this type is on the graph with both its endpoints.
    pub fn server_available(&self) -> bool {
        self.core.server_available()
    }

    /// Waits until a server can take a call, at most `timeout`.
    pub fn wait_for_service(&self, timeout: Duration) -> bool {
        self.core.wait_ready(Instant::now() + timeout).is_ok()
    }

    /// Calls once with `request` (a CDR_LE body of the request message, no encapsulation
    /// header); the reply comes back as its body, any rmw_cyclonedds header removed.
    pub fn call(&mut self, request: Vec<u8>, timeout: Duration) -> Result<RawReply, ServiceError> {
        self.core.call_blocking(&self.responses, &request, timeout)
    }
}
