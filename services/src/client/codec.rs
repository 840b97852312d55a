//! How a client turns requests into CDR bodies and reply bodies into responses: typed (a
//! [`Service`]'s serde types) or raw (bytes the caller encodes itself, for types known only at
//! run time).

use std::marker::PhantomData;

use horus_ros_msgs::Service;

use crate::wire::{decode, encode};
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
}

/// A reply as it came: its CDR body (without any request header) and byte order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawReply {
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
    type Response = RawReply;

    fn service_type(&self) -> &str {
        &self.service_type
    }

    fn encode(&self, request: &Vec<u8>) -> Result<Vec<u8>, ServiceError> {
        Ok(request.clone())
    }

    fn decode(&self, body: &[u8], big_endian: bool) -> Result<RawReply, ServiceError> {
        Ok(RawReply {
            body: body.to_vec(),
            big_endian,
        })
    }
}
