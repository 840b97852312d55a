//! [`DynamicServiceClient`]: calls a service whose type is known only at run time — by its
//! [`ServiceType`] (requests and responses as dynamic values, YAML or JSON), or by DDS type names
//! and hashes alone (CDR bodies the caller encodes and decodes) — how `horus-ros service call`
//! reaches services of packages it was not built with.

use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_dynamic::{DecodeError, RequestError, ServiceType, Value};
use horus_ros_msgs::{dds_type_name, TypeHash};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node};

use super::codec::{Raw, RawResponse};
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

/// Why a call with values ([`DynamicServiceClient::call_value`], `call_yaml`, `call_json`)
/// failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicCallError {
    /// The client was built from DDS type names only ([`DynamicServiceClient::builder`]), so it
    /// has no schema to fill a request or decode a response with.
    #[error(
        "this client knows its service type by DDS type names only; build it with \
         DynamicServiceClient::for_type to call with values"
    )]
    NoSchema,
    /// The request values do not fit the request type.
    #[error("invalid request for {service_type}: {cause}")]
    Request {
        /// The service type.
        service_type: String,
        /// What is wrong (the field named).
        cause: RequestError,
    },
    /// The call itself failed.
    #[error(transparent)]
    Call(#[from] ServiceError),
    /// The response does not decode as the response type.
    #[error("cannot decode the response as {service_type}: {cause}")]
    Response {
        /// The service type.
        service_type: String,
        /// What is wrong.
        cause: DecodeError,
    },
}

/// A [`DynamicCallError::Request`] for `service_type`.
fn invalid_request<E: Into<RequestError>>(
    service_type: &ServiceType,
) -> impl Fn(E) -> DynamicCallError + '_ {
    |source| DynamicCallError::Request {
        service_type: service_type.name().to_owned(),
        cause: source.into(),
    }
}

/// Builds a [`DynamicServiceClient`].
#[must_use = "a builder does nothing until .build() is called"]
#[derive(Clone, Debug)]
pub struct DynamicServiceClientBuilder {
    options: ClientOptions,
    service_type: String,
    request: DynamicPart,
    response: DynamicPart,
    schema: Option<Arc<ServiceType>>,
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
        Ok(DynamicServiceClient {
            core,
            responses,
            schema: self.schema,
        })
    }
}

/// A client for a service type known at run time; behaves like
/// [`ServiceClient`](crate::ServiceClient) (same server choice, wire conventions and errors).
#[must_use = "a client's endpoints exist only while it is held"]
pub struct DynamicServiceClient {
    core: Arc<ClientCore<Raw>>,
    responses: Membership,
    schema: Option<Arc<ServiceType>>,
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
            schema: None,
        }
    }

    /// A builder for the service `name` of the run-time type `service_type` (e.g.
    /// [`ServiceType::compiled`], or [`ServiceType::from_descriptions`] on what a node's
    /// `~/get_type_description` returned): its calls can take and give dynamic values, YAML and
    /// JSON.
    pub fn for_type(
        name: impl Into<String>,
        service_type: ServiceType,
    ) -> DynamicServiceClientBuilder {
        let (request_hash, response_hash) = service_type.part_hashes();
        let mut builder = Self::builder(
            name,
            service_type.name(),
            DynamicPart {
                dds_type_name: dds_type_name(service_type.request_type()),
                type_hash: request_hash,
            },
            DynamicPart {
                dds_type_name: dds_type_name(service_type.response_type()),
                type_hash: response_hash,
            },
        );
        builder.schema = Some(Arc::new(service_type));
        builder
    }

    /// The run-time service type, for a call with values.
    fn schema(&self) -> Result<Arc<ServiceType>, DynamicCallError> {
        self.schema.clone().ok_or(DynamicCallError::NoSchema)
    }

    /// The run-time service type, when the client was built with [`for_type`](Self::for_type).
    pub fn service_type(&self) -> Option<&ServiceType> {
        self.schema.as_deref()
    }

    /// The fully-qualified service name.
    pub fn name(&self) -> &ServiceName {
        self.core.name()
    }

    /// The GIDs of the request writer and the reply reader.
    pub fn gids(&self) -> (Gid, Gid) {
        self.core.gids()
    }

    /// Whether a server of this service and type is known to the graph with both its endpoints
    /// (discovered; see [the readiness words](crate#readiness)).
    pub fn server_available(&self) -> bool {
        self.core.server_available()
    }

    /// Whether a server can take a call now: known, and matched with this client both ways
    /// (rclcpp `service_is_ready`; see [the readiness words](crate#readiness)).
    pub fn is_server_ready(&self) -> bool {
        self.core.is_server_ready()
    }

    /// Waits until [`is_server_ready`](Self::is_server_ready), at most `timeout` (rclcpp
    /// `wait_for_service`); woken by graph changes, never polled.
    pub fn wait_for_service(&self, timeout: Duration) -> bool {
        self.core.wait_ready(Instant::now() + timeout).is_ok()
    }

    /// Calls once with `request` (a CDR_LE body of the request message, no encapsulation
    /// header); the reply comes back as its body, any rmw_cyclonedds header removed.
    pub fn call(
        &mut self,
        request: Vec<u8>,
        timeout: Duration,
    ) -> Result<RawResponse, ServiceError> {
        self.core.call_blocking(&self.responses, &request, timeout)
    }

    /// Calls once with `request` (a value of the request type, e.g. from
    /// [`ServiceType::request_from_yaml`]); the response comes back as a value of the response
    /// type.
    pub fn call_value(
        &mut self,
        request: &Value,
        timeout: Duration,
    ) -> Result<Value, DynamicCallError> {
        let schema = self.schema()?;
        let body = schema
            .encode_request(request)
            .map_err(invalid_request(&schema))?;
        let reply = self.call(body, timeout)?;
        schema
            .decode_response(&reply.body, reply.big_endian)
            .map_err(|source| DynamicCallError::Response {
                service_type: schema.name().to_owned(),
                cause: source,
            })
    }

    /// Calls once with the request filled from ros2cli's YAML (`'{a: 1, b: 2}'`, as
    /// `ros2 service call` takes it); fields not given keep their defaults.
    pub fn call_yaml(
        &mut self,
        request: &str,
        timeout: Duration,
    ) -> Result<Value, DynamicCallError> {
        let schema = self.schema()?;
        let request = schema
            .request_from_yaml(request)
            .map_err(invalid_request(&schema))?;
        self.call_value(&request, timeout)
    }

    /// Calls once with the request filled from a JSON object of its fields (checked as YAML
    /// values are); the response comes back as a JSON object of its fields.
    pub fn call_json(
        &mut self,
        request: &serde_json::Value,
        timeout: Duration,
    ) -> Result<serde_json::Value, DynamicCallError> {
        let schema = self.schema()?;
        let request = schema
            .request_from_json(request)
            .map_err(invalid_request(&schema))?;
        let response = self.call_value(&request, timeout)?;
        Ok(schema.response_to_json(&response))
    }
}
