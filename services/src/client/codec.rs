//! How a client turns requests into CDR bodies and reply bodies into responses: typed (a
//! [`Service`]'s serde types) or raw (bytes the caller encodes itself, for types known only at
//! run time).

use std::marker::PhantomData;

use horus_ros_msgs::description::EVENT_SUFFIX;
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_msgs::{dds_type_name, Service};

use crate::cdr::{decode, encode};
use crate::introspection::{encode_event, EventType};
use crate::ServiceError;

/// Encodes requests and decodes replies for one service type.
pub(crate) trait Codec: Send + Sync + 'static {
    /// What a call takes.
    type Request;
    /// What a call gives back.
    type Response: Send + 'static;
    /// The ROS service type (`pkg/srv/Name`): only servers of this type are called.
    fn service_type(&self) -> &str;
    /// The request as a CDR_LE body.
    fn encode(&self, request: &Self::Request) -> Result<Vec<u8>, ServiceError>;
    /// The response from a CDR body (the rmw_cyclonedds header already removed).
    fn decode(&self, body: &[u8], big_endian: bool) -> Result<Self::Response, ServiceError>;
    /// The `<Srv>_Event` type of introspection events, if this codec can build them.
    fn event_type(&self) -> Option<EventType>;
    /// An introspection event's body, with the request or response when `contents`.
    fn encode_event(
        &self,
        info: ServiceEventInfo,
        contents: bool,
        request: Option<&Self::Request>,
        response: Option<&Self::Response>,
    ) -> Option<Vec<u8>>;
}

/// The codec of a compiled service type.
pub(crate) struct Typed<S>(PhantomData<fn() -> S>);

impl<S> Default for Typed<S> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<S: Service> Codec for Typed<S> {
    type Request = S::Request;
    type Response = S::Response;

    fn service_type(&self) -> &str {
        S::TYPE_NAME
    }

    fn encode(&self, request: &S::Request) -> Result<Vec<u8>, ServiceError> {
        encode(request)
    }

    fn decode(&self, body: &[u8], big_endian: bool) -> Result<S::Response, ServiceError> {
        decode(body, big_endian)
    }

    fn event_type(&self) -> Option<EventType> {
        Some(EventType {
            dds_type_name: dds_type_name(&format!("{}{EVENT_SUFFIX}", S::TYPE_NAME)),
            type_hash: S::event_type_hash(),
        })
    }

    fn encode_event(
        &self,
        info: ServiceEventInfo,
        contents: bool,
        request: Option<&S::Request>,
        response: Option<&S::Response>,
    ) -> Option<Vec<u8>> {
        encode_event(info, contents, request, response)
    }
}

/// A response as it came (rmw `rmw_take_response`): its CDR body (without any request header)
/// and byte order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawResponse {
    /// The CDR body of the response message (after the encapsulation header).
    pub body: Vec<u8>,
    /// Whether the body is big-endian.
    pub big_endian: bool,
}

/// The codec of a service type known only by name: requests are CDR_LE bodies already.
pub(crate) struct Raw {
    pub(crate) service_type: String,
}

impl Codec for Raw {
    type Request = Vec<u8>;
    type Response = RawResponse;

    fn service_type(&self) -> &str {
        &self.service_type
    }

    fn encode(&self, request: &Vec<u8>) -> Result<Vec<u8>, ServiceError> {
        Ok(request.clone())
    }

    fn decode(&self, body: &[u8], big_endian: bool) -> Result<RawResponse, ServiceError> {
        Ok(RawResponse {
            body: body.to_vec(),
            big_endian,
        })
    }

    /// Bodies known only as bytes cannot be re-aligned inside an event message.
    fn event_type(&self) -> Option<EventType> {
        None
    }

    fn encode_event(
        &self,
        _info: ServiceEventInfo,
        _contents: bool,
        _request: Option<&Vec<u8>>,
        _response: Option<&RawResponse>,
    ) -> Option<Vec<u8>> {
        None
    }
}
