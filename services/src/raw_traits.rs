//! Raw, non-blocking service traits for executor-driven code: [`ServiceClientTrait`] and
//! [`ServiceServerTrait`] (the seeds' signatures and documented semantics), with their DDS
//! implementations [`DdsServiceClient`] and [`DdsServiceServer`].
//!
//! Every raw payload is one message as CDR with its 4-byte encapsulation header; see
//! [`ServiceClientTrait`] ("Byte buffers").

mod client;
mod server;

use std::borrow::Cow;
use std::task::Waker;

use horus_ros_msgs::cdr::{CDR_BE_ID, CDR_LE_ID};
use horus_ros_msgs::{Message, Service};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::TransportError;

pub use client::{DdsServiceClient, DdsServiceClientBuilder};
pub use server::{DdsServiceServer, DdsServiceServerBuilder};

/// A service type as the raw traits see it: a request and a reply message. Implemented for every
/// [`Service`] (with `Reply` = its `Response`).
pub trait RosService {
    /// The request message.
    type Request: Message;
    /// The reply (response) message.
    type Reply: Message;
}

impl<T: Service> RosService for T {
    type Request = T::Request;
    type Reply = T::Response;
}

/// A request taken by [`ServiceServerTrait::try_recv_request`], borrowing the caller's buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServiceRequest<'a> {
    /// The token to pass to [`ServiceServerTrait::send_reply`] to answer this request.
    pub sequence_number: i64,
    /// The request message as CDR with its encapsulation header (see [`ServiceServerTrait`], "Byte buffers").
    pub data: &'a [u8],
}

/// Service client trait for sending requests.
///
/// # Threading
///
/// `&mut self` on every method — the client is single-owner. For fan-out request patterns,
/// create one client per worker thread.
///
/// # Calling pattern
///
/// 1. `send_request_raw(buf)` — non-blocking; returns once the request is queued for
///    transmission.
/// 2. The executor drives I/O (for [`DdsServiceClient`], a background thread does).
/// 3. `try_recv_reply_raw(buf)` — non-blocking; returns `Ok(Some(len))` when the reply is back.
///
/// The deprecated `call_raw` blocking path is kept for backwards compatibility but should not be
/// called.
///
/// # Byte buffers
///
/// Every raw payload of these traits (`send_request_raw`, `try_recv_reply_raw`,
/// `try_recv_request`, `send_reply`) is one serialized message (the request or the response) as
/// plain CDR **with** its 4-byte encapsulation header: `00 01 00 00` (CDR_LE, what ROS 2 writes)
/// or `00 00 00 00` (CDR_BE), then the body, aligned relative to the body — exactly what
/// [`horus_ros_msgs::cdr::to_cdr`] writes and [`horus_ros_msgs::cdr::from_cdr`] reads. Wire-level
/// correlation data (rmw_cyclonedds' 16-byte request header, rmw_fastrtps'
/// `related_sample_identity`) is never in these buffers: the DDS types add and strip it.
/// Payloads given as CDR_BE are re-encoded as CDR_LE before sending (which needs them to decode
/// as the service's message type).
///
/// # Example
///
/// ```no_run
/// use horus_ros_services::prelude::*;
/// use horus_ros_services::{
///     DdsServiceClient, DdsServiceServer, ServiceClientTrait, ServiceServerTrait,
/// };
///
/// let mut server = DdsServiceServer::<AddTwoInts>::builder().name("/add").build()?;
/// let mut client = DdsServiceClient::<AddTwoInts>::builder().name("/add").build()?;
/// let (mut req_buf, mut reply_buf) = ([0u8; 256], [0u8; 256]);
/// client.send_request::<AddTwoInts>(&AddTwoIntsRequest { a: 1, b: 2 }, &mut req_buf)?;
/// loop {
///     // An executor would drive these from its loop and wakers instead of spinning.
///     server.handle_request::<AddTwoInts>(&mut req_buf, &mut reply_buf, |r| {
///         AddTwoIntsResponse { sum: r.a + r.b }
///     })?;
///     if let Some(reply) = client.try_recv_reply::<AddTwoInts>(&mut reply_buf)? {
///         assert_eq!(reply.sum, 3);
///         break;
///     }
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub trait ServiceClientTrait {
    /// Error type for service operations.
    type Error;

    /// Sends a service request without waiting for a reply (non-blocking). `request` is CDR with
    /// its encapsulation header. Poll [`try_recv_reply_raw`](Self::try_recv_reply_raw) for the
    /// reply.
    fn send_request_raw(&mut self, request: &[u8]) -> Result<(), Self::Error>;

    /// Polls for a reply to the most recently sent request (non-blocking): `Ok(Some(len))` when
    /// it has arrived (CDR with encapsulation header in `reply_buf[..len]`), `Ok(None)` if not yet.
    fn try_recv_reply_raw(&mut self, reply_buf: &mut [u8]) -> Result<Option<usize>, Self::Error>;

    /// Sends a request and waits for the reply (blocking).
    ///
    /// Deprecated — do not call. The default body returns `Timeout` immediately without polling:
    /// drive [`send_request_raw`](Self::send_request_raw) /
    /// [`try_recv_reply_raw`](Self::try_recv_reply_raw) from an executor instead (or use
    /// [`ServiceClient::call`](crate::ServiceClient::call)).
    #[deprecated(
        note = "use send_request + try_recv_reply from an executor (or ServiceClient::call) instead"
    )]
    fn call_raw(&mut self, request: &[u8], _reply_buf: &mut [u8]) -> Result<usize, Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        let _ = request;
        Err(TransportError::Timeout.into())
    }

    /// Sends a typed request without waiting for a reply (non-blocking): serializes it into
    /// `req_buf` (`BufferTooSmall` if it does not fit) and calls
    /// [`send_request_raw`](Self::send_request_raw).
    fn send_request<S: RosService>(
        &mut self,
        request: &S::Request,
        req_buf: &mut [u8],
    ) -> Result<(), Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        let len = serialize_into(request, req_buf)?;
        self.send_request_raw(&req_buf[..len])
    }

    /// Polls for a typed reply to the most recently sent request (non-blocking): calls
    /// [`try_recv_reply_raw`](Self::try_recv_reply_raw) and deserializes if available.
    fn try_recv_reply<S: RosService>(
        &mut self,
        reply_buf: &mut [u8],
    ) -> Result<Option<S::Reply>, Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        match self.try_recv_reply_raw(reply_buf)? {
            Some(len) => Ok(Some(deserialize(&reply_buf[..len])?)),
            None => Ok(None),
        }
    }

    /// Registers a waker to wake when a reply arrives. Default: no-op (callers poll).
    fn register_waker(&self, _waker: &Waker) {}

    /// Begins a server-discovery query that ends after `_timeout_ms` (non-blocking); collect the
    /// result with [`poll_server_discovery`](Self::poll_server_discovery). Default: no-op success.
    fn start_server_discovery(&mut self, _timeout_ms: u32) -> Result<(), Self::Error> {
        Ok(())
    }

    /// Polls the discovery query: `Ok(Some(true))` a server is ready (safe to send the first
    /// request), `Ok(Some(false))` the query ended without one, `Ok(None)` still in flight.
    /// Default: `Ok(Some(true))` (the server is assumed reachable).
    fn poll_server_discovery(&mut self) -> Result<Option<bool>, Self::Error> {
        Ok(Some(true))
    }

    /// Whether a matching server is ready now (rclcpp `service_is_ready`), non-blocking.
    /// Default: `true`.
    fn is_server_ready(&self) -> bool {
        true
    }

    /// Graph-aware availability: `Ok(true)` if a matching server has been discovered, `Ok(false)`
    /// if none yet, `Err` if the backend cannot tell. Default: `Err(TransportError::Unsupported)`.
    fn server_available(&self) -> Result<bool, Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        Err(TransportError::Unsupported.into())
    }

    /// Calls a service with typed messages (blocking).
    ///
    /// Deprecated — do not call. The default body returns `Timeout` immediately without polling;
    /// see [`call_raw`](Self::call_raw).
    #[deprecated(
        note = "use send_request + try_recv_reply from an executor (or ServiceClient::call) instead"
    )]
    fn call<S: RosService>(
        &mut self,
        request: &S::Request,
        req_buf: &mut [u8],
        _reply_buf: &mut [u8],
    ) -> Result<S::Reply, Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        let _ = (request, req_buf);
        Err(TransportError::Timeout.into())
    }
}

/// Service server trait for handling requests.
///
/// # Threading
///
/// `&mut self` on `try_recv_request` and `send_reply` — the executor owns the server while a
/// request is handled. Long handlers may reply later via the recorded `sequence_number`.
///
/// # Calling pattern
///
/// 1. `try_recv_request(buf)`.
/// 2. If `Some(req)`: decode, run the handler, encode the reply.
/// 3. `send_reply(req.sequence_number, &reply_buf[..len])`.
///
/// `sequence_number` is the request → reply correlation token; backends derive it from the
/// wire-level metadata.
///
/// # Byte buffers
///
/// Every raw payload of these traits (`send_request_raw`, `try_recv_reply_raw`,
/// `try_recv_request`, `send_reply`) is one serialized message (the request or the response) as
/// plain CDR **with** its 4-byte encapsulation header: `00 01 00 00` (CDR_LE, what ROS 2 writes)
/// or `00 00 00 00` (CDR_BE), then the body, aligned relative to the body — exactly what
/// [`horus_ros_msgs::cdr::to_cdr`] writes and [`horus_ros_msgs::cdr::from_cdr`] reads. Wire-level
/// correlation data (rmw_cyclonedds' 16-byte request header, rmw_fastrtps'
/// `related_sample_identity`) is never in these buffers: the DDS types add and strip it.
/// Payloads given as CDR_BE are re-encoded as CDR_LE before sending (which needs them to decode
/// as the service's message type).
pub trait ServiceServerTrait {
    /// Error type for service operations.
    type Error;

    /// Tries to receive a request into `buf` (non-blocking). The returned request borrows `buf`;
    /// its `data` is CDR with encapsulation header.
    fn try_recv_request<'a>(
        &mut self,
        buf: &'a mut [u8],
    ) -> Result<Option<ServiceRequest<'a>>, Self::Error>;

    /// Sends `data` (the response as CDR with encapsulation header) as the reply to the request
    /// numbered `sequence_number`.
    fn send_reply(&mut self, sequence_number: i64, data: &[u8]) -> Result<(), Self::Error>;

    /// Whether a request is available, without consuming it. Default: `true` (backends should
    /// override with a real check).
    fn has_request(&self) -> bool {
        true
    }

    /// Registers a waker to wake when [`has_request`](Self::has_request) flips true.
    /// Default: no-op (callers poll).
    fn register_waker(&self, _waker: &Waker) {}

    /// Handles one request with typed messages: `Ok(true)` if one was received and answered,
    /// `Ok(false)` if none was waiting.
    fn handle_request<S: RosService>(
        &mut self,
        req_buf: &mut [u8],
        reply_buf: &mut [u8],
        handler: impl FnOnce(&S::Request) -> S::Reply,
    ) -> Result<bool, Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        let Some(request) = self.try_recv_request(req_buf)? else {
            return Ok(false);
        };
        let sequence_number = request.sequence_number;
        let request: S::Request = deserialize(request.data)?;
        let reply = handler(&request);
        let len = serialize_into(&reply, reply_buf)?;
        self.send_reply(sequence_number, &reply_buf[..len])?;
        Ok(true)
    }

    /// Like [`handle_request`](Self::handle_request), with a handler returning
    /// `Box<S::Reply>` (for replies too large for the stack).
    fn handle_request_boxed<S: RosService>(
        &mut self,
        req_buf: &mut [u8],
        reply_buf: &mut [u8],
        handler: impl FnOnce(&S::Request) -> Box<S::Reply>,
    ) -> Result<bool, Self::Error>
    where
        Self::Error: From<TransportError>,
    {
        let Some(request) = self.try_recv_request(req_buf)? else {
            return Ok(false);
        };
        let sequence_number = request.sequence_number;
        let request: S::Request = deserialize(request.data)?;
        let reply = handler(&request);
        let len = serialize_into(reply.as_ref(), reply_buf)?;
        self.send_reply(sequence_number, &reply_buf[..len])?;
        Ok(true)
    }
}

/// Length of the CDR encapsulation header.
const ENCAPSULATION_LEN: usize = 4;

/// Serializes `value` as CDR_LE with encapsulation header into `buf`; returns the length.
fn serialize_into<T: Serialize>(value: &T, buf: &mut [u8]) -> Result<usize, TransportError> {
    let bytes = horus_ros_msgs::cdr::to_cdr(value)
        .map_err(|e| TransportError::Serialization(e.to_string()))?;
    let capacity = buf.len();
    let dst = buf
        .get_mut(..bytes.len())
        .ok_or(TransportError::BufferTooSmall {
            needed: bytes.len(),
            capacity,
        })?;
    dst.copy_from_slice(&bytes);
    Ok(bytes.len())
}

/// Deserializes CDR with encapsulation header (either byte order).
fn deserialize<T: DeserializeOwned>(data: &[u8]) -> Result<T, TransportError> {
    horus_ros_msgs::cdr::from_cdr(data).map_err(|e| TransportError::Deserialization(e.to_string()))
}

/// Writes the encapsulation header for `big_endian` and `body` into `buf`; returns the length.
fn encapsulate_into(
    body: &[u8],
    big_endian: bool,
    buf: &mut [u8],
) -> Result<usize, TransportError> {
    let needed = ENCAPSULATION_LEN + body.len();
    let capacity = buf.len();
    let dst = buf
        .get_mut(..needed)
        .ok_or(TransportError::BufferTooSmall { needed, capacity })?;
    let id = if big_endian { CDR_BE_ID } else { CDR_LE_ID };
    dst[..2].copy_from_slice(&id);
    dst[2..ENCAPSULATION_LEN].fill(0);
    dst[ENCAPSULATION_LEN..].copy_from_slice(body);
    Ok(needed)
}

/// The CDR_LE body of an encapsulated payload of type `T` (a CDR_BE payload is re-encoded).
fn le_body<T: Message>(payload: &[u8]) -> Result<Cow<'_, [u8]>, TransportError> {
    let (header, body) = payload
        .split_first_chunk::<ENCAPSULATION_LEN>()
        .ok_or_else(|| {
            TransportError::Serialization(format!(
                "payload of {} bytes is shorter than the CDR encapsulation header",
                payload.len()
            ))
        })?;
    match [header[0], header[1]] {
        CDR_LE_ID => Ok(Cow::Borrowed(body)),
        CDR_BE_ID => {
            let value: T = horus_ros_msgs::cdr::from_cdr_body::<T, byteorder::BigEndian>(body)
                .map_err(|e| TransportError::Serialization(e.to_string()))?;
            horus_ros_msgs::cdr::to_cdr_body(&value)
                .map(Cow::Owned)
                .map_err(|e| TransportError::Serialization(e.to_string()))
        }
        other => Err(TransportError::Serialization(format!(
            "unsupported CDR encapsulation {other:02x?}"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest};

    #[test]
    fn payloads_round_trip_with_their_encapsulation_header() {
        let request = AddTwoIntsRequest { a: 7, b: -3 };
        let mut buf = [0u8; 64];
        let len = serialize_into(&request, &mut buf).expect("fits");
        assert_eq!(&buf[..4], &[0, 1, 0, 0]);
        assert_eq!(len, 20);
        assert_eq!(deserialize::<AddTwoIntsRequest>(&buf[..len]), Ok(request));
        assert_eq!(
            serialize_into(&request, &mut [0u8; 19]),
            Err(TransportError::BufferTooSmall {
                needed: 20,
                capacity: 19
            })
        );
        let body = le_body::<AddTwoIntsRequest>(&buf[..len]).expect("LE");
        assert!(matches!(body, Cow::Borrowed(_)));
        let mut out = [0u8; 64];
        let n = encapsulate_into(&body, false, &mut out).expect("fits");
        assert_eq!(&out[..n], &buf[..len]);
    }

    #[test]
    fn big_endian_payloads_are_re_encoded_little_endian() {
        let mut be = vec![0u8, 0, 0, 0];
        be.extend_from_slice(&7i64.to_be_bytes());
        be.extend_from_slice(&(-3i64).to_be_bytes());
        let body = le_body::<AddTwoIntsRequest>(&be).expect("BE");
        let mut le = Vec::new();
        le.extend_from_slice(&7i64.to_le_bytes());
        le.extend_from_slice(&(-3i64).to_le_bytes());
        assert_eq!(body.as_ref(), &le[..]);
        assert!(le_body::<AddTwoIntsRequest>(&[0, 1]).is_err());
        assert!(le_body::<AddTwoIntsRequest>(&[0, 2, 0, 0]).is_err());
    }

    /// A backend that overrides nothing: the seeds' defaults.
    struct Defaults;

    impl ServiceClientTrait for Defaults {
        type Error = TransportError;
        fn send_request_raw(&mut self, _request: &[u8]) -> Result<(), TransportError> {
            Ok(())
        }
        fn try_recv_reply_raw(&mut self, _buf: &mut [u8]) -> Result<Option<usize>, TransportError> {
            Ok(None)
        }
    }

    #[test]
    #[allow(deprecated)]
    fn client_defaults_are_the_seeds() {
        let mut c = Defaults;
        let mut buf = [0u8; 64];
        assert_eq!(
            c.call_raw(&[0, 1, 0, 0], &mut buf),
            Err(TransportError::Timeout)
        );
        let request = AddTwoIntsRequest { a: 1, b: 2 };
        let (mut a, mut b) = ([0u8; 64], [0u8; 64]);
        assert_eq!(
            c.call::<AddTwoInts>(&request, &mut a, &mut b),
            Err(TransportError::Timeout)
        );
        assert_eq!(c.server_available(), Err(TransportError::Unsupported));
        assert!(c.is_server_ready());
        assert_eq!(c.start_server_discovery(10), Ok(()));
        assert_eq!(c.poll_server_discovery(), Ok(Some(true)));
        assert_eq!(c.send_request::<AddTwoInts>(&request, &mut a), Ok(()));
        assert_eq!(c.try_recv_reply::<AddTwoInts>(&mut b), Ok(None));
    }
}
