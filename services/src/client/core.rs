//! What sync and async clients share: the endpoints, the server lookup, sending in the server's
//! wire convention, and routing replies to the calls waiting for them.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::task::Waker;
use std::time::{Duration, Instant};

use horus_ros_graph::{GraphView, GraphWatcher};
use horus_ros_msgs::Service;
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::service::{Client, Peers, TakenResponse, WireFlavour};
use horus_ros_rmw::{Gid, RawReaderWaker};

use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;

use super::codec::{Codec, Typed};
use super::responses::{Membership, ResponseWaitSet, TakeResponses};
use crate::cdr::decode;
use crate::introspection::{Introspection, IntrospectionState};
use crate::naming::ServiceTopics;
use crate::runtime::Runtime;
use crate::{EndpointOptions, ServiceError, SetupError, TransportError};

/// Identifies one outstanding request.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct RequestKey {
    flavour: WireFlavour,
    sequence: i64,
}

/// Whether a call can be sent now, and if not, when to look again.
pub(crate) enum Readiness {
    /// A server is usable now.
    Ready(ReadyServer),
    /// No server is usable yet; a graph change may make one usable, and so may the passing of
    /// this instant (an rmw_cyclonedds server's reply writer settling, see
    /// [`ClientCore::ready_server`]).
    NotYet(Option<Instant>),
}

/// A server usable now: both endpoints known and matched with ours.
#[derive(Clone, Debug)]
pub(crate) struct ReadyServer {
    flavour: WireFlavour,
    /// The request readers of every server a request sent now reaches (matched with our
    /// request writer).
    reached: Vec<Gid>,
}

/// Where an outstanding request stands.
pub(crate) struct Slot<R> {
    result: Option<Result<R, ServiceError>>,
    waker: Option<Waker>,
    deadline: Instant,
    /// The request readers of the servers the request went to (matched with our request writer
    /// when it was sent) that are still matched: when none is left, the call ends with
    /// [`TransportError::ServerGone`].
    servers: Vec<Gid>,
}

/// The calls in flight, shared with the graph's thread: a graph change that leaves a call with
/// none of the servers it went to ends it with [`TransportError::ServerGone`] and wakes its caller
/// (the slot's waker, the condition variable, and the reply reader's wait).
pub(crate) struct Calls<R> {
    pending: Mutex<HashMap<RequestKey, Slot<R>>>,
    completed: Condvar,
    request_writer: Gid,
    reply_waker: RawReaderWaker,
    /// Set while the thread waiting on the reply reader also waits for a server (a request not
    /// sent yet): graph changes then wake it.
    wake_on_graph_change: AtomicBool,
}

impl<R: Send + 'static> GraphWatcher for Calls<R> {
    fn graph_changed(&self, graph: &GraphView<'_>) {
        let mut pending = lock(&self.pending);
        let mut ended = false;
        for slot in pending.values_mut() {
            if slot.result.is_some() || slot.servers.is_empty() {
                continue;
            }
            slot.servers
                .retain(|reader| graph.is_matched(self.request_writer, *reader));
            if slot.servers.is_empty() {
                slot.result = Some(Err(ServiceError::Transport(TransportError::ServerGone)));
                if let Some(waker) = slot.waker.take() {
                    waker.wake();
                }
                ended = true;
            }
        }
        drop(pending);
        if ended {
            self.completed.notify_all();
        }
        if ended || self.wake_on_graph_change.load(Ordering::SeqCst) {
            self.reply_waker.wake();
        }
    }
}

/// What a client of any kind is made from: the endpoint options its builder sets, and the
/// introspection to start with (set by the builders that offer it).
#[derive(Clone, Debug, Default)]
pub(crate) struct ClientOptions {
    pub(crate) endpoint: EndpointOptions,
    pub(crate) introspection: Option<(IntrospectionState, Qos)>,
}

pub(crate) struct ClientCore<C: Codec> {
    codec: C,
    runtime: Runtime,
    name: ServiceName,
    /// rmw's side: the request writer and response reader.
    endpoints: Client,
    /// What rmw_get_gid_for_client gives for this client (see [`ClientCore::with_codec`]).
    client_gid: [u8; 16],
    introspection: std::sync::Arc<Introspection>,
    flavour: Option<WireFlavour>,
    /// The calls in flight (also held, weakly, by the graph: see [`Calls`]).
    calls: Arc<Calls<C::Response>>,
    /// Futures waiting for a usable server, with their deadlines.
    unsent_wakers: Mutex<Vec<(Waker, Instant)>>,
    /// The graph generation the reply thread last looked at for [`unsent_wakers`](Self::wake_due).
    seen_generation: AtomicU64,
    /// When the reply thread looks again without an event (`None`: never); locked after
    /// `calls.pending`, so a call whose deadline comes sooner wakes it (see `set_waker`).
    planned_wake: Mutex<Option<Instant>>,
    /// The last [`Readiness::Ready`] and the graph generation it was found at: it holds until
    /// the graph changes (servers, matches and vendors are graph changes; time only makes a
    /// server ready), so calls in a quiet graph do not query it again.
    ready: Mutex<Option<(u64, ReadyServer)>>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl<S: Service> ClientCore<Typed<S>> {
    /// A client of the compiled service type `S`.
    pub(crate) fn new(options: ClientOptions) -> Result<Self, SetupError> {
        Self::for_service::<S>(Typed::default(), &options)
    }
}

impl<C: Codec> ClientCore<C> {
    /// A client of the compiled service type `S` (its topics, and its default name unless
    /// `options` name one) using `codec`.
    pub(crate) fn for_service<S: Service>(
        codec: C,
        options: &ClientOptions,
    ) -> Result<Self, SetupError> {
        let (runtime, topics) = Runtime::endpoint::<S>(
            &options.endpoint,
            horus_ros_rmw::ServiceEndpointRole::Client,
        )?;
        Self::with_codec(runtime, topics, codec, options)
    }

    /// A client on `topics` using `codec`.
    pub(crate) fn with_codec(
        runtime: Runtime,
        topics: ServiceTopics,
        codec: C,
        options: &ClientOptions,
    ) -> Result<Self, SetupError> {
        let endpoints = Client::new(&runtime.node, &topics.request, &topics.reply)?;
        // rmw_get_gid_for_client, which rcl puts in a client's introspection events: the request
        // writer's GUID on rmw_fastrtps (jazzy `rmw_get_gid_for_client.cpp`: `info->writer_guid_`),
        // the client id announced as `clientid=` on rmw_cyclonedds (jazzy `rmw_node.cpp`:
        // `cli->client.id`). A backend that carries related_sample_identity speaks the former's
        // convention, one that does not the latter's. rmw_zenoh (`rmw_get_gid_for_client`): the
        // client's GID, the hash of its SC token, which our request writer has.
        let capabilities = runtime.node.context().capabilities();
        let client_gid = match topics.request.service_id {
            Some(id) if !capabilities.carries_sample_identity && !capabilities.service_queries => {
                id.id
            }
            _ => *endpoints.request_writer().as_bytes(),
        };
        let introspection = Introspection::new(
            runtime.node.clone(),
            topics.name.clone(),
            codec.event_type(),
        );
        if let Some((state, qos)) = &options.introspection {
            introspection.configure(*state, qos)?;
        }
        let calls = Arc::new(Calls {
            pending: Mutex::new(HashMap::new()),
            completed: Condvar::new(),
            request_writer: endpoints.request_writer(),
            reply_waker: endpoints.response_reader_mut().waker(),
            wake_on_graph_change: AtomicBool::new(false),
        });
        let watcher: std::sync::Weak<dyn GraphWatcher> = Arc::downgrade(&calls) as _;
        runtime.graph.watch(watcher);
        Ok(Self {
            client_gid,
            introspection,
            codec,
            endpoints,
            runtime,
            name: topics.name,
            flavour: options.endpoint.wire_flavour,
            calls,
            unsent_wakers: Mutex::new(Vec::new()),
            seen_generation: AtomicU64::new(u64::MAX),
            planned_wake: Mutex::new(None),
            ready: Mutex::new(None),
        })
    }

    /// Calls once, blocking: waits (within `timeout`) for a server, sends, and waits for the
    /// reply in the context's response wait set (see [`join_responses`](Self::join_responses)).
    pub(crate) fn call_blocking(
        &self,
        responses: &Membership,
        request: &C::Request,
        timeout: Duration,
    ) -> Result<C::Response, ServiceError> {
        let deadline = Instant::now() + timeout;
        let server = self.wait_ready(deadline)?;
        let call_waker = responses.set().call_waker();
        let waker = Waker::from(Arc::clone(&call_waker));
        let key = self.send(request, server, deadline, Some(waker))?;
        loop {
            // A reply, or the end of every server the request went to (the graph's watcher
            // wakes the call's waker then).
            if let Some(result) = self.take_result(key) {
                return result;
            }
            if Instant::now() >= deadline {
                self.forget(key);
                return Err(ServiceError::Timeout);
            }
            responses
                .set()
                .wait(&call_waker, deadline, || self.is_done(key));
        }
    }

    /// Makes this client's calls wait in its context's response wait set, which takes its
    /// replies (for [`call_blocking`](Self::call_blocking)). The reader stays attached to the
    /// set for its life, so a client that joins takes no replies by itself any more.
    pub(crate) fn join_responses(self) -> Result<(Arc<Self>, Membership), SetupError>
    where
        C: 'static,
    {
        let set = ResponseWaitSet::of(self.runtime.node.context())?;
        let membership = set.attach(&mut self.endpoints.response_reader_mut())?;
        let core = Arc::new(self);
        let member: std::sync::Weak<dyn TakeResponses> = Arc::downgrade(&core) as _;
        membership.register(member);
        Ok((core, membership))
    }

    pub(crate) fn name(&self) -> &ServiceName {
        &self.name
    }

    /// rclcpp / rclpy `Client::configure_introspection` (see
    /// [`ServiceClient::configure_introspection`](crate::ServiceClient::configure_introspection)).
    pub(crate) fn configure_introspection(
        &self,
        state: IntrospectionState,
        qos: &Qos,
    ) -> Result<(), SetupError> {
        self.introspection.configure(state, qos)
    }

    /// The introspection state in force.
    pub(crate) fn introspection_state(&self) -> IntrospectionState {
        self.introspection.state()
    }

    /// The GID this client's introspection events carry as `client_gid`.
    pub(crate) fn introspection_client_gid(&self) -> Gid {
        Gid::from_bytes(self.client_gid)
    }

    /// The GID of the `<service>/_service_event` publisher, while introspection is on.
    pub(crate) fn introspection_gid(&self) -> Option<Gid> {
        self.introspection.publisher_gid()
    }

    /// The GIDs of the request writer and reply reader.
    pub(crate) fn gids(&self) -> (Gid, Gid) {
        (
            self.endpoints.request_writer(),
            self.endpoints.response_reader(),
        )
    }

    /// The servers of this service and type that the graph knows with both endpoints.
    fn servers(&self) -> Vec<(Gid, Gid)> {
        self.runtime
            .graph
            .read(|c| c.servers_info_by_service(self.name.as_str(), false))
            .unwrap_or_default()
            .into_iter()
            .filter(|s| s.service_type == self.codec.service_type() && s.endpoint_gids.len() == 2)
            .map(|s| (s.endpoint_gids[0], s.endpoint_gids[1]))
            .collect()
    }

    /// Whether any endpoint of this service with this type is on the graph (even half-visible).
    fn any_server_endpoint(&self) -> bool {
        self.runtime.graph.read(|c| {
            c.service_names_and_types(true)
                .get(self.name.as_str())
                .is_some_and(|types| types.contains(self.codec.service_type()))
                && c.count_services(self.name.as_str()) > 0
        })
    }

    /// Whether a server is on the graph with both endpoints (discovered).
    pub(crate) fn server_available(&self) -> bool {
        !self.servers().is_empty()
    }

    /// Whether a server can take a call now ([`ready_server`](Self::ready_server)).
    pub(crate) fn is_server_ready(&self) -> bool {
        self.ready_server().is_some()
    }

    /// A server usable now, if any: known to the graph with both endpoints, and its request
    /// reader and reply writer matched with our writer and reader (so neither the request nor
    /// the first reply can be lost).
    pub(crate) fn ready_server(&self) -> Option<ReadyServer> {
        match self.readiness() {
            Readiness::Ready(server) => Some(server),
            Readiness::NotYet(_) => None,
        }
    }

    /// [`ready_server`](Self::ready_server), or when to look again if none is usable.
    pub(crate) fn readiness(&self) -> Readiness {
        // Read before the graph is: a change made while it is looked at makes the next call
        // look again.
        let generation = self.runtime.graph.generation();
        if let Some((seen, ready)) = &*lock(&self.ready) {
            if *seen == generation {
                return Readiness::Ready(ready.clone());
            }
        }
        let readiness = self.find_readiness();
        if let Readiness::Ready(ready) = &readiness {
            *lock(&self.ready) = Some((generation, ready.clone()));
        }
        readiness
    }

    /// [`readiness`](Self::readiness) as the graph has it now.
    fn find_readiness(&self) -> Readiness {
        let graph = &self.runtime.graph;
        let servers = self.servers();
        let capabilities = self.runtime.node.context().capabilities();
        let mut settles_at: Option<Instant> = None;
        let flavour = servers.iter().find_map(|&(reader, writer)| {
            graph.matched_since(self.endpoints.request_writer(), reader)?;
            let reply_match = graph.matched_since(self.endpoints.response_reader(), writer)?;
            let flavour =
                WireFlavour::choose(capabilities, graph.vendor_of(reader), self.flavour).ok()?;
            // The convention may want the server's reply writer given time to match our reader
            // (`WireFlavour::reply_match_settle`): the waiters look again at that instant.
            if let Some(settle) = flavour.reply_match_settle(capabilities) {
                let settled = reply_match + settle;
                if Instant::now() < settled {
                    settles_at = Some(settles_at.map_or(settled, |s| s.min(settled)));
                    return None;
                }
            }
            Some(flavour)
        });
        let Some(flavour) = flavour else {
            return Readiness::NotYet(settles_at);
        };
        let reached = servers
            .into_iter()
            .map(|(reader, _)| reader)
            .filter(|reader| graph.is_matched(self.endpoints.request_writer(), *reader))
            .collect();
        Readiness::Ready(ReadyServer { flavour, reached })
    }

    /// The graph this client finds its servers in.
    #[cfg(feature = "tokio")]
    pub(crate) fn graph(&self) -> &Arc<horus_ros_graph::Graph> {
        &self.runtime.graph
    }

    /// When a server whose endpoints are matched with ours but that [`ready_server`]
    /// (Self::ready_server) does not give yet becomes ready with no further graph change: an
    /// server's reply writer is given its convention's
    /// [`reply_match_settle`](WireFlavour::reply_match_settle) to match our reader. `None` if no
    /// server waits for that.
    #[cfg(feature = "tokio")]
    pub(crate) fn settles_at(&self) -> Option<Instant> {
        let graph = &self.runtime.graph;
        let capabilities = self.runtime.node.context().capabilities();
        self.servers()
            .into_iter()
            .filter_map(|(reader, writer)| {
                graph.matched_since(self.endpoints.request_writer(), reader)?;
                let reply_match = graph.matched_since(self.endpoints.response_reader(), writer)?;
                let flavour =
                    WireFlavour::choose(capabilities, graph.vendor_of(reader), self.flavour)
                        .ok()?;
                Some(reply_match + flavour.reply_match_settle(capabilities)?)
            })
            .min()
    }

    /// Waits until a server is ready, at most until `deadline`: `NoServer` if none ever showed
    /// up, `Timeout` if one was there but never became usable.
    pub(crate) fn wait_ready(&self, deadline: Instant) -> Result<ReadyServer, ServiceError> {
        loop {
            let seen = self.runtime.graph.generation();
            let settles_at = match self.readiness() {
                Readiness::Ready(ready) => return Ok(ready),
                Readiness::NotYet(settles_at) => settles_at,
            };
            if let Some(why) = self.unusable_servers() {
                return Err(ServiceError::Transport(why));
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(self.not_ready_error());
            }
            // Servers appearing and matches being made are graph changes.
            let until = settles_at.map_or(deadline, |s| s.min(deadline));
            self.runtime
                .graph
                .wait_for_graph_change_since(seen, until.saturating_duration_since(now));
        }
    }

    /// Waits once for what can make a server ready (a graph change, or a settling instant),
    /// at most until `deadline`.
    pub(crate) fn wait_for_readiness_change(&self, deadline: Instant) {
        let seen = self.runtime.graph.generation();
        let settles_at = match self.readiness() {
            Readiness::Ready(_) => return,
            Readiness::NotYet(settles_at) => settles_at,
        };
        let until = settles_at.map_or(deadline, |s| s.min(deadline));
        self.runtime
            .graph
            .wait_for_graph_change_since(seen, until.saturating_duration_since(Instant::now()));
    }

    /// Why no server can be called from this backend, when every server on the graph follows a
    /// convention the backend cannot speak (`None` if there is none, or one that can be called).
    pub(crate) fn unusable_servers(&self) -> Option<TransportError> {
        let graph = &self.runtime.graph;
        let capabilities = self.runtime.node.context().capabilities();
        let mut why = None;
        for (reader, _) in self.servers() {
            match WireFlavour::choose(capabilities, graph.vendor_of(reader), self.flavour) {
                Ok(_) => return None,
                Err(reason) => why = Some(reason),
            }
        }
        why.map(|cause| TransportError::NoUsableServer {
            service: self.name.to_string(),
            cause,
        })
    }

    /// The error for a call that found no usable server.
    pub(crate) fn not_ready_error(&self) -> ServiceError {
        if let Some(why) = self.unusable_servers() {
            return ServiceError::Transport(why);
        }
        if self.any_server_endpoint() {
            ServiceError::Timeout
        } else {
            ServiceError::NoServer
        }
    }

    /// Sends `request` in the server's convention and registers the slot its reply goes to.
    pub(crate) fn send(
        &self,
        request: &C::Request,
        server: ReadyServer,
        deadline: Instant,
        waker: Option<Waker>,
    ) -> Result<RequestKey, ServiceError> {
        let body = self.codec.encode(request)?;
        // The pending lock is held while writing, so a reply cannot be routed before its slot exists.
        let mut pending = lock(&self.calls.pending);
        let sequence = self
            .endpoints
            .send_request(&body, server.flavour)
            .map_err(|e| ServiceError::Transport(TransportError::Send(e.to_string())))?;
        let key = RequestKey {
            flavour: server.flavour,
            sequence,
        };
        pending.insert(
            key,
            Slot {
                result: None,
                waker,
                deadline,
                servers: server.reached,
            },
        );
        // rcl `rcl_send_request`: REQUEST_SENT with the sequence number the RMW gave (under the
        // pending lock, so it is queued before the response's event).
        self.introspection.emit(
            ServiceEventInfo::REQUEST_SENT,
            self.client_gid,
            key.sequence,
            |info, contents| self.codec.encode_event(info, contents, Some(request), None),
        );
        Ok(key)
    }

    /// Takes every reply that has arrived and hands each to its call; replies to nobody (late,
    /// after a timeout, or to other clients) are dropped.
    pub(crate) fn drain_replies(&self) {
        let mut routed = false;
        loop {
            match self.endpoints.take_response() {
                Ok(Some(response)) => routed |= self.route(response),
                Ok(None) => break,
                Err(e) => tracing::debug!(service = %self.name, "dropped a reply: {e}"),
            }
        }
        if routed {
            self.calls.completed.notify_all();
        }
    }

    /// Waits for reply data, a graph change that ends a call, or [`wake`](Self::wake), at most
    /// `timeout` (`None`: no limit); then call [`drain_replies`](Self::drain_replies).
    pub(crate) fn wait_for_replies(&self, timeout: Option<Duration>) {
        self.endpoints.response_reader_mut().wait(timeout);
    }

    /// Makes the current or next [`wait_for_replies`](Self::wait_for_replies) return.
    pub(crate) fn wake(&self) {
        self.calls.reply_waker.wake();
    }

    /// Whether graph changes wake [`wait_for_replies`](Self::wait_for_replies) (while the
    /// waiting thread also waits for a server).
    pub(crate) fn set_wake_on_graph_change(&self, on: bool) {
        self.calls.wake_on_graph_change.store(on, Ordering::SeqCst);
    }

    /// The call `response` belongs to, and its outcome: a horus-ros server's error reply carries
    /// the handler's message as a CDR string.
    fn route(&self, response: TakenResponse) -> bool {
        let key = RequestKey {
            flavour: response.flavour,
            sequence: response.sequence_number,
        };
        let outcome = if response.failed {
            let message = decode::<String>(response.message(), response.big_endian)
                .unwrap_or_else(|_| "the service handler failed".to_owned());
            Err(ServiceError::ServiceFailed(message))
        } else {
            self.codec.decode(response.message(), response.big_endian)
        };
        let mut pending = lock(&self.calls.pending);
        // rcl `rcl_take_response_with_info`: RESPONSE_RECEIVED for every response taken (a
        // horus-ros server's error reply is no response).
        if let Ok(response) = &outcome {
            self.introspection.emit(
                ServiceEventInfo::RESPONSE_RECEIVED,
                self.client_gid,
                key.sequence,
                |info, contents| {
                    self.codec
                        .encode_event(info, contents, None, Some(response))
                },
            );
        }
        let Some(slot) = pending.get_mut(&key) else {
            return false;
        };
        if slot.result.is_none() {
            slot.result = Some(outcome);
            if let Some(waker) = slot.waker.take() {
                waker.wake();
            }
        }
        true
    }

    /// Whether `key` has its result (or is forgotten).
    fn is_done(&self, key: RequestKey) -> bool {
        lock(&self.calls.pending)
            .get(&key)
            .is_none_or(|slot| slot.result.is_some())
    }

    /// The result of `key` if it is in, removing its slot.
    pub(crate) fn take_result(&self, key: RequestKey) -> Option<Result<C::Response, ServiceError>> {
        let mut pending = lock(&self.calls.pending);
        let done = pending.get(&key).is_some_and(|s| s.result.is_some());
        if done {
            pending.remove(&key).and_then(|s| s.result)
        } else {
            None
        }
    }

    /// Stores the waker to wake when `key`'s reply arrives or its deadline passes (wakes the
    /// reply thread if that deadline comes before it planned to look again).
    pub(crate) fn set_waker(&self, key: RequestKey, waker: &Waker) {
        let mut pending = lock(&self.calls.pending);
        let Some(slot) = pending.get_mut(&key) else {
            return;
        };
        let first = slot.waker.is_none();
        if !slot.waker.as_ref().is_some_and(|w| w.will_wake(waker)) {
            slot.waker = Some(waker.clone());
        }
        let deadline = slot.deadline;
        if first {
            let mut planned = lock(&self.planned_wake);
            if planned.is_none_or(|p| deadline < p) {
                *planned = Some(deadline);
                drop(planned);
                drop(pending);
                self.wake();
            }
        }
    }

    /// Forgets `key` (its call timed out or was abandoned): a late reply is then dropped.
    pub(crate) fn forget(&self, key: RequestKey) {
        lock(&self.calls.pending).remove(&key);
    }

    /// Waits until `key` has its result (or is forgotten), at most until `deadline` — checked
    /// under the lock the result is stored under, so no completion is missed. Someone else
    /// (the reply thread of an async client) takes the replies off the reader.
    pub(crate) fn wait_completion(&self, key: RequestKey, deadline: Instant) {
        let mut pending = lock(&self.calls.pending);
        loop {
            if pending.get(&key).is_none_or(|slot| slot.result.is_some()) {
                return;
            }
            let now = Instant::now();
            if now >= deadline {
                return;
            }
            pending = self
                .calls
                .completed
                .wait_timeout(pending, deadline - now)
                .map(|(guard, _)| guard)
                .unwrap_or_else(|p| p.into_inner().0);
        }
    }

    /// Parks the waker of a future still waiting for a usable server (woken when the graph
    /// changes or its deadline passes), and wakes the reply thread to take it into account.
    pub(crate) fn park_unsent(&self, waker: &Waker, deadline: Instant) {
        {
            // A future polled again before the reply thread looked is parked once.
            let mut unsent = lock(&self.unsent_wakers);
            match unsent.iter_mut().find(|(w, _)| w.will_wake(waker)) {
                Some((_, at)) => *at = (*at).min(deadline),
                None => unsent.push((waker.clone(), deadline)),
            }
        }
        self.set_wake_on_graph_change(true);
        self.wake();
    }

    /// The async clients' reply thread, after each wake-up: wakes the futures waiting for a
    /// server when one may be usable now (the graph changed, or one is ready) or when their
    /// deadline passed, and the sent calls past their deadline. Returns when it must look again
    /// without any event: the earliest deadline of a waiting future or the settling instant of
    /// a server (`None`: only events matter).
    pub(crate) fn wake_due(&self) -> Option<Instant> {
        let now = Instant::now();
        let mut next: Option<Instant> = None;
        let mut earliest = |t: Instant| next = Some(next.map_or(t, |n| n.min(t)));
        let mut to_wake = Vec::new();
        {
            let mut unsent = lock(&self.unsent_wakers);
            if !unsent.is_empty() {
                let generation = self.runtime.graph.generation();
                let changed = self.seen_generation.swap(generation, Ordering::SeqCst) != generation;
                match self.readiness() {
                    Readiness::Ready(_) => to_wake.append(&mut unsent),
                    _ if changed => to_wake.append(&mut unsent),
                    Readiness::NotYet(settles_at) => {
                        unsent.retain(|(waker, deadline)| {
                            if *deadline <= now {
                                to_wake.push((waker.clone(), *deadline));
                                false
                            } else {
                                true
                            }
                        });
                        for (_, deadline) in unsent.iter() {
                            earliest(*deadline);
                        }
                        if let Some(settles_at) = settles_at.filter(|_| !unsent.is_empty()) {
                            earliest(settles_at);
                        }
                    }
                }
            }
            // Re-parked futures set it again (and wake this thread).
            self.set_wake_on_graph_change(!unsent.is_empty());
        }
        for (waker, _) in to_wake {
            waker.wake();
        }
        let mut pending = lock(&self.calls.pending);
        for slot in pending.values_mut() {
            if slot.result.is_some() {
                continue;
            }
            if slot.deadline <= now {
                if let Some(w) = slot.waker.take() {
                    w.wake();
                }
            } else if slot.waker.is_some() {
                earliest(slot.deadline);
            }
        }
        *lock(&self.planned_wake) = next;
        drop(pending);
        next
    }

    /// Requests waiting for their reply now.
    pub(crate) fn pending_count(&self) -> usize {
        lock(&self.calls.pending).len()
    }
}

impl<C: Codec> TakeResponses for ClientCore<C> {
    fn take_responses(&self) {
        self.drain_replies();
    }
}

/// The methods every client handle has, written once (each client holds a `core:
/// Arc<ClientCore<_>>`): `discovery` the name, GIDs and server lookup (doc lines given after it
/// are added to `wait_for_service`'s), `introspection` the introspection settings.
macro_rules! client_handle_methods {
    (discovery $(, $wait_doc:literal)*) => {
        /// The fully-qualified service name.
        pub fn name(&self) -> &horus_ros_rmw::names::ServiceName {
            self.core.name()
        }

        /// The GIDs of the request writer and the reply reader.
        pub fn gids(&self) -> (horus_ros_rmw::Gid, horus_ros_rmw::Gid) {
            self.core.gids()
        }

        /// Whether a server of this service and type is known to the graph with both its
        /// endpoints (discovered; see [the readiness words](crate#readiness)).
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
        $(#[doc = $wait_doc])*
        pub fn wait_for_service(&self, timeout: std::time::Duration) -> bool {
            self.core
                .wait_ready(std::time::Instant::now() + timeout)
                .is_ok()
        }
    };
    (introspection) => {
        /// Turns service introspection on or off (rclcpp / rclpy
        /// `Client::configure_introspection`, rcl `rcl_client_configure_service_introspection`):
        /// OFF removes the `<service>/_service_event` publisher; METADATA publishes
        /// `REQUEST_SENT` and `RESPONSE_RECEIVED` events with their `ServiceEventInfo` only,
        /// CONTENTS with the request and the response. The publisher is created with `qos` when
        /// there is none; an existing one keeps its QoS. Events never hold up a call: they go
        /// through a bounded queue and are dropped when it is full.
        pub fn configure_introspection(
            &self,
            state: $crate::IntrospectionState,
            qos: &horus_ros_rmw::qos::Qos,
        ) -> Result<(), $crate::SetupError> {
            self.core.configure_introspection(state, qos)
        }

        /// The introspection state in force.
        pub fn introspection_state(&self) -> $crate::IntrospectionState {
            self.core.introspection_state()
        }

        /// The `client_gid` of this client's introspection events (rmw
        /// `rmw_get_gid_for_client`): its request writer's GID on the rustdds backend (as
        /// rmw_fastrtps), its `clientid` on the Cyclone backend (as rmw_cyclonedds).
        pub fn introspection_client_gid(&self) -> horus_ros_rmw::Gid {
            self.core.introspection_client_gid()
        }

        /// The GID of the `<service>/_service_event` publisher, while introspection is on.
        pub fn introspection_gid(&self) -> Option<horus_ros_rmw::Gid> {
            self.core.introspection_gid()
        }
    };
}
pub(crate) use client_handle_methods;
