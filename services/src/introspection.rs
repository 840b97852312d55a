//! Service introspection, as rcl (jazzy 9.2) has it: servers and clients can publish
//! `service_msgs` events about their calls on `<service>/_service_event`.
//!
//! What follows rcl `src/rcl/service_event_publisher.c`, `service.c` and `client.c`:
//! - The topic is the service name followed by `RCL_SERVICE_INTROSPECTION_TOPIC_POSTFIX`
//!   (`/_service_event`); its type is the service's generated `<Srv>_Event` message
//!   `{ServiceEventInfo info; Request[<=1] request; Response[<=1] response}`.
//! - `rcl_send_service_event_message` stamps the event with the configured clock at the moment of
//!   publishing (`stamp.sec` = the seconds cast to `int32`, `stamp.nanosec` = the remainder),
//!   copies the 16-byte GID and the sequence number it is given, and leaves `request` and
//!   `response` empty in `METADATA` state; in `CONTENTS` state a `REQUEST_*` event carries the
//!   request and a `RESPONSE_*` event the response.
//! - A server publishes `REQUEST_RECEIVED` when it takes a request and `RESPONSE_SENT` after it
//!   sent the response, both with the request header's `writer_guid` and `sequence_number`. A
//!   client publishes `REQUEST_SENT` after sending (with the sequence number the RMW returned) and
//!   `RESPONSE_RECEIVED` when it takes a response, both with `rmw_get_gid_for_client`.
//! - `configure_introspection(OFF)` destroys the event publisher (the topic leaves the graph);
//!   `METADATA` / `CONTENTS` create it with the QoS given if there is none, and otherwise only
//!   change the state (the QoS of an existing publisher is kept).
//!
//! Unlike rcl, publishing never holds up the serving thread or a call: events are encoded in the
//! caller and handed to a bounded queue drained by the publisher's own thread; when the queue is
//! full the event is dropped (events are best effort from the service's point of view).

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::mpsc::{sync_channel, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{SystemTime, UNIX_EPOCH};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::names::{ServiceName, TopicName};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, Node, RawEndpointSpec};
use serde::Serialize;

use crate::SetupError;

/// rcl `RCL_SERVICE_INTROSPECTION_TOPIC_POSTFIX`.
pub const SERVICE_EVENT_TOPIC_POSTFIX: &str = "/_service_event";

/// Events waiting for the publisher thread before new ones are dropped.
const EVENT_QUEUE: usize = 256;

/// What a server or client publishes about its calls (rcl `rcl_service_introspection_state_t`,
/// rclpy `ServiceIntrospectionState`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IntrospectionState {
    /// Nothing; no event publisher exists.
    #[default]
    Off,
    /// Events with their [`ServiceEventInfo`] only (empty `request` / `response`).
    Metadata,
    /// Events with the request or response too.
    Contents,
}

impl IntrospectionState {
    fn to_u8(self) -> u8 {
        match self {
            Self::Off => 0,
            Self::Metadata => 1,
            Self::Contents => 2,
        }
    }

    fn from_u8(v: u8) -> Self {
        match v {
            1 => Self::Metadata,
            2 => Self::Contents,
            _ => Self::Off,
        }
    }
}

impl std::str::FromStr for IntrospectionState {
    type Err = String;

    /// `off` (or `disabled`, as the Jazzy demos say), `metadata`, `contents`; any case.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "off" | "disabled" => Ok(Self::Off),
            "metadata" => Ok(Self::Metadata),
            "contents" => Ok(Self::Contents),
            _ => Err(format!(
                "unknown introspection state '{s}' (off, metadata or contents)"
            )),
        }
    }
}

impl std::fmt::Display for IntrospectionState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Off => "OFF",
            Self::Metadata => "METADATA",
            Self::Contents => "CONTENTS",
        })
    }
}

/// The `<Srv>_Event` message of a compiled service, borrowing its request or response.
#[derive(Serialize)]
pub(crate) struct EventRef<'a, Q, R> {
    /// The metadata.
    pub(crate) info: ServiceEventInfo,
    /// `Request[<=1]`.
    pub(crate) request: &'a [Q],
    /// `Response[<=1]`.
    pub(crate) response: &'a [R],
}

/// The event topic's DDS type: name and hash of `<Srv>_Event`.
#[derive(Clone, Debug)]
pub(crate) struct EventType {
    pub(crate) dds_type_name: String,
    pub(crate) type_hash: TypeHash,
}

/// The info of an event happening now: rcl stamps it with the clock when it publishes (ROS time,
/// which is system time without a simulated clock).
pub(crate) fn event_info(
    event_type: u8,
    client_gid: [u8; 16],
    sequence_number: i64,
) -> ServiceEventInfo {
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    ServiceEventInfo {
        event_type,
        // rcl: `(int32_t)RCL_NS_TO_S(now)`, `now % 1e9`.
        stamp: Time {
            sec: now.as_secs() as i32,
            nanosec: now.subsec_nanos(),
        },
        client_gid,
        sequence_number,
    }
}

/// A live event publisher: the writer lives on its own thread, fed through a bounded queue.
struct EventPublisher {
    queue: Option<SyncSender<Vec<u8>>>,
    thread: Option<JoinHandle<()>>,
    gid: Gid,
}

impl Drop for EventPublisher {
    fn drop(&mut self) {
        // Closing the queue ends the thread once it has written what was queued; the writer
        // leaves the graph with it.
        self.queue.take();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The introspection of one server or client: its state and, unless OFF, its event publisher.
pub(crate) struct Introspection {
    node: Node,
    service: ServiceName,
    event_type: Option<EventType>,
    state: AtomicU8,
    publisher: Mutex<Option<EventPublisher>>,
    /// Serialises `configure` calls (creating a writer happens outside the publisher lock).
    configuring: Mutex<()>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Introspection {
    /// OFF introspection of `service` served or called from `node`; `event_type` is `None` for
    /// types whose events cannot be built (then only OFF can be configured).
    pub(crate) fn new(
        node: Node,
        service: ServiceName,
        event_type: Option<EventType>,
    ) -> Arc<Self> {
        Arc::new(Self {
            node,
            service,
            event_type,
            state: AtomicU8::new(IntrospectionState::Off.to_u8()),
            publisher: Mutex::new(None),
            configuring: Mutex::new(()),
        })
    }

    /// The state in force.
    pub(crate) fn state(&self) -> IntrospectionState {
        IntrospectionState::from_u8(self.state.load(Ordering::Acquire))
    }

    /// The GID of the event publisher, while there is one.
    pub(crate) fn publisher_gid(&self) -> Option<Gid> {
        lock(&self.publisher).as_ref().map(|p| p.gid)
    }

    /// rcl `rcl_service_configure_service_introspection` / `rcl_client_configure_…`: OFF destroys
    /// the event publisher; METADATA / CONTENTS create it with `qos` if absent, else only change
    /// the state.
    pub(crate) fn configure(&self, state: IntrospectionState, qos: &Qos) -> Result<(), SetupError> {
        let _one_at_a_time = lock(&self.configuring);
        if state == IntrospectionState::Off {
            self.state.store(state.to_u8(), Ordering::Release);
            let old = lock(&self.publisher).take();
            drop(old);
            return Ok(());
        }
        if lock(&self.publisher).is_none() {
            let publisher = self.create_publisher(qos)?;
            *lock(&self.publisher) = Some(publisher);
        }
        self.state.store(state.to_u8(), Ordering::Release);
        Ok(())
    }

    fn create_publisher(&self, qos: &Qos) -> Result<EventPublisher, SetupError> {
        let event_type = self
            .event_type
            .clone()
            .ok_or(SetupError::IntrospectionUnsupported)?;
        let topic = format!("{}{SERVICE_EVENT_TOPIC_POSTFIX}", self.service);
        let topic = TopicName::new(&topic).map_err(|source| SetupError::InvalidEventTopic {
            name: topic.clone(),
            cause: source,
        })?;
        let spec = RawEndpointSpec {
            dds_topic_name: topic.to_dds_topic_name(qos.avoid_ros_namespace_conventions),
            dds_type_name: event_type.dds_type_name,
            type_hash: event_type.type_hash,
            qos: *qos,
            service_id: None,
        };
        let writer = self.node.create_raw_writer(&spec)?;
        let gid = writer.gid();
        let (queue, events) = sync_channel::<Vec<u8>>(EVENT_QUEUE);
        let service = self.service.clone();
        let thread = std::thread::Builder::new()
            .name(format!("horus-evt{}", self.service))
            .spawn(move || {
                for body in events {
                    if let Err(e) = writer.write(body, None, None) {
                        tracing::debug!(service = %service, "could not publish a service event: {e}");
                    }
                }
            })?;
        Ok(EventPublisher {
            queue: Some(queue),
            thread: Some(thread),
            gid,
        })
    }

    /// Publishes one event unless OFF: `encode` builds its body from the info and whether the
    /// contents go in (CONTENTS). Never blocks on the network: a full queue drops the event.
    pub(crate) fn emit(
        &self,
        event_type: u8,
        client_gid: [u8; 16],
        sequence_number: i64,
        encode: impl FnOnce(ServiceEventInfo, bool) -> Option<Vec<u8>>,
    ) {
        let state = self.state();
        if state == IntrospectionState::Off {
            return;
        }
        let info = event_info(event_type, client_gid, sequence_number);
        let Some(body) = encode(info, state == IntrospectionState::Contents) else {
            return;
        };
        let guard = lock(&self.publisher);
        let Some(queue) = guard.as_ref().and_then(|p| p.queue.as_ref()) else {
            return;
        };
        match queue.try_send(body) {
            Ok(()) => {}
            Err(TrySendError::Full(_)) => {
                tracing::debug!(service = %self.service, "service event queue full; event dropped");
            }
            Err(TrySendError::Disconnected(_)) => {}
        }
    }
}

/// Encodes the event of a compiled service: `request` / `response` go in only when `contents`.
pub(crate) fn encode_event<Q: Serialize, R: Serialize>(
    info: ServiceEventInfo,
    contents: bool,
    request: Option<&Q>,
    response: Option<&R>,
) -> Option<Vec<u8>> {
    let request: &[Q] = match (contents, request) {
        (true, Some(r)) => std::slice::from_ref(r),
        _ => &[],
    };
    let response: &[R] = match (contents, response) {
        (true, Some(r)) => std::slice::from_ref(r),
        _ => &[],
    };
    match crate::cdr::encode(&EventRef {
        info,
        request,
        response,
    }) {
        Ok(body) => Some(body),
        Err(e) => {
            tracing::debug!("could not encode a service event: {e}");
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_msgs::example_interfaces::srv::{AddTwoIntsRequest, AddTwoIntsResponse};

    #[test]
    fn events_are_laid_out_as_the_generated_event_message() {
        let info = ServiceEventInfo {
            event_type: ServiceEventInfo::REQUEST_SENT,
            stamp: Time { sec: 7, nanosec: 9 },
            client_gid: [0xab; 16],
            sequence_number: 3,
        };
        let body = encode_event::<_, AddTwoIntsResponse>(
            info,
            true,
            Some(&AddTwoIntsRequest { a: 2, b: 3 }),
            None,
        )
        .expect("encoded");
        let mut want = vec![0u8, 0, 0, 0, 7, 0, 0, 0, 9, 0, 0, 0];
        want.extend_from_slice(&[0xab; 16]);
        want.extend_from_slice(&[0, 0, 0, 0]); // pad to 8 for the int64
        want.extend_from_slice(&3i64.to_le_bytes());
        want.extend_from_slice(&1u32.to_le_bytes()); // request: one element
        want.extend_from_slice(&[0, 0, 0, 0]); // pad to 8 for `a`
        want.extend_from_slice(&2i64.to_le_bytes());
        want.extend_from_slice(&3i64.to_le_bytes());
        want.extend_from_slice(&0u32.to_le_bytes()); // response: none
        assert_eq!(body, want);
        let meta = encode_event(
            info,
            false,
            Some(&AddTwoIntsRequest { a: 2, b: 3 }),
            Some(&AddTwoIntsResponse { sum: 5 }),
        )
        .expect("encoded");
        assert_eq!(meta.len(), 48);
        assert_eq!(&meta[40..], &[0u8, 0, 0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn states_parse_as_the_demos_name_them() {
        assert_eq!("disabled".parse(), Ok(IntrospectionState::Off));
        assert_eq!("Metadata".parse(), Ok(IntrospectionState::Metadata));
        assert_eq!("contents".parse(), Ok(IntrospectionState::Contents));
        assert!("all".parse::<IntrospectionState>().is_err());
    }
}
