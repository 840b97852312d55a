//! The conformance suite on the Zenoh backend: contexts of this process joined by a Zenoh router
//! the test starts on a port of its own (rmw_zenoh's router configuration), each context's
//! session configured through `horus_ros_rmw::zenoh::implementation` (rmw_zenoh's session
//! configuration, connecting to that router). Run inside `scripts/isolated`.

use std::sync::OnceLock;

use horus_ros_graph::Graph;
use horus_ros_msgs::std_msgs::msg::String as StringMsg;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::Context;
use horus_ros_rmw_conformance::{conformance_tests, SECOND};
use zenoh::Wait;

/// The router's port (no other test uses it).
const PORT: u16 = 17571;

/// The router, started by the first test that needs it and kept for the process.
fn router() -> &'static zenoh::Session {
    static ROUTER: OnceLock<zenoh::Session> = OnceLock::new();
    ROUTER.get_or_init(|| {
        let get = |k: &str| {
            (k == config::CONFIG_OVERRIDE_ENV)
                .then(|| format!(r#"listen/endpoints=["tcp/127.0.0.1:{PORT}"]"#))
        };
        zenoh::open(config::config(ConfigKind::Router, get).expect("router config"))
            .wait()
            .expect("router")
    })
}

/// A context on the Zenoh backend in `domain`, joined to the router.
fn context(domain: u32) -> Context {
    router();
    let get = |k: &str| {
        (k == config::CONFIG_OVERRIDE_ENV).then(|| {
            format!(
                r#"connect/endpoints=["tcp/127.0.0.1:{PORT}"];listen/endpoints=["tcp/127.0.0.1:0"]"#
            )
        })
    };
    let session = config::config(ConfigKind::Session, get).expect("session config");
    Context::builder()
        .domain_id(domain)
        .implementation(horus_ros_rmw::zenoh::implementation(session))
        .build()
        .expect("context")
}

conformance_tests!(context);

/// Zenoh has no request/offered QoS matching (rmw_zenoh's graph matches every subscription on a
/// publisher's key): a RELIABLE subscription matches a BEST_EFFORT publisher and gets its
/// samples.
#[test]
fn a_reliable_subscription_matches_a_best_effort_publisher() {
    let a = context(10);
    let n = a.create_node("lossy", "/").expect("node");
    let lossy = n
        .create_publisher::<StringMsg>("lossy", &Qos::default_profile().best_effort())
        .expect("publisher");
    let b = context(10);
    let peer = b.create_node("peer", "/").expect("node");
    let mut strict = peer
        .create_subscription::<StringMsg>("/lossy", &Qos::default_profile())
        .expect("subscription");
    let graph = Graph::of(&a).expect("graph");
    assert!(graph.wait_for_match(lossy.gid(), strict.gid(), 10 * SECOND));
    lossy
        .publish(StringMsg {
            data: "delivered".into(),
        })
        .expect("publish");
    assert!(strict.wait(10 * SECOND), "nothing came");
    assert_eq!(
        strict.try_take().expect("take").map(|m| m.data),
        Some("delivered".into())
    );
}
