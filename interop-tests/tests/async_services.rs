//! The `tokio` feature against independent peers: our awaited client
//! (`AsyncServiceClient::call`) calls a Cyclone DDS server (rmw_cyclonedds convention) and a Fast
//! DDS 2.9 server (rmw_fastrtps convention); their clients call our async server
//! (`ServiceServerBuilder::on_request_async`). As in `cyclone_services.rs` and
//! `fastdds_services.rs`, on the Cyclone backend the rmw_fastrtps convention cannot be spoken:
//! there the awaited call is refused at once with `Transport`, and the Fast DDS client gets no
//! answer.

use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_services::prelude::*;
use horus_ros_services::AsyncServiceServer;
use interop_tests::fastdds::{FastDdsPeer, Served};
use interop_tests::{cyclone_config, peer_script, python, Peer};
use serde_json::Value;
use tokio::task::JoinSet;

const SECOND: Duration = Duration::from_secs(1);

fn node(domain: u32, name: &str) -> (Context, Node) {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node(name, "/").expect("node");
    (context, node)
}

fn lines(stdout: &str) -> Vec<Value> {
    stdout
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect()
}

/// An async AddTwoInts server that yields to the runtime before each answer.
fn async_adder(node: &Node, service: &str) -> AsyncServiceServer<AddTwoInts> {
    ServiceServerBuilder::<AddTwoInts>::new()
        .node(node)
        .name(service)
        .on_request_async(|r| async move {
            tokio::task::yield_now().await;
            Ok(AddTwoIntsResponse { sum: r.a + r.b })
        })
        .build()
        .expect("async server")
}

fn async_client(node: &Node, service: &str) -> Arc<AsyncServiceClient<AddTwoInts>> {
    Arc::new(
        AsyncServiceClient::<AddTwoInts>::builder()
            .node(node)
            .name(service)
            .build_async()
            .expect("client"),
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn our_awaited_calls_reach_a_cyclone_server() {
    const DOMAIN: u32 = 220;
    const CALLS: i64 = 6;
    let (_context, node) = node(DOMAIN, "horus_async_caller");
    let server = Peer::start(
        "cyclone_add_two_ints_server.py",
        &[DOMAIN.to_string(), "/async_add".into(), CALLS.to_string()],
    )
    .expect("start the Cyclone DDS server peer");
    let client = async_client(&node, "/async_add");
    assert!(
        client.wait_for_service_async(20 * SECOND).await,
        "the Cyclone server never became ready"
    );
    // All in flight at once, from one join set.
    let mut calls = JoinSet::new();
    for i in 1..=CALLS {
        let client = Arc::clone(&client);
        calls.spawn(async move {
            (
                i,
                client
                    .call(AddTwoIntsRequest { a: i, b: 100 * i }, 10 * SECOND)
                    .await,
            )
        });
    }
    let mut replies = Vec::new();
    while let Some(joined) = calls.join_next().await {
        replies.push(joined.expect("task"));
    }
    assert_eq!(client.pending_requests(), 0);
    drop(client);
    let out = tokio::task::spawn_blocking(move || server.wait(20 * SECOND))
        .await
        .expect("join")
        .expect("server output");
    assert_eq!(
        out.code,
        Some(0),
        "server failed: {} {}",
        out.stdout,
        out.stderr
    );
    for (i, reply) in replies {
        assert_eq!(
            reply,
            Ok(AddTwoIntsResponse { sum: 101 * i }),
            "server said: {}",
            out.stdout
        );
    }
    let served: Vec<Value> = lines(&out.stdout)
        .into_iter()
        .filter(|l| l.get("seq").is_some())
        .collect();
    assert_eq!(served.len() as i64, CALLS, "{}", out.stdout);
    // rmw_cyclonedds' header: one client id, every reply sent.
    assert!(
        served
            .iter()
            .all(|l| l["guid"] == served[0]["guid"] && l["reply"] == "sent"),
        "{served:?}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_cyclone_client_calls_our_async_server() {
    const DOMAIN: u32 = 221;
    const COUNT: u64 = 5;
    let (_context, node) = node(DOMAIN, "horus_async_adder");
    let server = async_adder(&node, "/async_add");
    let output = tokio::task::spawn_blocking(|| {
        Command::new(python())
            .arg(peer_script("cyclone_add_two_ints_client.py"))
            .args([
                DOMAIN.to_string(),
                "/async_add".into(),
                COUNT.to_string(),
                "20".into(),
            ])
            .env("CYCLONEDDS_URI", cyclone_config())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .output()
    })
    .await
    .expect("join")
    .expect("run the Cyclone DDS client peer");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "client failed: {stdout} {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let calls: Vec<Value> = lines(&stdout)
        .into_iter()
        .filter(|l| l.get("sum").is_some())
        .collect();
    assert_eq!(calls.len() as u64, COUNT, "{stdout}");
    for c in &calls {
        assert_eq!(
            c["sum"].as_i64(),
            Some(c["a"].as_i64().unwrap_or(0) + c["b"].as_i64().unwrap_or(0)),
            "{c}"
        );
    }
    assert_eq!(server.served_count(), COUNT);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn our_awaited_calls_reach_a_fastdds_server() {
    const DOMAIN: u32 = 222;
    const SERVICE: &str = "/fast_async/add_two_ints";
    const CALLS: i64 = 5;
    let (context, node) = node(DOMAIN, "horus_async_caller");
    let refusing = !context.backend().carries_sample_identity();
    let mut peer = tokio::task::spawn_blocking(move || {
        let mut peer = FastDdsPeer::start(
            DOMAIN,
            "/fast_async",
            "fast_server",
            SERVICE,
            Duration::from_secs(if refusing { 8 } else { 15 }),
        )
        .expect("build and start the Fast DDS peer");
        peer.created(10 * SECOND)
            .expect("the peer says what it created");
        peer
    })
    .await
    .expect("join");
    let client = async_client(&node, SERVICE);
    let (request_writer, reply_reader) = client.gids();
    if refusing {
        // Once the server is on the graph, the awaited call fails at once, naming why.
        let graph = horus_ros_graph::Graph::shared(&context).expect("graph");
        let seen =
            tokio::task::spawn_blocking(move || graph.wait_for_service(SERVICE, 10 * SECOND));
        assert!(
            seen.await.expect("join"),
            "the Fast DDS server never showed up"
        );
        let asked = Instant::now();
        match client
            .call(AddTwoIntsRequest { a: 1, b: 1 }, 5 * SECOND)
            .await
        {
            Err(ServiceError::Transport(m)) => {
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
        client.wait_for_service_async(10 * SECOND).await,
        "the Fast DDS server never became usable; peer output:\n{}",
        peer.output()
    );
    let mut calls = JoinSet::new();
    for i in 1..=CALLS {
        let client = Arc::clone(&client);
        calls.spawn(async move {
            (
                i,
                client
                    .call(
                        AddTwoIntsRequest {
                            a: i,
                            b: 100 * i + 7,
                        },
                        10 * SECOND,
                    )
                    .await,
            )
        });
    }
    while let Some(joined) = calls.join_next().await {
        let (i, reply) = joined.expect("task");
        assert_eq!(
            reply,
            Ok(AddTwoIntsResponse { sum: 101 * i + 7 }),
            "peer output:\n{}",
            peer.output()
        );
    }
    assert_eq!(client.pending_requests(), 0);
    // The peer saw rmw_fastrtps requests, answered once our reply reader was matched.
    let served = tokio::task::spawn_blocking(move || {
        let mut served = Vec::new();
        let deadline = Instant::now() + 5 * SECOND;
        while served.len() < CALLS as usize && Instant::now() < deadline {
            if let Some(line) = peer.next_line(Duration::from_millis(100)) {
                if let Some(s) = Served::parse(&line) {
                    served.push(s);
                }
            }
        }
        (served, peer.output())
    })
    .await
    .expect("join");
    let (served, output) = served;
    assert_eq!(served.len(), CALLS as usize, "peer output:\n{output}");
    for s in &served {
        assert_eq!(s.sum, s.a + s.b, "{s:?}");
        // rmw_fastrtps' request id names our reply reader (related_sample_identity).
        assert_eq!(s.sample_writer, request_writer.to_string(), "{s:?}");
        assert_eq!(s.related_guid, reply_reader.to_string(), "{s:?}");
        assert_eq!(s.request_id_guid, reply_reader.to_string(), "{s:?}");
        assert_eq!(s.client_present, "YES", "{s:?}");
        assert!(s.sent, "{s:?}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fastdds_client_calls_our_async_server() {
    const DOMAIN: u32 = 223;
    const SERVICE: &str = "/horus_async/add_two_ints";
    const CALLS: u32 = 5;
    let (context, node) = node(DOMAIN, "horus_async_server");
    let refusing = !context.backend().carries_sample_identity();
    let server = async_adder(&node, SERVICE);
    let (code, lines, output) = tokio::task::spawn_blocking(move || {
        let mut peer = FastDdsPeer::start_calling(
            DOMAIN,
            "/fast_async",
            "fast_client",
            SERVICE,
            Duration::from_secs(if refusing { 6 } else { 12 }),
            CALLS,
        )
        .expect("build and start the Fast DDS peer");
        peer.created(10 * SECOND)
            .expect("the peer says what it created");
        let (code, lines) = peer.finish(15 * SECOND).expect("wait for the peer");
        (code, lines, peer.output())
    })
    .await
    .expect("join");
    let parsed: Vec<Value> = lines
        .iter()
        .map(|l| serde_json::from_str(l).unwrap_or(Value::Null))
        .collect();
    let replies: Vec<&Value> = parsed.iter().filter(|v| v.get("sum").is_some()).collect();
    if refusing {
        assert_eq!(
            code,
            Some(1),
            "the Fast DDS client must get no reply; output:\n{output}"
        );
        assert!(replies.is_empty(), "output:\n{output}");
        assert_eq!(server.served_count(), 0);
        return;
    }
    assert_eq!(
        code,
        Some(0),
        "the Fast DDS client failed; output:\n{output}"
    );
    assert_eq!(replies.len(), CALLS as usize, "output:\n{output}");
    for (k, reply) in replies.iter().enumerate() {
        let i = k as i64 + 1;
        assert_eq!(reply["sum"], 11 * i, "output:\n{output}");
        // Our reply's related_sample_identity carried the request's sequence number back.
        assert_eq!(reply["sequence_number"], i, "output:\n{output}");
    }
    assert_eq!(server.served_count(), u64::from(CALLS));
    assert_eq!(server.failed_count(), 0);
}
