//! The backend contract is complete, and a backend outside horus-ros' own list plugs in with no
//! change to any other crate: contexts on the in-memory test backend (no middleware at all) pass
//! the conformance suite (`horus-ros-rmw-conformance`, which every built-in backend passes too).
//! Each test has its own domain (its own in-memory bus).

use horus_ros_graph::Graph;
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Context;
use horus_ros_rmw_conformance::{conformance_tests, SECOND};
use horus_ros_rmw_memory as memory;

/// A context on the in-memory backend in `domain`.
fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .implementation(memory::implementation())
        .build()
        .expect("context")
}

conformance_tests!(context);

/// DDS-shaped GIDs: an endpoint's participant is found from its GID's prefix.
#[test]
fn an_endpoints_participant_is_found_from_its_gid() {
    let a = context(9);
    let publisher = a
        .create_node("talker", "/")
        .expect("node")
        .create_publisher::<StringMsg>("chatter", &Qos::default_profile())
        .expect("publisher");
    let graph = Graph::of(&context(9)).expect("graph");
    assert!(graph.wait_until(10 * SECOND, |c| c.count_publishers("/chatter") == 1));
    assert_eq!(
        graph.participant_vendor(publisher.gid()),
        Some(memory::VENDOR)
    );
}

/// DDS's request/offered rule: a RELIABLE reader does not match a BEST_EFFORT writer; the
/// reverse matches.
#[test]
fn a_reliable_reader_does_not_match_a_best_effort_writer() {
    let a = context(10);
    let n = a.create_node("lossy", "/").expect("node");
    let lossy = n
        .create_publisher::<StringMsg>("lossy", &Qos::default_profile().best_effort())
        .expect("publisher");
    let b = context(10);
    let peer = b.create_node("peer", "/").expect("node");
    let strict = peer
        .create_subscription::<StringMsg>("/lossy", &Qos::default_profile())
        .expect("subscription");
    let lenient = peer
        .create_subscription::<StringMsg>("/lossy", &Qos::sensor_data())
        .expect("subscription");
    let graph = Graph::of(&b).expect("graph");
    assert!(graph.wait_for_match(lenient.gid(), lossy.gid(), 10 * SECOND));
    assert!(!graph.is_matched(strict.gid(), lossy.gid()));
}

/// A watcher that holds the graph and lets it go when told of a change, then says so.
struct LetsGo {
    graph: std::sync::Mutex<Option<std::sync::Arc<Graph>>>,
    done: std::sync::Mutex<std::sync::mpsc::Sender<()>>,
}

impl horus_ros_graph::GraphWatcher for LetsGo {
    fn graph_changed(&self, _: &horus_ros_graph::GraphView<'_>) {
        let graph = self.graph.lock().map(|mut g| g.take()).unwrap_or_default();
        drop(graph);
        let _ = self.done.lock().map(|done| done.send(()));
    }
}

/// The graph's last handle let go on the graph's own thread (by a watcher, as a server's does
/// through its peers): the graph ends without joining its own thread (which panicked there).
#[test]
fn the_graphs_last_handle_can_go_on_its_own_thread() {
    let c = context(10);
    let graph = Graph::of(&c).expect("graph");
    let (done, finished) = std::sync::mpsc::channel();
    let watcher = std::sync::Arc::new(LetsGo {
        graph: std::sync::Mutex::new(Some(graph.clone())),
        done: std::sync::Mutex::new(done),
    });
    let weak: std::sync::Weak<dyn horus_ros_graph::GraphWatcher> =
        std::sync::Arc::downgrade(&watcher) as _;
    graph.watch(weak);
    drop(graph);
    // A change: the graph's thread tells the watcher, which drops the last handle there.
    let _node = c.create_node("changes", "/").expect("node");
    assert_eq!(
        finished.recv_timeout(10 * SECOND),
        Ok(()),
        "the watcher never returned from dropping the graph"
    );
}
