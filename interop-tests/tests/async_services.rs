//! The `tokio` feature against real ROS 2 Jazzy nodes: our awaited client
//! (`AsyncServiceClient::call`) calls an rclpy server, and an rclpy client calls our async server
//! (`AsyncServiceServer::builder`), on the run's RMW: rmw_fastrtps_cpp (rmw_fastrtps
//! convention), in the `*+rmw_cyclonedds_cpp` runs rmw_cyclonedds_cpp (its request header), or in
//! the Zenoh run rmw_zenoh_cpp (queries with the request id in their attachment).
//! As in `jazzy_services.rs`, on the Cyclone backend the rmw_fastrtps convention cannot be
//! spoken: with rmw_fastrtps peers there the awaited call is refused at once with `Transport`,
//! and the rclpy client gets no answer.

use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolRequest, SetBoolResponse};
use horus_ros_services::prelude::*;
use horus_ros_services::AsyncServiceServer;
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::{request_ids, RclpyPeer};
use serde_json::json;
use tokio::task::JoinSet;

const SECOND: Duration = Duration::from_secs(1);
/// Calls each rclpy test makes.
const CALLS: usize = 5;

fn node(domain: u32, name: &str) -> (Context, Node) {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node(name, "/").expect("node");
    (context, node)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn our_awaited_calls_reach_an_rclpy_server() {
    const DOMAIN: u32 = 222;
    const SERVICE: &str = "/rclpy_async/set";
    let (context, node) = node(DOMAIN, "horus_async_caller");
    let rmw = Rmw::of_peers();
    let refusing = !context.capabilities().carries_sample_identity && rmw.needs_sample_identity();
    let mut peer = tokio::task::spawn_blocking(move || {
        let mut peer = RclpyPeer::start(&json!({
            "domain": DOMAIN, "namespace": "/rclpy_async", "name": "rclpy_server",
            "servers": [{"service": SERVICE, "type": "std_srvs/srv/SetBool",
                         "introspection": true}],
        }))
        .expect("start the rclpy peer");
        peer.ready(20 * SECOND).expect("the rclpy node is up");
        peer
    })
    .await
    .expect("join");
    let client = Arc::new(
        AsyncServiceClient::<SetBool>::builder()
            .node(&node)
            .name(SERVICE)
            .build()
            .expect("client"),
    );
    let gids = client.gids();
    if refusing {
        // Once the server is on the graph, the awaited call fails at once, naming why.
        let graph = horus_ros_graph::Graph::of(&context).expect("graph");
        let seen =
            tokio::task::spawn_blocking(move || graph.wait_for_service(SERVICE, 20 * SECOND));
        assert!(
            seen.await.expect("join"),
            "the rclpy server never showed up"
        );
        let asked = Instant::now();
        match client.call(SetBoolRequest { data: true }, 5 * SECOND).await {
            Err(ServiceError::Transport(cause @ TransportError::NoUsableServer { .. })) => {
                let m = cause.to_string();
                assert!(m.contains("rmw_fastrtps") && m.contains("rustdds"), "{m}")
            }
            other => panic!("expected a Transport refusal, got {other:?}"),
        }
        assert!(
            asked.elapsed() < 2 * SECOND,
            "refused after {:?}",
            asked.elapsed()
        );
        assert!(!client.wait_for_service_async(SECOND).await);
        assert_eq!(client.pending_requests(), 0);
        return;
    }
    assert!(
        client.wait_for_service_async(20 * SECOND).await,
        "the rclpy server never became usable; {}",
        peer.output()
    );
    // All in flight at once.
    let mut calls = JoinSet::new();
    for i in 0..CALLS {
        let client = Arc::clone(&client);
        calls.spawn(async move {
            let data = i % 2 == 0;
            (
                data,
                client.call(SetBoolRequest { data }, 10 * SECOND).await,
            )
        });
    }
    while let Some(joined) = calls.join_next().await {
        let (data, reply) = joined.expect("task");
        assert_eq!(
            reply.map(|r| (r.success, r.message)),
            Ok((
                data,
                format!("set to {}", if data { "True" } else { "False" })
            )),
            "{}",
            peer.output()
        );
    }
    assert_eq!(client.pending_requests(), 0);
    // The peer's RMW took each request with the request id that names our client, and the
    // sequence numbers of our CALLS requests (see `peers::request_ids`).
    let events = tokio::task::spawn_blocking(move || {
        peer.wait_for(
            20 * SECOND,
            "the server's REQUEST_RECEIVED events",
            |lines| {
                let got: Vec<serde_json::Value> = lines
                    .iter()
                    .filter_map(|l| l.get("event"))
                    .filter(|e| e["event_type"] == 1)
                    .cloned()
                    .collect();
                (got.len() == CALLS).then_some(got)
            },
        )
    })
    .await
    .expect("join")
    .unwrap_or_else(|e| panic!("{e}"));
    let mut sequence_numbers: Vec<i64> = events
        .iter()
        .map(|e| {
            assert!(
                e["client_gid"]
                    .as_str()
                    .is_some_and(|gid| request_ids::names_our_client(rmw, gids, gid)),
                "{e}: not our client {gids:?} as {} names it",
                rmw.name()
            );
            e["sequence_number"].as_i64().unwrap_or_default()
        })
        .collect();
    // In flight at once: taken in any order. No other client of this process calls, so on
    // rmw_cyclonedds (numbers of the whole process) they are consecutive too.
    sequence_numbers.sort_unstable();
    assert!(
        request_ids::sequence_numbers_are_ours(rmw, &sequence_numbers, true),
        "{sequence_numbers:?} are not the numbers of our {CALLS} requests on {}",
        rmw.name()
    );
    assert_eq!(sequence_numbers.len(), CALLS);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_rclpy_client_calls_our_async_server() {
    const DOMAIN: u32 = 223;
    const SERVICE: &str = "/horus_async/set";
    let (context, node) = node(DOMAIN, "horus_async_server");
    let refusing =
        !context.capabilities().carries_sample_identity && Rmw::of_peers().needs_sample_identity();
    let server = AsyncServiceServer::<SetBool>::builder()
        .node(&node)
        .name(SERVICE)
        .on_request(|r| async move {
            tokio::task::yield_now().await;
            Ok(SetBoolResponse {
                success: !r.data,
                message: format!("async {}", r.data),
            })
        })
        .build()
        .expect("async server");
    let (code, replies, output) = tokio::task::spawn_blocking(move || {
        let calls: Vec<serde_json::Value> =
            (0..CALLS).map(|i| json!({"data": i % 2 == 0})).collect();
        let mut peer = RclpyPeer::start(&json!({
            "domain": DOMAIN, "namespace": "/rclpy_async", "name": "rclpy_client",
            "clients": [{"service": SERVICE, "type": "std_srvs/srv/SetBool", "wait_s": 20,
                         "timeout_s": if refusing { 1.0 } else { 10.0 }, "calls": calls}],
            "leave_when_done": true,
        }))
        .expect("start the rclpy peer");
        let code = peer.wait_exit(60 * SECOND).expect("the peer's exit");
        let replies: Vec<serde_json::Value> = peer.all("reply").into_iter().cloned().collect();
        (code, replies, peer.output())
    })
    .await
    .expect("join");
    if refusing {
        assert_eq!(
            code,
            Some(1),
            "the rclpy client must get no reply: {output}"
        );
        assert!(replies.is_empty(), "{output}");
        assert_eq!(server.served_count(), 0);
        return;
    }
    assert_eq!(code, Some(0), "the rclpy client failed: {output}");
    assert_eq!(replies.len(), CALLS, "{output}");
    for (i, reply) in replies.iter().enumerate() {
        let data = i % 2 == 0;
        assert_eq!(
            reply["response"],
            json!({"success": !data, "message": format!("async {data}")}),
            "{output}"
        );
    }
    assert_eq!(server.served_count(), CALLS as u64);
    assert_eq!(server.failed_count(), 0);
}
