//! [`Graph`]: a [`GraphCache`] kept up to date from a context's discovery feed by a background
//! thread, with change notification (`wait_for_graph_change`, event subscriptions) and service
//! readiness checks — what rcl offers through the graph guard condition and
//! `rcl_service_server_is_available`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, Weak};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use std::collections::{BTreeMap, HashMap};

use horus_ros_rmw::qos::EndpointKind;
use horus_ros_rmw::service::ClientIdLookup;
use horus_ros_rmw::{
    Context, DiscoveryEvent, DiscoveryFeed, DiscoveryFeedError, FeedWaker, Gid, VendorId,
};

use crate::subscription::{GraphSubscription, Subscribers, SUBSCRIPTION_CAPACITY};
use crate::{EndpointEntry, GraphCache};
/// Most discovery events applied under one lock, so readers are never held off for long.
const MAX_BATCH: usize = 1024;

/// Why a [`Graph`] could not be started.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GraphStartError {
    /// The context's discovery feed could not be opened (e.g. another `Graph` holds it).
    #[error(transparent)]
    Feed(#[from] DiscoveryFeedError),
    /// The background thread could not be started.
    #[error("could not start the graph thread: {0}")]
    Thread(std::io::Error),
}

/// Applies one discovery event to the cache; returns whether the cache changed.
pub fn apply_discovery_event(cache: &mut GraphCache, event: DiscoveryEvent) -> bool {
    match event {
        DiscoveryEvent::ParticipantDiscovered(p) => cache.add_participant(p.gid, p.enclave),
        DiscoveryEvent::ParticipantLost { gid } => cache.remove_participant(gid),
        DiscoveryEvent::EndpointDiscovered(e) => cache.add_entity(EndpointEntry {
            gid: e.gid,
            participant_gid: e.participant_gid,
            dds_topic_name: e.dds_topic_name,
            dds_type_name: e.dds_type_name,
            qos: e.qos,
            type_hash: e.type_hash,
            kind: e.kind,
        }),
        DiscoveryEvent::EndpointLost { gid, .. } => cache.remove_entity(gid),
        DiscoveryEvent::ParticipantEntities(info) => cache.update_participant_entities(info),
        // Matches are kept by `Graph`, not by the cache.
        DiscoveryEvent::Matched { .. } => false,
    }
}

struct State {
    cache: GraphCache,
    /// Whether the feed reads participants' USER_DATA (an enclave it does not report is absent).
    reads_user_data: bool,
    /// Vendor of each participant seen by SPDP, by GUID prefix (the cache keeps no vendors).
    vendors: BTreeMap<[u8; 12], VendorId>,
    /// For each of our endpoints, the endpoints it is matched with, and since when.
    matches: HashMap<Gid, BTreeMap<Gid, Instant>>,
    /// The rmw_cyclonedds client id (USER_DATA `clientid=`) of each discovered endpoint that
    /// announces one; kept as long as the endpoint is.
    client_ids: HashMap<Gid, Arc<str>>,
    /// Bumped on every change of the cache.
    generation: u64,
    /// When `generation` was last bumped (the graph's creation before any change).
    changed_at: Instant,
}

struct Shared {
    state: Mutex<State>,
    changed: Condvar,
    /// The queues of `subscribe` and (feature `tokio`) `events`, fed with every change.
    subscribers: Subscribers,
    watchers: Mutex<Vec<Weak<dyn GraphWatcher>>>,
    stop: AtomicBool,
}

impl Shared {
    fn state(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn is_matched(&self, local: Gid, remote: Gid) -> bool {
        self.state()
            .matches
            .get(&local)
            .is_some_and(|m| m.contains_key(&remote))
    }

    fn matched_in_participant(&self, local: Gid, participant: Gid) -> Option<Gid> {
        let prefix = participant.prefix();
        self.state()
            .matches
            .get(&local)?
            .keys()
            .find(|remote| remote.prefix() == prefix)
            .copied()
    }

    fn participant_matched_since(&self, local: Gid, participant: Gid) -> Option<Instant> {
        let prefix = participant.prefix();
        self.state()
            .matches
            .get(&local)?
            .iter()
            .filter(|(remote, _)| remote.prefix() == prefix)
            .map(|(_, since)| *since)
            .min()
    }

    fn client_id(&self, gid: Gid) -> ClientIdLookup {
        let state = self.state();
        match state.client_ids.get(&gid) {
            Some(id) => ClientIdLookup::Id(Arc::clone(id)),
            None if state.cache.endpoints.contains_key(&gid) => ClientIdLookup::Absent,
            None => ClientIdLookup::Undiscovered,
        }
    }

    fn matched_with_client_id(&self, local: Gid, participant: Gid, id: &str) -> bool {
        let prefix = participant.prefix();
        let state = self.state();
        state.matches.get(&local).is_some_and(|remotes| {
            remotes.keys().any(|remote| {
                remote.prefix() == prefix
                    && state.client_ids.get(remote).is_some_and(|r| &**r == id)
            })
        })
    }

    /// Tells every live watcher of a change (outside every lock of the graph), forgetting the
    /// dropped ones.
    fn tell_watchers(&self) {
        let live: Vec<Arc<dyn GraphWatcher>> = {
            let mut watchers = self.watchers.lock().unwrap_or_else(|p| p.into_inner());
            watchers.retain(|w| w.strong_count() > 0);
            watchers.iter().filter_map(Weak::upgrade).collect()
        };
        let view = GraphView { shared: self };
        for watcher in live {
            watcher.graph_changed(&view);
        }
    }
}

/// Told of every change of a [`Graph`] (endpoints, participants, nodes, matches made or lost),
/// on the graph's own thread, right after the change is applied: see [`Graph::watch`].
pub trait GraphWatcher: Send + Sync {
    /// The graph changed; `graph` answers queries on it as it is now. Runs on the graph's
    /// thread: keep it short and never block in it (e.g. wake a thread of your own).
    fn graph_changed(&self, graph: &GraphView<'_>);
}

/// The graph as a [`GraphWatcher`] sees it during [`graph_changed`](GraphWatcher::graph_changed).
pub struct GraphView<'a> {
    shared: &'a Shared,
}

impl GraphView<'_> {
    /// Whether our endpoint `local` is matched with `remote` (see [`Graph::is_matched`]).
    pub fn is_matched(&self, local: Gid, remote: Gid) -> bool {
        self.shared.is_matched(local, remote)
    }

    /// An endpoint of `participant` matched with our `local` (see
    /// [`Graph::matched_in_participant`]).
    pub fn matched_in_participant(&self, local: Gid, participant: Gid) -> Option<Gid> {
        self.shared.matched_in_participant(local, participant)
    }

    /// Runs `f` on the cache as it is now (see [`Graph::read`]).
    pub fn read<R>(&self, f: impl FnOnce(&GraphCache) -> R) -> R {
        f(&self.shared.state().cache)
    }
}

/// The live ROS graph of one context: every participant, node and endpoint it can see, its own
/// included. Dropping it stops the background thread.
#[must_use = "the graph stops following discovery when dropped"]
pub struct Graph {
    shared: Arc<Shared>,
    worker: Option<JoinHandle<()>>,
    /// Wakes the background thread (to stop it).
    feed_waker: FeedWaker,
}

impl std::fmt::Debug for Graph {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Graph")
            .field("generation", &self.generation())
            .finish()
    }
}

impl Graph {
    /// The graph of `context` — the one way to it: started on first use, then the same one for
    /// every caller while any of them keeps it (services, the CLI and applications all look at
    /// one graph). The context holds it (see [`Context::shared`]), as rmw_zenoh's context holds
    /// its graph cache.
    pub fn of(context: &Context) -> Result<Arc<Self>, GraphStartError> {
        context.shared(|| Self::start(context))
    }

    /// Starts following `context`'s discovery (a context's discovery feed can be taken once).
    fn start(context: &Context) -> Result<Self, GraphStartError> {
        let feed = context.discovery_feed()?;
        let mut cache = GraphCache::new();
        cache.record_events(true);
        let shared = Arc::new(Shared {
            state: Mutex::new(State {
                cache,
                reads_user_data: context.capabilities().reads_participant_user_data,
                vendors: BTreeMap::new(),
                matches: HashMap::new(),
                client_ids: HashMap::new(),
                generation: 0,
                changed_at: Instant::now(),
            }),
            changed: Condvar::new(),
            subscribers: Subscribers::default(),
            watchers: Mutex::new(Vec::new()),
            stop: AtomicBool::new(false),
        });
        let feed_waker = feed.waker();
        let worker_shared = Arc::clone(&shared);
        let worker = std::thread::Builder::new()
            .name("horus-ros-graph".to_owned())
            .spawn(move || run(&worker_shared, feed))?;
        Ok(Self {
            shared,
            worker: Some(worker),
            feed_waker,
        })
    }

    /// Runs `f` on the cache as it is now (the cache is locked meanwhile: keep `f` short).
    pub fn read<R>(&self, f: impl FnOnce(&GraphCache) -> R) -> R {
        f(&self.shared.state().cache)
    }

    /// A counter bumped on every change of the graph.
    pub fn generation(&self) -> u64 {
        self.shared.state().generation
    }

    /// When the graph last changed (when it was created, before any change): a reader can
    /// tell how long the graph has been quiet without waiting.
    pub fn last_change(&self) -> Instant {
        self.shared.state().changed_at
    }

    /// Every change from now on, as typed events in a bounded queue (see
    /// [`GraphSubscription`] for what happens to a subscriber that falls behind). Dropping the
    /// subscription unsubscribes.
    pub fn subscribe(&self) -> GraphSubscription {
        GraphSubscription::new(self.subscribers().add(SUBSCRIPTION_CAPACITY))
    }

    /// The queues every change goes to (`subscribe`, and `events` with the feature `tokio`).
    pub(crate) fn subscribers(&self) -> &Subscribers {
        &self.shared.subscribers
    }

    /// Tells `watcher` of every change from now on, until it is dropped (the graph keeps only a
    /// weak reference). This is how a thread that waits on something else (a DDS reader) learns
    /// of graph changes without polling: its watcher wakes it.
    pub fn watch(&self, watcher: Weak<dyn GraphWatcher>) {
        let mut watchers = self
            .shared
            .watchers
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        // Dropped watchers go here too, not only at changes: in a quiet graph, watchers made and
        // dropped again and again would otherwise pile up.
        watchers.retain(|w| w.strong_count() > 0);
        watchers.push(watcher);
    }

    /// Waits until the graph changes, at most `timeout`; returns whether it changed
    /// (`rcl_wait` on the graph guard condition). A caller that looked at the graph before
    /// waiting must use [`wait_for_graph_change_since`](Self::wait_for_graph_change_since)
    /// with the generation it looked at, or miss a change made in between.
    pub fn wait_for_graph_change(&self, timeout: Duration) -> bool {
        let start = self.generation();
        self.wait_for_graph_change_since(start, timeout)
    }

    /// Waits until the graph's [`generation`](Self::generation) is no longer `seen`, at most
    /// `timeout`; returns whether it changed (at once if it already has). Read the generation
    /// before looking at the graph, look, then wait with it: no change can fall in between.
    pub fn wait_for_graph_change_since(&self, seen: u64, timeout: Duration) -> bool {
        let deadline = Instant::now().checked_add(timeout);
        let mut state = self.shared.state();
        while state.generation == seen {
            let Some(deadline) = deadline else {
                state = self
                    .shared
                    .changed
                    .wait(state)
                    .unwrap_or_else(|p| p.into_inner());
                continue;
            };
            let now = Instant::now();
            if now >= deadline {
                return false;
            }
            state = self
                .shared
                .changed
                .wait_timeout(state, deadline - now)
                .map(|(s, _)| s)
                .unwrap_or_else(|p| p.into_inner().0);
        }
        true
    }

    /// Waits until `condition` holds on the cache, at most `timeout`; returns whether it holds.
    /// Checked at once and after every change, never by polling.
    pub fn wait_until(
        &self,
        timeout: Duration,
        mut condition: impl FnMut(&GraphCache) -> bool,
    ) -> bool {
        self.wait_state(timeout, |state| condition(&state.cache))
    }

    /// Waits until `condition` holds on the state, at most `timeout`, re-checking on every change.
    fn wait_state(&self, timeout: Duration, mut condition: impl FnMut(&State) -> bool) -> bool {
        let deadline = Instant::now() + timeout;
        let mut state = self.shared.state();
        loop {
            if condition(&state) {
                return true;
            }
            let now = Instant::now();
            if now >= deadline {
                return false;
            }
            let seen = state.generation;
            while state.generation == seen {
                let now = Instant::now();
                if now >= deadline {
                    return condition(&state);
                }
                state = self
                    .shared
                    .changed
                    .wait_timeout(state, deadline - now)
                    .map(|(s, _)| s)
                    .unwrap_or_else(|p| p.into_inner().0);
            }
        }
    }

    /// Whether our endpoint `local` is matched with `remote` (data from the writer of the pair
    /// reaches the reader), as the DDS layer reported it.
    pub fn is_matched(&self, local: Gid, remote: Gid) -> bool {
        self.shared.is_matched(local, remote)
    }

    /// An endpoint of the participant of `participant` (any GID of it: the participant's or an
    /// endpoint's) that our endpoint `local` is matched with, if any — from the matches the DDS
    /// layer reported, whether or not discovery has listed that endpoint yet.
    pub fn matched_in_participant(&self, local: Gid, participant: Gid) -> Option<Gid> {
        self.shared.matched_in_participant(local, participant)
    }

    /// The endpoints our endpoint `local` is matched with, as the DDS layer reported them (their
    /// number is rcl's `rcl_subscription_get_publisher_count` / `rcl_publisher_get_subscription_count`).
    pub fn matched_with(&self, local: Gid) -> Vec<Gid> {
        self.shared
            .state()
            .matches
            .get(&local)
            .map(|m| m.keys().copied().collect())
            .unwrap_or_default()
    }

    /// When our endpoint `local` was matched with `remote`, if it is.
    pub fn matched_since(&self, local: Gid, remote: Gid) -> Option<Instant> {
        self.shared
            .state()
            .matches
            .get(&local)
            .and_then(|m| m.get(&remote))
            .copied()
    }

    /// Waits until `local` is matched with `remote`, at most `timeout`.
    pub fn wait_for_match(&self, local: Gid, remote: Gid, timeout: Duration) -> bool {
        self.wait_state(timeout, |s| {
            s.matches
                .get(&local)
                .is_some_and(|m| m.contains_key(&remote))
        })
    }

    /// Waits until our endpoint `local` is matched with every endpoint of `kind` discovery lists
    /// on the DDS topic `dds_topic` (but those in `except`), at most `timeout`; returns whether
    /// it is.
    pub fn wait_for_all_matched(
        &self,
        local: Gid,
        dds_topic: &str,
        kind: EndpointKind,
        except: &[Gid],
        timeout: Duration,
    ) -> bool {
        self.wait_state(timeout, |s| {
            let matched = s.matches.get(&local);
            s.cache.index.topics.get(dds_topic).is_none_or(|topic| {
                topic
                    .gids(kind)
                    .iter()
                    .filter(|gid| **gid != local && !except.contains(gid))
                    .all(|gid| matched.is_some_and(|m| m.contains_key(gid)))
            })
        })
    }

    /// Records the RIHS01 hash of a service type known to this process (Jazzy peers do not send
    /// service type hashes), so that servers/clients info can show it.
    pub fn set_service_type_hash(&self, service_type: &str, hash: horus_ros_msgs::TypeHash) {
        self.shared
            .state()
            .cache
            .set_service_type_hash(service_type, hash);
    }

    /// The DDS vendor of the participant `gid` belongs to (any GID of it: participant or
    /// endpoint), if SPDP has announced it: tells which RMW's wire conventions it follows.
    pub fn participant_vendor(&self, gid: Gid) -> Option<VendorId> {
        self.shared.state().vendors.get(&gid.prefix()).copied()
    }

    /// Whether a server of `service` (fully qualified) can answer now: its request reader AND its
    /// reply writer are both known (a request sent when only the reader is known could have its
    /// reply lost — rclcpp#625).
    pub fn service_is_ready(&self, service: &str) -> bool {
        self.read(|c| c.service_is_available(service))
    }

    /// Waits until [`service_is_ready`](Self::service_is_ready), at most `timeout`.
    pub fn wait_for_service(&self, service: &str, timeout: Duration) -> bool {
        self.wait_until(timeout, |c| c.service_is_available(service))
    }
}

/// What the request/reply layer of rmw asks of the graph.
impl horus_ros_rmw::service::Peers for Graph {
    fn participant_vendor(&self, gid: Gid) -> Option<VendorId> {
        Graph::participant_vendor(self, gid)
    }

    fn is_matched(&self, local: Gid, remote: Gid) -> bool {
        Graph::is_matched(self, local, remote)
    }

    fn participant_matched_since(&self, local: Gid, remote: Gid) -> Option<Instant> {
        self.shared.participant_matched_since(local, remote)
    }

    fn client_id(&self, gid: Gid) -> ClientIdLookup {
        self.shared.client_id(gid)
    }

    fn matched_with_client_id(&self, local: Gid, remote: Gid, id: &str) -> bool {
        self.shared.matched_with_client_id(local, remote, id)
    }
}

impl Drop for Graph {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.feed_waker.wake();
        if let Some(worker) = self.worker.take() {
            // The last handle can go on the graph's own thread, when a watcher it lets go held
            // the graph (a server's, through its peers): that thread then ends by itself, as it
            // sees `stop` once the watcher returns. Joining itself would fail (EDEADLK).
            if worker.thread().id() != std::thread::current().id() {
                let _ = worker.join();
            }
        }
        self.shared.subscribers.close_all();
    }
}

/// Applies one event to the state: vendors, then the cache.
fn apply(state: &mut State, event: DiscoveryEvent) -> bool {
    match &event {
        DiscoveryEvent::ParticipantDiscovered(p) => {
            state.vendors.insert(p.gid.prefix(), p.vendor_id);
            // USER_DATA read without `enclave=`: not a ROS participant, unless its DDS is
            // RustDDS, whose ROS participants (ours on the rustdds backend, ros2-client) cannot
            // announce USER_DATA at all.
            if state.reads_user_data && p.enclave.is_none() && p.vendor_id != VendorId::RUSTDDS {
                let gid = p.gid;
                let added = apply_discovery_event(&mut state.cache, event);
                return state.cache.mark_not_ros(gid) || added;
            }
        }
        DiscoveryEvent::ParticipantLost { gid } => {
            let prefix = gid.prefix();
            state.vendors.remove(&prefix);
            state
                .client_ids
                .retain(|endpoint, _| endpoint.prefix() != prefix);
            state.matches.retain(|local, _| local.prefix() != prefix);
            for remotes in state.matches.values_mut() {
                remotes.retain(|r, _| r.prefix() != prefix);
            }
        }
        DiscoveryEvent::EndpointDiscovered(e) => {
            let id = client_id_of(&e.user_data);
            let changed = match id {
                Some(id) if state.client_ids.get(&e.gid) != Some(&id) => {
                    state.client_ids.insert(e.gid, id);
                    true
                }
                Some(_) => false,
                None => state.client_ids.remove(&e.gid).is_some(),
            };
            return apply_discovery_event(&mut state.cache, event) || changed;
        }
        DiscoveryEvent::EndpointLost { gid, .. } => {
            state.client_ids.remove(gid);
            state.matches.remove(gid);
            for remotes in state.matches.values_mut() {
                remotes.remove(gid);
            }
        }
        DiscoveryEvent::Matched { local, remote } => {
            let remotes = state.matches.entry(*local).or_default();
            if remotes.contains_key(remote) {
                return false;
            }
            remotes.insert(*remote, Instant::now());
            return true;
        }
        _ => {}
    }
    apply_discovery_event(&mut state.cache, event)
}

/// The `clientid=` in an endpoint's USER_DATA (rmw_cyclonedds jazzy `rmw_node.cpp`
/// `get_user_data_key`), if it announces one.
fn client_id_of(user_data: &[u8]) -> Option<Arc<str>> {
    let mut pairs = horus_ros_msgs::user_data::parse_key_value(user_data);
    let id = pairs.remove("clientid")?;
    Some(String::from_utf8_lossy(&id).into())
}

/// The background thread: applies discovery events in batches and tells waiters and subscribers.
fn run(shared: &Shared, mut feed: DiscoveryFeed) {
    while !shared.stop.load(Ordering::SeqCst) {
        // Woken by discovery, by our own context's changes and by `Graph::drop`.
        let Some(first) = feed.next_timeout(None) else {
            continue;
        };
        let changed = {
            let mut state = shared.state();
            let mut changed = apply(&mut state, first);
            for _ in 1..MAX_BATCH {
                match feed.try_next() {
                    Some(event) => changed |= apply(&mut state, event),
                    None => break,
                }
            }
            if changed {
                state.generation += 1;
                state.changed_at = Instant::now();
            }
            // To the subscribers before the change can be seen (the state is still locked).
            shared.subscribers.deliver(&state.cache.drain_events());
            changed
        };
        shared.changed.notify_all();
        shared.subscribers.wake();
        if changed {
            shared.tell_watchers();
        }
    }
}

// The message shows the cause, so it is no `source()` (not `#[from]`).
impl From<std::io::Error> for GraphStartError {
    fn from(e: std::io::Error) -> Self {
        Self::Thread(e)
    }
}
