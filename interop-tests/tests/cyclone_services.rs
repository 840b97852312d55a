//! Services against a Cyclone DDS peer that follows rmw_cyclonedds_cpp to the byte (16-byte
//! request header in the payload): our client calls its server, its client calls our server. The
//! wire convention is chosen from the peer's vendor id, with no configuration.

use std::process::{Command, Stdio};
use std::time::Duration;

use horus_ros_services::prelude::*;
use interop_tests::{cyclone_config, peer_script, python, Peer};
use serde_json::Value;

fn lines(stdout: &str) -> Vec<Value> {
    stdout
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect()
}

#[test]
fn our_client_calls_a_cyclone_server() {
    const DOMAIN: u32 = 72;
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("horus_caller", "/").expect("node");
    let server = Peer::start(
        "cyclone_add_two_ints_server.py",
        &[DOMAIN.to_string(), "/add_two_ints".into(), "6".into()],
    )
    .expect("start the Cyclone DDS server peer");
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/add_two_ints")
        .build()
        .expect("client");
    assert!(
        client.wait_for_service(Duration::from_secs(20)),
        "the Cyclone server never became ready"
    );
    let replies: Vec<_> = (1..=5)
        .map(|i| {
            client.call(
                AddTwoIntsRequest { a: i, b: 100 * i },
                Duration::from_secs(5),
            )
        })
        .collect();
    drop(client);
    let out = server.wait(Duration::from_secs(20)).expect("server output");
    assert_eq!(
        out.code,
        Some(0),
        "server failed: {} {}",
        out.stdout,
        out.stderr
    );
    let expected: Vec<_> = (1..=5)
        .map(|i| Ok(AddTwoIntsResponse { sum: 101 * i }))
        .collect();
    assert_eq!(replies, expected, "server said: {}", out.stdout);
    let served: Vec<Value> = lines(&out.stdout)
        .into_iter()
        .filter(|l| l.get("seq").is_some())
        .collect();
    assert_eq!(served.len(), 5, "{}", out.stdout);
    // One client id in every header, increasing sequence numbers, every reply sent.
    assert!(
        served
            .iter()
            .all(|l| l["guid"] == served[0]["guid"] && l["reply"] == "sent"),
        "{served:?}"
    );
    let seqs: Vec<i64> = served.iter().filter_map(|l| l["seq"].as_i64()).collect();
    assert!(seqs.windows(2).all(|w| w[0] < w[1]), "{seqs:?}");
}

#[test]
fn a_cyclone_client_calls_our_server() {
    const DOMAIN: u32 = 73;
    const COUNT: u64 = 5;
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("horus_adder", "/").expect("node");
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name("/add_two_ints")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let output = Command::new(python())
        .arg(peer_script("cyclone_add_two_ints_client.py"))
        .args([
            DOMAIN.to_string(),
            "/add_two_ints".into(),
            COUNT.to_string(),
            "20".into(),
        ])
        .env("CYCLONEDDS_URI", cyclone_config())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output()
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
