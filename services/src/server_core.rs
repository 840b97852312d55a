//! [`ServerCore`]: what every service server is, whatever runs its handlers — its endpoints
//! (request reader, reply writer), the wire conventions and parked replies ([`ServerWire`]),
//! introspection, its counters and its stop flag — set up once, and the one path a request takes
//! in and its reply out. [`ServiceServer`](crate::ServiceServer) runs handlers on its thread,
//! [`AsyncServiceServer`](crate::AsyncServiceServer) as tokio tasks; both are a `ServerCore` and
//! a way to run handlers.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use horus_ros_msgs::description::EVENT_SUFFIX;
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_msgs::{dds_type_name, Service};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::service::{ReplyRoute, Request};
use horus_ros_rmw::{Gid, Node, RawReader, RawReaderWaker, RawWriter};

use crate::cdr::encode;
use crate::introspection::{encode_event, EventType, Introspection, IntrospectionState};
use crate::runtime::Runtime;
use crate::server_wire::{Serve, ServerWire};
use crate::{EndpointOptions, SetupError};

/// What a server is made from (the builder's settings).
pub(crate) struct ServerSettings<'a> {
    pub(crate) options: &'a EndpointOptions,
    pub(crate) introspection: Option<&'a (IntrospectionState, Qos)>,
}

/// What every server of a compiled service type is made of, whatever serves it
/// ([`ServerCore`], [`DdsServiceServer`](crate::DdsServiceServer)): its node, resolved name,
/// request reader and reply writer, and its reply path.
pub(crate) struct ServerEndpoints {
    /// The node and graph the endpoints live in.
    pub(crate) runtime: Runtime,
    /// The fully-qualified service name.
    pub(crate) name: ServiceName,
    /// The request reader.
    pub(crate) requests: RawReader,
    /// The reply writer.
    pub(crate) replies: RawWriter,
    /// The wire conventions and parked replies of the reply writer.
    pub(crate) wire: ServerWire,
}

impl ServerEndpoints {
    /// Creates the request reader and reply writer of service `S` as `options` set them, and
    /// their reply path: parked replies go out when their client's reader is matched, the graph
    /// waking the thread that waits on the request reader.
    pub(crate) fn create<S: Service>(options: &EndpointOptions) -> Result<Self, SetupError> {
        let (runtime, topics) =
            Runtime::endpoint::<S>(options, horus_ros_rmw::ServiceEndpointRole::Server)?;
        let requests = runtime.node.create_raw_reader(&topics.request)?;
        let replies = runtime.node.create_raw_writer(&topics.reply)?;
        let wire = ServerWire::new(
            &runtime,
            topics.name.clone(),
            replies.gid(),
            options.wire_flavour,
            requests.waker(),
        );
        Ok(Self {
            runtime,
            name: topics.name,
            requests,
            replies,
            wire,
        })
    }
}

/// A server's endpoints, reply path, introspection and counters (see the module docs).
pub(crate) struct ServerCore {
    name: ServiceName,
    request_reader: Gid,
    reply_writer: Gid,
    replies: RawWriter,
    wire: ServerWire,
    introspection: Arc<Introspection>,
    served: AtomicU64,
    failed: AtomicU64,
    stop: AtomicBool,
    /// Wakes the thread that takes requests (for [`stop`](Self::stop)).
    waker: RawReaderWaker,
    _node: Node,
}

impl ServerCore {
    /// Creates the request reader (returned, for the thread that takes requests) and the reply
    /// writer of service `S`, its introspection (configured as asked) and its reply path.
    pub(crate) fn create<S: Service>(
        settings: ServerSettings<'_>,
    ) -> Result<(Arc<Self>, RawReader), SetupError> {
        let ServerEndpoints {
            runtime,
            name,
            requests,
            replies,
            wire,
        } = ServerEndpoints::create::<S>(settings.options)?;
        let waker = requests.waker();
        let (request_reader, reply_writer) = (requests.gid(), replies.gid());
        let introspection = Introspection::new(
            runtime.node.clone(),
            name.clone(),
            Some(EventType {
                dds_type_name: dds_type_name(&format!("{}{EVENT_SUFFIX}", S::TYPE_NAME)),
                type_hash: S::event_type_hash(),
            }),
        );
        if let Some((state, qos)) = settings.introspection {
            introspection.configure(*state, qos)?;
        }
        let core = Self {
            name,
            request_reader,
            reply_writer,
            replies,
            wire,
            introspection,
            served: AtomicU64::new(0),
            failed: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            waker,
            _node: runtime.node,
        };
        Ok((Arc::new(core), requests))
    }

    /// The fully-qualified service name.
    pub(crate) fn name(&self) -> &ServiceName {
        &self.name
    }

    /// The GIDs of the request reader and the reply writer.
    pub(crate) fn gids(&self) -> (Gid, Gid) {
        (self.request_reader, self.reply_writer)
    }

    /// Requests answered with a response so far.
    pub(crate) fn served_count(&self) -> u64 {
        self.served.load(Ordering::Relaxed)
    }

    /// Requests whose handler failed (returned `Err` or panicked) so far.
    pub(crate) fn failed_count(&self) -> u64 {
        self.failed.load(Ordering::Relaxed)
    }

    /// The server's introspection.
    pub(crate) fn introspection(&self) -> &Introspection {
        &self.introspection
    }

    /// Asks the thread that takes requests to stop, and wakes it.
    pub(crate) fn stop(&self) {
        self.stop.store(true, Ordering::SeqCst);
        self.waker.wake();
    }

    /// Wakes the thread that takes requests (a handler finished: room for another).
    #[cfg(feature = "tokio")]
    pub(crate) fn wake(&self) {
        self.waker.wake();
    }

    /// Starts the thread that takes requests from `requests` (named `<thread><service name>`):
    /// it hands them to `server` until [`stop`](Self::stop) (see [`ServerWire::serve`]).
    pub(crate) fn start(
        self: &Arc<Self>,
        thread: &str,
        mut requests: RawReader,
        mut server: impl Serve + Send + 'static,
    ) -> std::io::Result<JoinHandle<()>> {
        let core = Arc::clone(self);
        std::thread::Builder::new()
            .name(format!("{thread}{}", self.name))
            .spawn(move || core.wire.serve(&mut requests, &core.stop, &mut server))
    }

    /// Sends the parked replies whose client can hear them now, drops the old ones; when the
    /// next one expires.
    pub(crate) fn flush_parked(&self) -> Option<Instant> {
        self.wire.flush_parked(&self.replies)
    }

    /// rcl `rcl_take_request_with_info`: REQUEST_RECEIVED once a request is taken.
    pub(crate) fn received<S: Service>(&self, request: &Request, decoded: &S::Request) {
        self.introspection.emit(
            ServiceEventInfo::REQUEST_RECEIVED,
            request.id.writer_guid,
            request.id.sequence_number,
            |info, contents| {
                encode_event::<S::Request, S::Response>(info, contents, Some(decoded), None)
            },
        );
    }

    /// Answers one request with its handler's `outcome`, in its client's convention: counted,
    /// sent at once if the client's reply reader is matched, else parked until it is (never
    /// waiting here); RESPONSE_SENT once sent (rcl `rcl_send_response`).
    pub(crate) fn finish<S: Service>(
        &self,
        route: &ReplyRoute,
        client_gid: [u8; 16],
        sequence: i64,
        outcome: Result<S::Response, String>,
    ) {
        let (result, response) = match outcome {
            Ok(response) => match encode(&response) {
                Ok(body) => (Ok(body), Some(response)),
                Err(e) => (Err(e.to_string()), None),
            },
            Err(message) => (Err(message), None),
        };
        let counter = if result.is_ok() {
            &self.served
        } else {
            &self.failed
        };
        counter.fetch_add(1, Ordering::Relaxed);
        let Some(mut reply) = self.wire.response(route, result) else {
            return;
        };
        if let Some(response) = response {
            if self.introspection.state() != IntrospectionState::Off {
                let introspection = Arc::clone(&self.introspection);
                reply = reply.on_sent(Box::new(move || {
                    introspection.emit(
                        ServiceEventInfo::RESPONSE_SENT,
                        client_gid,
                        sequence,
                        |info, contents| {
                            encode_event::<S::Request, S::Response>(
                                info,
                                contents,
                                None,
                                Some(&response),
                            )
                        },
                    );
                }));
            }
        }
        if let Err(e) = self.wire.send_response(&self.replies, reply) {
            tracing::warn!(service = %self.wire.service(), "could not send a reply: {e}");
        }
    }
}

/// The methods every server handle has, written once (each server holds a `core:
/// Arc<ServerCore>`).
macro_rules! server_handle_methods {
    () => {
        /// The fully-qualified service name.
        pub fn name(&self) -> &horus_ros_rmw::names::ServiceName {
            self.core.name()
        }

        /// The GIDs of the request reader and the reply writer (as `service info -v` lists
        /// them).
        pub fn gids(&self) -> (horus_ros_rmw::Gid, horus_ros_rmw::Gid) {
            self.core.gids()
        }

        /// Requests answered with a response so far.
        pub fn served_count(&self) -> u64 {
            self.core.served_count()
        }

        /// Requests whose handler failed (returned `Err` or panicked) so far.
        pub fn failed_count(&self) -> u64 {
            self.core.failed_count()
        }

        /// Turns service introspection on or off while serving (rclcpp / rclpy
        /// `configure_introspection`, rcl `rcl_service_configure_service_introspection`): OFF
        /// removes the `<service>/_service_event` publisher; METADATA publishes
        /// `REQUEST_RECEIVED` and `RESPONSE_SENT` events with their `ServiceEventInfo` only,
        /// CONTENTS with the request and the response. The publisher is created with `qos` when
        /// there is none; an existing one keeps its QoS. Events never hold up serving: they go
        /// through a bounded queue and are dropped when it is full.
        pub fn configure_introspection(
            &self,
            state: $crate::IntrospectionState,
            qos: &horus_ros_rmw::qos::Qos,
        ) -> Result<(), $crate::SetupError> {
            self.core.introspection().configure(state, qos)
        }

        /// The introspection state in force.
        pub fn introspection_state(&self) -> $crate::IntrospectionState {
            self.core.introspection().state()
        }

        /// The GID of the `<service>/_service_event` publisher, while introspection is on.
        pub fn introspection_gid(&self) -> Option<horus_ros_rmw::Gid> {
            self.core.introspection().publisher_gid()
        }
    };
}
pub(crate) use server_handle_methods;
