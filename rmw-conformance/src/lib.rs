//! The backend contract's conformance suite: every test of the contract, written once and run on
//! every backend — the in-memory test backend (`horus-ros-rmw-memory`), RustDDS, Cyclone DDS
//! and Zenoh (this crate's `tests/`) — and usable by a backend outside the workspace:
//!
//! ```ignore
//! // tests/conformance.rs of a backend's crate (dev-dependency: horus-ros-rmw-conformance)
//! fn context(domain: u32) -> horus_ros_rmw::Context {
//!     horus_ros_rmw::Context::builder()
//!         .domain_id(domain)
//!         .implementation(std::sync::Arc::new(MyBackend::default()))
//!         .build()
//!         .expect("context")
//! }
//! horus_ros_rmw_conformance::conformance_tests!(context);
//! ```
//!
//! What is tested, through the whole stack above the contract: the graph (nodes, topics,
//! services, endpoints and their nodes, departures), publishers and subscriptions within and
//! between contexts, QoS matching and history depth, late joiners, wait sets, blocking and
//! awaited service calls in the convention the backend offers, a server that leaves, node
//! services, and a client that knows only DDS type names. Each test takes the backend's context
//! factory (`context(domain)`) and uses domains of its own (1 to 12). Waits are bounded and woken
//! by the event (a sample, a graph change); what a backend cannot do (its
//! [`Capabilities`](horus_ros_rmw::Capabilities)) is asserted as refused.

use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_msgs::rcl_interfaces::srv::{ListParameters, ListParametersRequest};
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_msgs::type_description_interfaces::srv::{
    GetTypeDescription, GetTypeDescriptionRequest,
};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, RawEndpointSpec, RawReader, SampleId, Subscription, WaitSet};
use horus_ros_services::prelude::*;
use horus_ros_services::{
    DdsServiceServer, DynamicPart, DynamicServiceClient, DynamicServiceType, NodeServices,
    ServiceServerTrait, ServiceType,
};

/// The conformance tests as `#[test]`s of the including file, each run on the contexts
/// `$context(domain)` makes.
///
/// `conformance_tests!(context; known_failure: name)` declares one test a known failure of the
/// backend: it is generated `#[should_panic]`, so that it fails the day the backend is fixed
/// (and the declaration must go). Only
/// [`a_volatile_reader_gets_none_of_a_writers_history`] can be declared so.
#[macro_export]
macro_rules! conformance_tests {
    ($context:ident) => {
        $crate::conformance_tests!(@all $context);
        $crate::conformance_tests!(@each $context: a_volatile_reader_gets_none_of_a_writers_history);
    };
    ($context:ident; known_failure: a_volatile_reader_gets_none_of_a_writers_history) => {
        $crate::conformance_tests!(@all $context);

        #[test]
        #[should_panic]
        fn a_volatile_reader_gets_none_of_a_writers_history() {
            $crate::a_volatile_reader_gets_none_of_a_writers_history(&$context);
        }
    };
    (@all $context:ident) => {
        $crate::conformance_tests!(@each $context:
            the_graph_sees_another_contexts_nodes_topics_services_and_endpoints,
            messages_reach_subscriptions_of_other_contexts_and_of_the_same_one,
            a_wait_set_reports_the_readers_with_data_and_its_own_wake_up,
            blocking_calls_are_answered_and_their_failures_reported,
            a_server_that_leaves_ends_the_call_waiting_for_it,
            awaited_calls_are_answered_by_sync_and_async_servers,
            node_services_answer,
            qos_decides_matches_depth_and_what_late_joiners_get,
            a_client_of_dds_type_names_only_reaches_a_server
        );
    };
    (@each $context:ident: $($test:ident),+) => {
        $(
            #[test]
            fn $test() {
                $crate::$test(&$context);
            }
        )+
    };
}

/// One second.
pub const SECOND: Duration = Duration::from_secs(1);

fn adder(node: &Node, name: &str) -> ServiceServer<AddTwoInts> {
    ServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .on_request(|req| match req.a {
            0 => Err("a must not be zero".to_owned()),
            _ => Ok(AddTwoIntsResponse { sum: req.a + req.b }),
        })
        .build()
        .expect("server")
}

fn client(node: &Node, name: &str) -> ServiceClient<AddTwoInts> {
    ServiceClient::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .build()
        .expect("client")
}

/// The next message of `subscription`, waiting for it (at most 10 s).
fn receive_within(subscription: &mut Subscription<StringMsg>, what: &str) -> StringMsg {
    let deadline = Instant::now() + 10 * SECOND;
    loop {
        if let Some(message) = subscription.try_take().expect("take") {
            return message;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(subscription.wait(left), "{what} never came");
    }
}

/// Wakes a parked thread (the waker of a raw server's requests).
struct Unparker(thread::Thread);

impl std::task::Wake for Unparker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

/// Another context's nodes, topics, services and endpoints (each under its node) are in the
/// graph, whether they came before or after the graph was opened, and go when they go.
pub fn the_graph_sees_another_contexts_nodes_topics_services_and_endpoints(
    context: &dyn Fn(u32) -> Context,
) {
    let a = context(1);
    let talker = a.create_node("talker", "/memory").expect("node");
    let publisher = talker
        .create_publisher::<StringMsg>("chatter", &Qos::default_profile())
        .expect("publisher");
    let server = adder(&talker, "add");
    let b = context(1);
    let listener = b.create_node("listener", "/").expect("node");
    let subscription = listener
        .create_subscription::<StringMsg>("/memory/chatter", &Qos::default_profile())
        .expect("subscription");

    // Opened after everything was created: the feed starts from what is already there.
    let graph = Graph::of(&b).expect("graph");
    // Complete: endpoints and nodes, and each endpoint listed under its node (which a backend
    // may learn after the endpoint itself, as ros_discovery_info follows DDS discovery).
    let complete = |c: &horus_ros_graph::GraphCache| {
        c.node_count() == 2
            && c.count_publishers("/memory/chatter") == 1
            && c.count_subscribers("/memory/chatter") == 1
            && c.service_is_available("/memory/add")
            && c.publishers_info_by_topic("/memory/chatter", false)
                .iter()
                .chain(&c.subscriptions_info_by_topic("/memory/chatter", false))
                .all(|e| e.node_name != "_NODE_NAME_UNKNOWN_")
            && c.servers_info_by_service("/memory/add", false)
                .is_ok_and(|s| s.iter().all(|e| e.node_name == "talker"))
    };
    assert!(
        graph.wait_until(10 * SECOND, complete),
        "graph incomplete: {:?}",
        graph.read(|c| (
            c.node_names(),
            c.count_publishers("/memory/chatter"),
            c.count_subscribers("/memory/chatter"),
            c.service_is_available("/memory/add")
        ))
    );
    graph.read(|c| {
        let nodes: Vec<(String, String)> = c
            .node_names()
            .into_iter()
            .map(|n| (n.namespace, n.name))
            .collect();
        assert_eq!(
            nodes,
            [
                ("/".to_owned(), "listener".to_owned()),
                ("/memory".to_owned(), "talker".to_owned())
            ]
        );
        let topics = c.topic_names_and_types(false);
        assert_eq!(
            topics
                .get("/memory/chatter")
                .map(|t| t.iter().map(String::as_str).collect::<Vec<_>>()),
            Some(vec!["std_msgs/msg/String"])
        );
        let services = c.service_names_and_types(false);
        assert_eq!(
            services
                .get("/memory/add")
                .map(|t| t.iter().map(String::as_str).collect::<Vec<_>>()),
            Some(vec!["example_interfaces/srv/AddTwoInts"])
        );
        let publishers = c.publishers_info_by_topic("/memory/chatter", false);
        assert_eq!(publishers.len(), 1);
        assert_eq!(publishers[0].node_name, "talker");
        assert_eq!(publishers[0].node_namespace, "/memory");
        assert_eq!(publishers[0].endpoint_gid, publisher.gid());
        assert_eq!(publishers[0].topic_type, "std_msgs/msg/String");
        // Announced where the publisher's backend announces type hashes (not rustdds: no
        // USER_DATA), else unknown.
        let hash = if a.capabilities().announces_type_hashes {
            StringMsg::type_hash()
        } else {
            TypeHash::ZERO
        };
        assert_eq!(publishers[0].topic_type_hash, hash);
        let subscribers = c.subscriptions_info_by_topic("/memory/chatter", false);
        assert_eq!(subscribers.len(), 1);
        assert_eq!(subscribers[0].node_name, "listener");
        assert_eq!(subscribers[0].endpoint_gid, subscription.gid());
        let servers = c
            .servers_info_by_service("/memory/add", false)
            .expect("servers");
        assert_eq!(servers.len(), 1);
        assert_eq!(servers[0].node_name, "talker");
        assert_eq!(servers[0].service_type, "example_interfaces/srv/AddTwoInts");
        assert_eq!(servers[0].endpoint_count(), 2);
    });
    // The other context's participant, with its backend's vendor.
    assert_eq!(graph.participant_vendor(a.gid()), Some(a.vendor_id()));
    assert!(graph.is_matched(subscription.gid(), publisher.gid()));

    // A change wakes a waiter at once.
    let seen = graph.generation();
    let waiter = {
        let graph = Arc::clone(&graph);
        thread::spawn(move || {
            let start = Instant::now();
            (
                graph.wait_for_graph_change_since(seen, 30 * SECOND),
                start.elapsed(),
            )
        })
    };
    let extra = a.create_node("extra", "/memory").expect("node");
    let (changed, took) = waiter.join().expect("waiter");
    assert!(changed && took < 10 * SECOND, "{changed} after {took:?}");
    assert!(graph.wait_until(10 * SECOND, |c| c.node_count() == 3));

    // Endpoints and nodes withdrawn, then the whole participant gone.
    let publisher_gid = publisher.gid();
    drop(publisher);
    assert!(graph.wait_until(10 * SECOND, |c| c.count_publishers("/memory/chatter") == 0));
    assert!(!graph.is_matched(subscription.gid(), publisher_gid));
    drop(extra);
    assert!(graph.wait_until(10 * SECOND, |c| c.node_count() == 2));
    drop((server, talker, a));
    assert!(graph.wait_until(10 * SECOND, |c| c.node_count() == 1
        && !c.service_is_available("/memory/add")));

    // A feed opened again starts from a new snapshot.
    drop(graph);
    let graph = Graph::of(&b).expect("graph again");
    assert!(graph.wait_until(10 * SECOND, |c| c.node_count() == 1
        && c.count_subscribers("/memory/chatter") == 1));
}

/// A message reaches the matched subscriptions of another context and of the publisher's own.
pub fn messages_reach_subscriptions_of_other_contexts_and_of_the_same_one(
    context: &dyn Fn(u32) -> Context,
) {
    let a = context(2);
    let talker = a.create_node("talker", "/").expect("node");
    let publisher = talker
        .create_publisher::<StringMsg>("chatter", &Qos::default_profile())
        .expect("publisher");
    let mut own = talker
        .create_subscription::<StringMsg>("chatter", &Qos::default_profile())
        .expect("own subscription");
    let b = context(2);
    let listener = b.create_node("listener", "/").expect("node");
    let mut remote = listener
        .create_subscription::<StringMsg>("/chatter", &Qos::default_profile())
        .expect("subscription");
    // Matched as discovery reports it, on the publisher's side.
    let graph = Graph::of(&a).expect("graph");
    assert!(graph.wait_for_match(publisher.gid(), remote.gid(), 10 * SECOND));
    assert!(graph.wait_for_match(publisher.gid(), own.gid(), 10 * SECOND));
    assert!(graph.wait_for_match(own.gid(), publisher.gid(), 10 * SECOND));
    for i in 0..3 {
        publisher
            .publish(StringMsg {
                data: format!("hello {i}"),
            })
            .expect("publish");
    }
    for subscription in [&mut remote, &mut own] {
        for i in 0..3 {
            let message = receive_within(subscription, "a message");
            assert_eq!(message.data, format!("hello {i}"));
        }
        assert_eq!(subscription.try_take().expect("take"), None);
    }
    // A reader's waker ends its wait with nothing to take.
    let waker = remote.waker();
    let woken = thread::spawn(move || waker.wake());
    assert!(remote.wait(30 * SECOND));
    woken.join().expect("waker");
}

/// A wait set reports exactly the attached readers that got data, and its own wake-up from
/// another thread; with nothing to report it times out.
pub fn a_wait_set_reports_the_readers_with_data_and_its_own_wake_up(
    context: &dyn Fn(u32) -> Context,
) {
    let a = context(3);
    let n = a.create_node("raw", "/").expect("node");
    let spec = |topic: &str| RawEndpointSpec {
        dds_topic_name: format!("rt/{topic}"),
        dds_type_name: "std_msgs::msg::dds_::String_".to_owned(),
        type_hash: TypeHash::ZERO,
        qos: Qos::default_profile(),
        service_id: None,
    };
    let writer = n.create_raw_writer(&spec("one")).expect("writer");
    let mut one = n.create_raw_reader(&spec("one")).expect("reader");
    let mut two = n.create_raw_reader(&spec("two")).expect("reader");
    let set = WaitSet::new(&a).expect("wait set");
    set.attach(&mut one, 1).expect("attach");
    set.attach(&mut two, 2).expect("attach");
    // Matched both ways before anything is written (a VOLATILE reader of a DDS backend gets
    // nothing written before its writer knew it, even in the same participant).
    let graph = Graph::of(&a).expect("graph");
    let matched = |writer: Gid, reader: Gid| {
        graph.wait_for_match(writer, reader, 10 * SECOND)
            && graph.wait_for_match(reader, writer, 10 * SECOND)
    };
    assert!(matched(writer.gid(), one.gid()), "the reader never matched");
    // Whether samples carry a related identity and can be addressed to one reader (a backend
    // without it refuses a related identity).
    let identities = a.capabilities().carries_sample_identity;
    let first = writer
        .write(vec![1, 0, 0, 0, 0], None, None)
        .expect("write");
    let related = identities.then_some(first);
    let second = writer
        .write(vec![1, 0, 0, 0, 0], related, None)
        .expect("write");
    assert_eq!((first.writer, first.sequence_number), (writer.gid(), 1));
    assert_eq!(second.sequence_number, 2);
    let mut ready = Vec::new();
    assert!(set.wait(10 * SECOND, &mut ready));
    assert_eq!(ready, [1]);
    // The identity the writer gave, or its writer with an unknown sequence number where the
    // backend reports none on receipt (Cyclone DDS).
    let same = |taken: SampleId, written: SampleId| {
        taken == written
            || (taken.writer == written.writer
                && taken.sequence_number == SampleId::UNKNOWN_SEQUENCE_NUMBER)
    };
    // An attached reader is waited for through its set.
    let take_via_set = |reader: &mut RawReader, what: &str| {
        let deadline = Instant::now() + 10 * SECOND;
        loop {
            if let Some(sample) = reader.take().expect("take") {
                return sample;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            let mut ready = Vec::new();
            assert!(set.wait(left, &mut ready), "{what} never came");
        }
    };
    let taken = take_via_set(&mut one, "the first sample");
    assert!(same(taken.id, first), "{:?} for {first:?}", taken.id);
    assert_eq!(taken.related, None);
    let taken = take_via_set(&mut one, "the second sample");
    assert!(same(taken.id, second), "{:?} for {second:?}", taken.id);
    assert_eq!(taken.related, related);
    assert_eq!(two.take().expect("take"), None);
    // The set's own waker (after whatever the second sample's arrival left marked).
    set.wait(Duration::ZERO, &mut Vec::new());
    let waker = set.waker();
    thread::spawn(move || waker.wake()).join().expect("waker");
    ready.clear();
    assert!(set.wait(10 * SECOND, &mut ready));
    assert!(ready.is_empty(), "{ready:?}");
    ready.clear();
    assert!(!set.wait(Duration::from_millis(50), &mut ready));
    if identities {
        // Addressed to one reader only.
        let mut three = n.create_raw_reader(&spec("one")).expect("reader");
        assert!(
            matched(writer.gid(), three.gid()),
            "the reader never matched"
        );
        writer
            .write(vec![1, 0, 0, 0, 0], None, Some(three.gid()))
            .expect("write");
        assert!(three.wait(10 * SECOND));
        assert!(three.take().expect("take").is_some());
        // (Whether the other readers get it too is the backend's: the contract says the
        // sample *may* go to that reader only.)
    } else {
        assert!(writer
            .write(vec![1, 0, 0, 0, 0], Some(first), None)
            .is_err());
    }
}

/// Blocking calls are answered; a handler's failure and a missing server are reported as such.
pub fn blocking_calls_are_answered_and_their_failures_reported(context: &dyn Fn(u32) -> Context) {
    let a = context(4);
    let server_node = a.create_node("server", "/").expect("node");
    let b = context(4);
    let client_node = b.create_node("client", "/").expect("node");
    let mut c = client(&client_node, "/add");
    assert!(!c.server_available());
    let start = Instant::now();
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(300)),
        Err(ServiceError::NoServer)
    );
    assert!(start.elapsed() >= Duration::from_millis(300));

    let server = adder(&server_node, "/add");
    assert!(c.wait_for_service(10 * SECOND));
    assert!(c.server_available());
    for i in 1..=20 {
        assert_eq!(
            c.call(AddTwoIntsRequest { a: i, b: 2 }, 10 * SECOND),
            Ok(AddTwoIntsResponse { sum: i + 2 })
        );
    }
    assert_eq!(
        c.call(AddTwoIntsRequest { a: 0, b: 2 }, 10 * SECOND),
        Err(ServiceError::ServiceFailed("a must not be zero".to_owned()))
    );
    assert_eq!((server.served_count(), server.failed_count()), (20, 1));
    assert_eq!(c.pending_requests(), 0);

    // A client and a server of the same context.
    let mut local = client(&server_node, "/add");
    assert!(local.wait_for_service(10 * SECOND));
    assert_eq!(
        local.call(AddTwoIntsRequest { a: 5, b: 5 }, 10 * SECOND),
        Ok(AddTwoIntsResponse { sum: 10 })
    );

    // The server gone: the client sees it leave, and calls find no server.
    drop(server);
    let graph = Graph::of(&b).expect("graph");
    assert!(graph.wait_until(10 * SECOND, |g| !g.service_is_available("/add")));
    assert!(!c.server_available());
    // No server, or (where the client's request writer was still matched with the server's
    // reader when it sent: a DDS match ends after the graph's listing) the server gone.
    let call = c.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_millis(300));
    assert!(
        matches!(
            call,
            Err(ServiceError::NoServer | ServiceError::Transport(TransportError::ServerGone))
        ),
        "{call:?}"
    );
}

/// A call waiting for a server that leaves ends (it does not wait out its timeout).
pub fn a_server_that_leaves_ends_the_call_waiting_for_it(context: &dyn Fn(u32) -> Context) {
    let a = context(5);
    let server_node = a.create_node("leaving", "/").expect("node");
    let mut server = DdsServiceServer::<AddTwoInts>::builder()
        .node(&server_node)
        .name("/leaving")
        .build()
        .expect("server");
    let b = context(5);
    let mut c = client(&b.create_node("abandoned", "/").expect("node"), "/leaving");
    assert!(c.wait_for_service(10 * SECOND));
    let caller = thread::spawn(move || c.call(AddTwoIntsRequest { a: 1, b: 2 }, 30 * SECOND));
    // The server takes the request and never answers; then it leaves.
    let mut buf = [0u8; 256];
    let deadline = Instant::now() + 10 * SECOND;
    while server.try_recv_request(&mut buf).expect("take").is_none() {
        assert!(Instant::now() < deadline, "the request never came");
        let waker = std::task::Waker::from(Arc::new(Unparker(thread::current())));
        server.register_waker(&waker);
        thread::park_timeout(SECOND);
    }
    let left = Instant::now();
    drop(server);
    let result = caller.join().expect("caller");
    assert!(
        matches!(
            &result,
            Err(ServiceError::Transport(TransportError::ServerGone))
        ),
        "{result:?}"
    );
    assert!(left.elapsed() < 10 * SECOND, "noticed late");
}

/// Awaited calls (on a runtime of two worker threads) to a blocking and an async server; a call
/// to nobody ends `NoServer`.
pub fn awaited_calls_are_answered_by_sync_and_async_servers(context: &dyn Fn(u32) -> Context) {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("tokio runtime")
        .block_on(awaited_calls(context));
}

async fn awaited_calls(context: &dyn Fn(u32) -> Context) {
    let a = context(6);
    let server_node = a.create_node("server", "/").expect("node");
    let _sync = adder(&server_node, "/sync_add");
    let _async = AsyncServiceServer::<AddTwoInts>::builder()
        .node(&server_node)
        .name("/async_add")
        .on_request(|req| async move {
            tokio::task::yield_now().await;
            Ok(AddTwoIntsResponse { sum: req.a * req.b })
        })
        .build()
        .expect("async server");
    let b = context(6);
    let client_node = b.create_node("client", "/").expect("node");
    for (name, sum) in [("/sync_add", 7), ("/async_add", 12)] {
        let c = AsyncServiceClient::<AddTwoInts>::builder()
            .node(&client_node)
            .name(name)
            .build()
            .expect("client");
        assert!(c.wait_for_service_async(10 * SECOND).await, "{name}");
        assert_eq!(
            c.call(AddTwoIntsRequest { a: 3, b: 4 }, 10 * SECOND).await,
            Ok(AddTwoIntsResponse { sum }),
            "{name}"
        );
    }
    let nobody = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&client_node)
        .name("/nobody")
        .build()
        .expect("client");
    assert_eq!(
        nobody
            .call(AddTwoIntsRequest::default(), Duration::from_millis(200))
            .await,
        Err(ServiceError::NoServer)
    );
}

/// A node's services (parameters, type descriptions) answer another context's clients.
pub fn node_services_answer(context: &dyn Fn(u32) -> Context) {
    let a = context(7);
    let n = a.create_node("params_node", "/ns").expect("node");
    let services = NodeServices::start(&n).expect("node services");
    let hash = services.register_service::<AddTwoInts>();
    let b = context(7);
    let peer = b.create_node("caller", "/").expect("node");

    let mut describe = ServiceClient::<GetTypeDescription>::builder()
        .node(&peer)
        .name("/ns/params_node/get_type_description")
        .build()
        .expect("client");
    assert!(describe.wait_for_service(10 * SECOND));
    let reply = describe
        .call(
            GetTypeDescriptionRequest {
                type_name: "example_interfaces/srv/AddTwoInts".into(),
                type_hash: hash.to_string(),
                include_type_sources: false,
            },
            10 * SECOND,
        )
        .expect("get_type_description");
    assert!(reply.successful, "{}", reply.failure_reason);
    assert_eq!(reply.type_description.compute_type_hash(), hash);

    let mut list = ServiceClient::<ListParameters>::builder()
        .node(&peer)
        .name("/ns/params_node/list_parameters")
        .build()
        .expect("client");
    assert!(list.wait_for_service(10 * SECOND));
    let names = list
        .call(ListParametersRequest::default(), 10 * SECOND)
        .expect("list_parameters")
        .result
        .names;
    assert!(names.iter().all(|n| !n.is_empty()), "{names:?}");
}

/// QoS decides what matches, how many samples a reader keeps and what a late joiner gets.
pub fn qos_decides_matches_depth_and_what_late_joiners_get(context: &dyn Fn(u32) -> Context) {
    let a = context(8);
    let n = a.create_node("qos", "/").expect("node");
    let latched = Qos::default_profile().transient_local().keep_last(2);
    let publisher = n
        .create_publisher::<StringMsg>("latched", &latched)
        .expect("publisher");
    for i in 0..3 {
        publisher
            .publish(StringMsg {
                data: format!("{i}"),
            })
            .expect("publish");
    }
    // A TRANSIENT_LOCAL late joiner gets the writer's last 2.
    let b = context(8);
    let peer = b.create_node("peer", "/").expect("node");
    let mut late = peer
        .create_subscription::<StringMsg>("/latched", &latched)
        .expect("subscription");
    // Taken once the late joiner has all it will get of the history (matched, and the
    // publisher's samples acknowledged where the backend acknowledges), up to the last one: its
    // KEEP_LAST 2 then holds the last 2, however the history arrived.
    // (Each side's matches are reported by its own context.)
    let (ours, theirs) = (Graph::of(&a).expect("graph"), Graph::of(&b).expect("graph"));
    assert!(
        theirs.wait_for_match(late.gid(), publisher.gid(), 10 * SECOND)
            && ours.wait_for_match(publisher.gid(), late.gid(), 10 * SECOND),
        "the late joiner never matched"
    );
    assert!(publisher.wait_for_acknowledgments(10 * SECOND));
    let mut got = Vec::new();
    while got.last().is_none_or(|last| last != "2") {
        got.push(receive_within(&mut late, "a late joiner's sample").data);
    }
    assert_eq!(got, ["1", "2"]);
    // A reader keeps its depth: the oldest go. (In the publisher's own context, matched both
    // ways first; taken once the publisher's samples are acknowledged, so none is in flight.)
    let mut shallow = n
        .create_subscription::<StringMsg>("/latched", &Qos::default_profile().keep_last(1))
        .expect("subscription");
    assert!(
        ours.wait_for_match(publisher.gid(), shallow.gid(), 10 * SECOND)
            && ours.wait_for_match(shallow.gid(), publisher.gid(), 10 * SECOND),
        "the shallow reader never matched"
    );
    for data in ["x", "y"] {
        publisher
            .publish(StringMsg { data: data.into() })
            .expect("publish");
    }
    assert!(publisher.wait_for_acknowledgments(10 * SECOND));
    assert_eq!(
        shallow.try_take().expect("take").map(|m| m.data),
        Some("y".into())
    );
    // A BEST_EFFORT reader matches a RELIABLE writer everywhere (whether a RELIABLE reader
    // matches a BEST_EFFORT writer is the backend's: each backend's own tests say).
    let graph = Graph::of(&b).expect("graph");
    let lenient = peer
        .create_subscription::<StringMsg>("/latched", &Qos::sensor_data())
        .expect("subscription");
    assert!(graph.wait_for_match(lenient.gid(), publisher.gid(), 10 * SECOND));
}

/// A VOLATILE reader gets nothing that a TRANSIENT_LOCAL writer wrote before they matched: its
/// first sample is the first written after (DDS's durability: a writer's history goes to
/// TRANSIENT_LOCAL readers only).
pub fn a_volatile_reader_gets_none_of_a_writers_history(context: &dyn Fn(u32) -> Context) {
    let a = context(12);
    let latched = Qos::default_profile().transient_local().keep_last(2);
    let publisher = a
        .create_node("history", "/")
        .expect("node")
        .create_publisher::<StringMsg>("history", &latched)
        .expect("publisher");
    for data in ["old", "older"] {
        publisher
            .publish(StringMsg { data: data.into() })
            .expect("publish");
    }
    let b = context(12);
    let mut volatile = b
        .create_node("newcomer", "/")
        .expect("node")
        .create_subscription::<StringMsg>("/history", &Qos::default_profile())
        .expect("subscription");
    let (ours, theirs) = (Graph::of(&a).expect("graph"), Graph::of(&b).expect("graph"));
    assert!(
        theirs.wait_for_match(volatile.gid(), publisher.gid(), 10 * SECOND)
            && ours.wait_for_match(publisher.gid(), volatile.gid(), 10 * SECOND),
        "the reader never matched"
    );
    publisher
        .publish(StringMsg { data: "new".into() })
        .expect("publish");
    assert_eq!(receive_within(&mut volatile, "the new sample").data, "new");
}

/// A client that knows its service only by DDS type names and part hashes (no service type
/// hash, which rmw_zenoh's keys carry) calls a typed server, in CDR bodies.
pub fn a_client_of_dds_type_names_only_reaches_a_server(context: &dyn Fn(u32) -> Context) {
    let a = context(11);
    let _server = adder(&a.create_node("typed", "/").expect("node"), "/parts_add");
    let b = context(11);
    let node = b.create_node("parts", "/").expect("node");
    let ty = ServiceType::compiled("example_interfaces/srv/AddTwoInts").expect("compiled type");
    let (request_hash, response_hash) = ty.part_hashes();
    let mut client = DynamicServiceClient::builder(DynamicServiceType::Parts {
        service_type: ty.name().to_owned(),
        request: DynamicPart {
            dds_type_name: "example_interfaces::srv::dds_::AddTwoInts_Request_".to_owned(),
            type_hash: request_hash,
        },
        response: DynamicPart {
            dds_type_name: "example_interfaces::srv::dds_::AddTwoInts_Response_".to_owned(),
            type_hash: response_hash,
        },
    })
    .name("/parts_add")
    .node(&node)
    .build()
    .expect("client");
    let graph = Graph::of(&b).expect("graph");
    assert!(graph.wait_for_service("/parts_add", 10 * SECOND));
    // {a: 2, b: 40} as CDR_LE: two int64.
    let mut request = 2i64.to_le_bytes().to_vec();
    request.extend_from_slice(&40i64.to_le_bytes());
    let response = client
        .call(request, 10 * SECOND)
        .expect("the server's answer");
    assert!(!response.big_endian);
    assert_eq!(response.body, 42i64.to_le_bytes());
}
