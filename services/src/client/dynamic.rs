//! [`DynamicServiceClient`]: calls a service whose type is known only at run time — by its
//! [`ServiceType`] (requests and responses as dynamic values, YAML or JSON), or by DDS type names
//! and hashes alone (CDR bodies the caller encodes and decodes) — how `horus-ros service call`
//! reaches services of packages it was not built with.

use std::sync::Arc;
use std::time::Duration;

use horus_ros_dynamic::{DecodeError, RequestError, ServiceType, Value};
use horus_ros_msgs::{dds_type_name, TypeHash};

use super::codec::{Raw, RawResponse};
use super::core::{client_handle_methods, ClientCore, ClientOptions};
use super::responses::Membership;
use crate::runtime::Runtime;
use crate::{EndpointBuilder, EndpointOptions, ServiceError, SetupError};

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
    /// The client was built from DDS type names only ([`DynamicServiceType::Parts`]), so it
    /// has no schema to fill a request or decode a response with.
    #[error(
        "this client knows its service type by DDS type names only; build it from a ServiceType \
         to call with values"
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

/// What a [`DynamicServiceClient`] knows of its service type: the argument of
/// [`DynamicServiceClient::builder`].
#[derive(Clone, Debug)]
pub enum DynamicServiceType {
    /// The whole type (e.g. [`ServiceType::compiled`], or [`ServiceType::from_descriptions`] on
    /// what a node's `~/get_type_description` returned): calls can take and give dynamic values,
    /// YAML and JSON as well as CDR bodies.
    Schema(ServiceType),
    /// The DDS type names and hashes alone: calls take and give CDR bodies only
    /// ([`DynamicServiceClient::call`]).
    Parts {
        /// The service type's name (`pkg/srv/Name`).
        service_type: String,
        /// The request part.
        request: DynamicPart,
        /// The response part.
        response: DynamicPart,
    },
}

impl From<ServiceType> for DynamicServiceType {
    fn from(service_type: ServiceType) -> Self {
        Self::Schema(service_type)
    }
}

/// Builds a [`DynamicServiceClient`] ([`DynamicServiceClient::builder`]). Node, name, QoS and
/// wire convention are set with the [`EndpointBuilder`] setters.
#[must_use = "a builder does nothing until .build() is called"]
#[derive(Clone, Debug)]
pub struct DynamicServiceClientBuilder {
    options: ClientOptions,
    service_type: String,
    /// The service type's RIHS01 hash (ZERO for [`DynamicServiceType::Parts`]).
    service_hash: TypeHash,
    request: DynamicPart,
    response: DynamicPart,
    schema: Option<Arc<ServiceType>>,
}

impl EndpointBuilder for DynamicServiceClientBuilder {
    fn options_mut(&mut self) -> &mut EndpointOptions {
        &mut self.options.endpoint
    }
}

impl DynamicServiceClientBuilder {
    /// Creates the request writer and reply reader.
    pub fn build(self) -> Result<DynamicServiceClient, SetupError> {
        let (runtime, topics) = Runtime::for_node(self.options.endpoint.node.as_ref())?
            .with_topics(
                &self.options.endpoint,
                horus_ros_rmw::ServiceEndpointRole::Client,
                (&self.service_type, self.service_hash),
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
    /// A builder of a client of a service of the run-time type `service_type`: a
    /// [`ServiceType`] (calls with values, YAML, JSON or CDR bodies) or
    /// [`DynamicServiceType::Parts`] (CDR bodies only). The type is the builder's argument
    /// because, unlike the options, it has no default: a dynamic client has no compiled type to
    /// take it from. The name defaults to the type's name in snake case, as for compiled types
    /// ([`default_service_name`](crate::default_service_name)).
    ///
    /// ```no_run
    /// use horus_ros_services::prelude::*;
    /// use horus_ros_services::{DynamicServiceClient, ServiceType};
    ///
    /// let service_type = ServiceType::compiled("example_interfaces/srv/AddTwoInts")
    ///     .ok_or("not compiled in")?;
    /// let mut client = DynamicServiceClient::builder(service_type)
    ///     .name("/add_two_ints")
    ///     .build()?;
    /// let sum = client.call_yaml("{a: 2, b: 3}", Duration::from_secs(1))?;
    /// println!("{sum:?}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn builder(service_type: impl Into<DynamicServiceType>) -> DynamicServiceClientBuilder {
        let (service_type, request, response, schema) = match service_type.into() {
            DynamicServiceType::Schema(schema) => {
                let (request_hash, response_hash) = schema.part_hashes();
                let request = DynamicPart {
                    dds_type_name: dds_type_name(schema.request_type()),
                    type_hash: request_hash,
                };
                let response = DynamicPart {
                    dds_type_name: dds_type_name(schema.response_type()),
                    type_hash: response_hash,
                };
                (
                    schema.name().to_owned(),
                    request,
                    response,
                    Some(Arc::new(schema)),
                )
            }
            DynamicServiceType::Parts {
                service_type,
                request,
                response,
            } => (service_type, request, response, None),
        };
        let service_hash = schema.as_ref().map_or(TypeHash::ZERO, |s| s.service_hash());
        DynamicServiceClientBuilder {
            options: ClientOptions::default(),
            service_type,
            service_hash,
            request,
            response,
            schema,
        }
    }

    /// The run-time service type, for a call with values.
    fn schema(&self) -> Result<Arc<ServiceType>, DynamicCallError> {
        self.schema.clone().ok_or(DynamicCallError::NoSchema)
    }

    /// The run-time service type, when the client was built from a [`ServiceType`].
    pub fn service_type(&self) -> Option<&ServiceType> {
        self.schema.as_deref()
    }

    client_handle_methods!(discovery);

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
        self.call_filled(timeout, |schema| schema.request_from_yaml(request))
            .map(|(_, response)| response)
    }

    /// Calls once with the request filled from a JSON object of its fields (checked as YAML
    /// values are); the response comes back as a JSON object of its fields.
    pub fn call_json(
        &mut self,
        request: &serde_json::Value,
        timeout: Duration,
    ) -> Result<serde_json::Value, DynamicCallError> {
        let (schema, response) =
            self.call_filled(timeout, |schema| schema.request_from_json(request))?;
        Ok(schema.response_to_json(&response))
    }

    /// Calls once with the request `fill` makes with the run-time service type (from YAML or
    /// JSON); gives that type and the response.
    fn call_filled<E: Into<RequestError>>(
        &mut self,
        timeout: Duration,
        fill: impl FnOnce(&ServiceType) -> Result<Value, E>,
    ) -> Result<(Arc<ServiceType>, Value), DynamicCallError> {
        let schema = self.schema()?;
        let request = fill(&schema).map_err(invalid_request(&schema))?;
        let response = self.call_value(&request, timeout)?;
        Ok((schema, response))
    }
}
