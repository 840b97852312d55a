//! `horus-ros service echo` against our own servers and clients with introspection on, and against
//! real rmw_cyclonedds_cpp nodes (rclpy 7.1.6 on rmw_cyclonedds_cpp 2.2.2, whatever the run's
//! peers use: `interop-tests/peers/jazzy_node.py`): one that decodes our events with rclpy's
//! own `AddTwoInts.Event`, and one that publishes fixed events, which the echo prints as
//! `ros2 service echo` does.
//!
//! Run inside the private network namespace (`scripts/isolated`), on each backend
//! (`HORUS_ROS_BACKEND`).

mod common;

use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use common::Streaming;
use horus_ros_graph::Graph;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Context, Gid};
use horus_ros_services::prelude::*;
use horus_ros_services::IntrospectionState;
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::RclpyPeer;
use serde_json::{json, Value};

const WAIT: Duration = Duration::from_secs(15);

/// A running `horus-ros service echo`, its stdout lines on a channel.
struct Echo(Streaming);

impl Echo {
    fn start(domain: u32, args: &[&str]) -> Self {
        let process = Streaming::spawn(
            Command::new(env!("CARGO_BIN_EXE_horus-ros"))
                .arg("--domain-id")
                .arg(domain.to_string())
                .arg("service")
                .arg("echo")
                .args(args)
                .env_remove("ROS_DOMAIN_ID")
                .env("RUST_LOG", "error")
                .stderr(Stdio::inherit()),
        )
        .expect("start horus-ros service echo");
        Self(process)
    }

    /// The next line, within `WAIT`.
    fn line(&self) -> String {
        self.0.line(WAIT)
    }

    /// Everything up to the end of output (the process exits after `--count` events).
    fn rest(&mut self) -> String {
        self.0.rest(WAIT)
    }
}

fn no_publishers(service: &str) -> String {
    format!(
        "No publishers on topic '{service}/_service_event'; is service introspection on the client \
         or server enabled?"
    )
}

/// Waits until `writer` (ours) is matched with some reader of the DDS topic `dds_topic`.
fn wait_for_a_reader(graph: &Arc<Graph>, writer: Gid, dds_topic: &str) {
    let deadline = Instant::now() + WAIT;
    loop {
        // Looked at after reading the generation: a match made meanwhile is not missed.
        let seen = graph.generation();
        let readers = graph.read(|c| c.subscriptions_info_by_topic(dds_topic, true));
        if readers
            .iter()
            .any(|r| graph.is_matched(writer, r.endpoint_gid))
        {
            return;
        }
        let now = Instant::now();
        assert!(now < deadline, "no reader matched {writer} on {dds_topic}");
        graph.wait_for_graph_change_since(seen, deadline - now);
    }
}

/// The YAML lines `client_gid` takes in block style.
fn gid_lines(gid: Gid) -> String {
    gid.as_bytes()
        .iter()
        .map(|b| format!("  - {b}\n"))
        .collect()
}

/// One event as ros2 service echo prints it, stamps written as `sec: S` / `nanosec: N`.
fn expected(
    kind: &str,
    gid: Gid,
    seq: i64,
    request: Option<(i64, i64)>,
    response: Option<i64>,
) -> String {
    let request = request.map_or("request: []\n".to_owned(), |(a, b)| {
        format!("request:\n- a: {a}\n  b: {b}\n")
    });
    let response = response.map_or("response: []\n".to_owned(), |s| {
        format!("response:\n- sum: {s}\n")
    });
    format!(
        "info:\n  event_type: {kind}\n  stamp:\n    sec: S\n    nanosec: N\n  client_gid:\n{}  \
         sequence_number: {seq}\n{request}{response}---\n",
        gid_lines(gid)
    )
}

/// Splits echo output into events, stamps masked, sorted (the server's and client's writers are
/// independent, so their events interleave in any order).
fn events(out: &str) -> Vec<String> {
    let mut events: Vec<String> = out
        .split_inclusive("---\n")
        .map(|e| {
            e.lines()
                .map(|l| {
                    if let Some(rest) = l.strip_prefix("    sec: ") {
                        assert!(rest.parse::<i32>().is_ok(), "{l}");
                        "    sec: S".to_owned()
                    } else if let Some(rest) = l.strip_prefix("    nanosec: ") {
                        assert!(rest.parse::<u32>().is_ok(), "{l}");
                        "    nanosec: N".to_owned()
                    } else {
                        l.to_owned()
                    }
                })
                .map(|l| l + "\n")
                .collect()
        })
        .collect();
    events.sort();
    events
}

struct Pair {
    graph: Arc<Graph>,
    server: ServiceServer<AddTwoInts>,
    client: ServiceClient<AddTwoInts>,
    _context: Context,
}

fn pair(domain: u32, service: &str, state: IntrospectionState) -> Pair {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node("introspected", "/").expect("node");
    let graph = Graph::of(&context).expect("graph");
    let qos = Qos::services_default();
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name(service)
        .introspection(state, qos)
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name(service)
        .introspection(state, qos)
        .build()
        .expect("client");
    Pair {
        graph,
        server,
        client,
        _context: context,
    }
}

impl Pair {
    /// Both event writers matched with a reader of the event topic.
    fn wait_for_echo(&self, service: &str) {
        let topic = format!("rt{service}/_service_event");
        for w in [
            self.server.introspection_gid(),
            self.client.introspection_gid(),
        ] {
            wait_for_a_reader(&self.graph, w.expect("event writer"), &topic);
        }
    }

    /// The `client_gid` the server's events carry, as the client's RMW convention makes it.
    fn server_side_gid(&self) -> Gid {
        let (request_writer, reply_reader) = self.client.gids();
        if self._context.capabilities().carries_sample_identity {
            // rmw_fastrtps: the related_sample_identity GUID, the client's reply reader.
            reply_reader
        } else {
            // rmw_cyclonedds: the header's client id, then the server's handle of the writer.
            let mut g = [0u8; 16];
            let id = horus_client_id(request_writer);
            g[..8].copy_from_slice(&id.to_le_bytes());
            // The last 8 bytes stay zero: `mask_handle` zeroes them in the output.
            Gid::from_bytes(g)
        }
    }
}

/// A horus-ros client's id in rmw_cyclonedds' header: "HO" over the low 48 bits of the FNV-1a
/// hash of its request writer's GID.
fn horus_client_id(writer: Gid) -> u64 {
    let hash = writer
        .as_bytes()
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
        });
    (0x484f << 48) | (hash & 0xffff_ffff_ffff)
}

/// Masks the last 8 bytes of the server-side GID on a backend without related_sample_identity
/// (Cyclone's local instance handle of the client's writer, known only inside the server).
fn mask_handle(out: &str, server_gid_prefix: &[u8]) -> String {
    let mut result = String::new();
    for event in out.split_inclusive("---\n") {
        let lines: Vec<&str> = event.lines().collect();
        let gid_at = lines.iter().position(|l| *l == "  client_gid:");
        let mut lines: Vec<String> = lines.iter().map(|l| (*l).to_owned()).collect();
        if let Some(at) = gid_at {
            let bytes: Vec<u8> = lines[at + 1..at + 17]
                .iter()
                .filter_map(|l| l.trim_start_matches("  - ").parse().ok())
                .collect();
            if bytes.len() == 16 && bytes[..8] == *server_gid_prefix {
                for l in &mut lines[at + 9..at + 17] {
                    *l = "  - 0".to_owned();
                }
            }
        }
        for l in lines {
            result.push_str(&l);
            result.push('\n');
        }
    }
    result
}

fn run_call(domain: u32, service: &str, state: IntrospectionState, contents: bool) {
    // The service does not exist yet: its type is given (as ros2 service echo needs then).
    let mut echo = Echo::start(
        domain,
        &[service, "example_interfaces/srv/AddTwoInts", "--count", "4"],
    );
    assert_eq!(echo.line(), no_publishers(service));
    let mut p = pair(domain, service, state);
    p.wait_for_echo(service);

    let reply = p
        .client
        .call(AddTwoIntsRequest { a: 2, b: 3 }, WAIT)
        .expect("call");
    assert_eq!(reply.sum, 5);
    let out = echo.rest();
    let server_gid = p.server_side_gid();
    let out = if p._context.capabilities().carries_sample_identity {
        out
    } else {
        mask_handle(&out, &server_gid.as_bytes()[..8])
    };
    let client_gid = p.client.introspection_client_gid();
    if !p._context.capabilities().carries_sample_identity {
        // rmw_cyclonedds' client id: the participant's GUID prefix and a counter.
        assert_eq!(
            client_gid.as_bytes()[..12],
            p.client.gids().0.as_bytes()[..12]
        );
    } else {
        assert_eq!(
            client_gid,
            p.client.gids().0,
            "rmw_fastrtps: the request writer"
        );
    }
    let (req, resp) = if contents {
        (Some((2, 3)), Some(5))
    } else {
        (None, None)
    };
    // rmw_fastrtps numbers by writer sample, rmw_cyclonedds by a process-wide counter (shared by
    // the tests of this binary): the four events carry the same one.
    let seqs: Vec<i64> = out
        .lines()
        .filter_map(|l| l.strip_prefix("  sequence_number: "))
        .filter_map(|n| n.parse().ok())
        .collect();
    assert_eq!(seqs.len(), 4, "{out}");
    assert!(seqs.iter().all(|s| *s == seqs[0]), "{out}");
    let seq = seqs[0];
    let mut want = vec![
        expected("REQUEST_SENT", client_gid, seq, req, None),
        expected("REQUEST_RECEIVED", server_gid, seq, req, None),
        expected("RESPONSE_SENT", server_gid, seq, None, resp),
        expected("RESPONSE_RECEIVED", client_gid, seq, None, resp),
    ];
    want.sort();
    assert_eq!(events(&out), want, "service echo printed:\n{out}");
}

#[test]
fn contents_of_our_server_and_client() {
    run_call(81, "/add_two_ints_c", IntrospectionState::Contents, true);
}

#[test]
fn metadata_leaves_request_and_response_out() {
    run_call(82, "/add_two_ints_m", IntrospectionState::Metadata, false);
}

#[test]
fn off_publishes_nothing_until_turned_on() {
    let service = "/add_two_ints_o";
    let domain = 83;
    // The service does not exist yet: its type is given (as ros2 service echo needs then).
    let mut echo = Echo::start(
        domain,
        &[service, "example_interfaces/srv/AddTwoInts", "--count", "4"],
    );
    assert_eq!(echo.line(), no_publishers(service));
    let mut p = pair(domain, service, IntrospectionState::Off);
    assert_eq!(p.server.introspection_gid(), None);
    assert_eq!(p.client.introspection_gid(), None);
    // Call 1 with introspection off…
    let first = p.client.call(AddTwoIntsRequest { a: 1, b: 1 }, WAIT);
    assert_eq!(first.map(|r| r.sum), Ok(2));
    // …then on: only call 2's events may reach the echo, which stops after four.
    let qos = Qos::services_default();
    p.server
        .configure_introspection(IntrospectionState::Contents, &qos)
        .expect("server on");
    p.client
        .configure_introspection(IntrospectionState::Contents, &qos)
        .expect("client on");
    p.wait_for_echo(service);
    let second = p.client.call(AddTwoIntsRequest { a: 20, b: 22 }, WAIT);
    assert_eq!(second.map(|r| r.sum), Ok(42));
    let out = echo.rest();
    let seqs: Vec<&str> = out
        .lines()
        .filter_map(|l| l.strip_prefix("  sequence_number: "))
        .collect();
    assert_eq!(seqs.len(), 4, "{out}");
    assert!(
        seqs.iter().all(|s| *s == seqs[0]),
        "one call's events:\n{out}"
    );
    assert!(
        !out.contains("- a: 1\n"),
        "no event of the first call:\n{out}"
    );
    assert_eq!(out.matches("- a: 20\n  b: 22\n").count(), 2, "{out}");
    assert_eq!(out.matches("- sum: 42\n").count(), 2, "{out}");
    // OFF again removes the event writers from the graph.
    p.server
        .configure_introspection(IntrospectionState::Off, &qos)
        .expect("server off");
    assert_eq!(p.server.introspection_gid(), None);
}

/// A real rmw_cyclonedds_cpp node that reads the events of `service` (rclpy's own
/// `AddTwoInts.Event`), printing each (`interop-tests/peers/jazzy_node.py`, "event_watches").
fn rclpy_event_reader(domain: u32, service: &str) -> RclpyPeer {
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({
            "domain": domain, "namespace": "/", "name": "event_reader",
            "event_watches": [{"service": service, "type": "example_interfaces/srv/AddTwoInts"}],
        }),
    )
    .expect("start the rclpy peer");
    peer.ready(WAIT).expect("the rclpy node is up");
    peer
}

/// A real rmw_cyclonedds_cpp node that publishes, once a reader has matched it, the four events
/// of one call of AddTwoInts on `service` (a=2, b=3, sum=5, client GID 01.10.ab.cd.…05,
/// sequence number 7, stamps 100.1 … 100.4 s) on its `_service_event` topic, as rclpy's
/// introspection writes them (`interop-tests/peers/jazzy_node.py`, "event_publishers").
fn rclpy_event_publisher(domain: u32, service: &str) -> RclpyPeer {
    let gid = [
        0x01, 0x10, 0xab, 0xcd, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x05,
    ];
    let request = json!([{"a": 2, "b": 3}]);
    let response = json!([{"sum": 5}]);
    let events: Vec<Value> = (0..4u32)
        .map(|kind| {
            json!({
                "event_type": kind, "stamp": [100, 100_000_000 * (kind + 1)],
                "client_gid": gid, "sequence_number": 7,
                "request": if kind < 2 { request.clone() } else { json!([]) },
                "response": if kind < 2 { json!([]) } else { response.clone() },
            })
        })
        .collect();
    let mut peer = RclpyPeer::start_on(
        Rmw::CycloneDds,
        &json!({
            "domain": domain, "namespace": "/", "name": "event_publisher",
            "event_publishers": [{"service": service,
                                  "type": "example_interfaces/srv/AddTwoInts",
                                  "events": events}],
        }),
    )
    .expect("start the rclpy peer");
    peer.ready(WAIT).expect("the rclpy node is up");
    peer
}

#[test]
fn an_rmw_cyclonedds_node_decodes_our_events() {
    let service = "/add_two_ints_p";
    let domain = 84;
    let mut reader = rclpy_event_reader(domain, service);
    let mut p = pair(domain, service, IntrospectionState::Contents);
    p.wait_for_echo(service);
    // …and the rclpy reader has matched both writers too.
    let topic = format!("{service}/_service_event");
    reader
        .wait_for(
            WAIT,
            "both event writers matched by the rclpy reader",
            |lines| {
                lines
                    .iter()
                    .filter_map(|l| l.get("matched"))
                    .any(|m| m["topic"] == topic.as_str() && m["count"].as_u64() >= Some(2))
                    .then_some(())
            },
        )
        .unwrap_or_else(|e| panic!("{e}"));
    // A first call brings both writers' heartbeats (a Cyclone reader learns where a reliable
    // writer's data starts from its first HEARTBEAT, and a rustdds writer may write before its
    // first heartbeat reaches the reader: that first event can then be lost); the second
    // call's events are checked.
    assert_eq!(
        p.client
            .call(AddTwoIntsRequest { a: 1, b: 1 }, WAIT)
            .map(|r| r.sum),
        Ok(2)
    );
    let reply = p.client.call(AddTwoIntsRequest { a: 40, b: 2 }, WAIT);
    assert_eq!(reply.map(|r| r.sum), Ok(42));
    let mut got = second_call_events(&mut reader);
    got.sort_by_key(|v| v["event_type"].as_u64());
    let client_gid = p.client.introspection_client_gid().to_string();
    let server_gid = p.server_side_gid().to_string();
    let types: Vec<u64> = got
        .iter()
        .filter_map(|v| v["event_type"].as_u64())
        .collect();
    assert_eq!(types, [0, 1, 2, 3]);
    assert_eq!(got[0]["client_gid"], client_gid.as_str());
    assert_eq!(got[3]["client_gid"], client_gid.as_str());
    if p._context.capabilities().carries_sample_identity {
        assert_eq!(got[1]["client_gid"], server_gid.as_str());
        assert_eq!(got[2]["client_gid"], server_gid.as_str());
    } else {
        let head = &server_gid[..23];
        assert!(got[1]["client_gid"]
            .as_str()
            .is_some_and(|g| g.starts_with(head)));
    }
    for v in &got {
        assert_eq!(v["sequence_number"], got[0]["sequence_number"]);
        assert!(
            v["stamp"][0].as_i64().is_some_and(|s| s > 1_600_000_000),
            "{v}"
        );
    }
    let (request, response) = (json!([{"a": 40, "b": 2}]), json!([{"sum": 42}]));
    assert_eq!(got[0]["request"], request);
    assert_eq!(got[1]["request"], request);
    assert_eq!(got[2]["response"], response);
    assert_eq!(got[3]["response"], response);
    assert_eq!(got[0]["response"], json!([]));
    assert_eq!(got[2]["request"], json!([]));
    assert_eq!(reader.finish(WAIT), Ok(Some(0)), "{}", reader.output());
}

/// The four events of the call of 40 + 2 the rclpy reader printed, waited for at most [`WAIT`];
/// events of other calls are left out.
fn second_call_events(peer: &mut RclpyPeer) -> Vec<Value> {
    peer.wait_for(WAIT, "the four events of the call of 40 + 2", |lines| {
        let events: Vec<&Value> = lines.iter().filter_map(|l| l.get("event")).collect();
        let ours = |e: &&Value| {
            e["request"] == json!([{"a": 40, "b": 2}]) || e["response"] == json!([{"sum": 42}])
        };
        let sequence = events.iter().copied().find(ours)?["sequence_number"].clone();
        let call: Vec<Value> = events
            .into_iter()
            .filter(|e| e["sequence_number"] == sequence)
            .cloned()
            .collect();
        (call.len() == 4).then_some(call)
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn events_of_an_rclpy_publisher_print_as_ros2_service_echo_does() {
    let service = "/add_two_ints_r";
    let domain = 85;
    let mut echo = Echo::start(
        domain,
        &[service, "example_interfaces/srv/AddTwoInts", "--count", "4"],
    );
    assert_eq!(echo.line(), no_publishers(service));
    let _publisher = rclpy_event_publisher(domain, service);
    let out = echo.rest();
    let gid =
        "  client_gid:\n  - 1\n  - 16\n  - 171\n  - 205\n  - 0\n  - 0\n  - 0\n  - 0\n  - 0\n  \
               - 0\n  - 0\n  - 0\n  - 0\n  - 0\n  - 0\n  - 5\n";
    let event = |kind: &str, nanos: u32, body: &str| {
        format!(
            "info:\n  event_type: {kind}\n  stamp:\n    sec: 100\n    nanosec: {nanos}\n{gid}  \
             sequence_number: 7\n{body}---\n"
        )
    };
    let req = "request:\n- a: 2\n  b: 3\nresponse: []\n";
    let resp = "request: []\nresponse:\n- sum: 5\n";
    let want = [
        event("REQUEST_SENT", 100_000_000, req),
        event("REQUEST_RECEIVED", 200_000_000, req),
        event("RESPONSE_SENT", 300_000_000, resp),
        event("RESPONSE_RECEIVED", 400_000_000, resp),
    ]
    .concat();
    assert_eq!(out, want);
}

#[test]
fn flow_style_csv_and_json() {
    let service = "/add_two_ints_f";
    for (domain, args, want) in [
        (
            86,
            vec!["--flow-style"],
            "info:\n  event_type: REQUEST_SENT\n  stamp:\n    sec: 100\n    nanosec: 100000000\n  \
             client_gid: [1, 16, 171, 205, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5]\n  \
             sequence_number: 7\nrequest: [{a: 2, b: 3}]\nresponse: []\n---\n",
        ),
        (
            88,
            vec!["--csv"],
            "0,100,100000000,1,16,171,205,0,0,0,0,0,0,0,0,0,0,0,5,7,2,3,\n",
        ),
        (
            89,
            vec!["--no-arr"],
            "info:\n  event_type: REQUEST_SENT\n  stamp:\n    sec: 100\n    nanosec: 100000000\n  \
             client_gid: '<array type: uint8[16]>'\n  sequence_number: 7\nrequest: '<sequence \
             type: example_interfaces/srv/AddTwoInts_Request[1], length: 1>'\nresponse: \
             '<sequence type: example_interfaces/srv/AddTwoInts_Response[1], length: 0>'\n---\n",
        ),
        (
            90,
            vec!["-l", "2"],
            "info:\n  event_type: REQUEST_SENT\n  stamp:\n    sec: 100\n    nanosec: 100000000\n  \
             client_gid:\n  - 1\n  - 16\n  - '...'\n  sequence_number: 7\nrequest:\n- a: 2\n  b: \
             3\nresponse: []\n---\n",
        ),
    ] {
        let mut a = vec![service, "example_interfaces/srv/AddTwoInts", "--count", "1"];
        a.extend(args.iter().copied());
        let mut echo = Echo::start(domain, &a);
        assert_eq!(echo.line(), no_publishers(service));
        let _publisher = rclpy_event_publisher(domain, service);
        assert_eq!(echo.rest(), want, "{args:?}");
    }
    let echo = Echo::start(
        87,
        &[
            "--json",
            service,
            "example_interfaces/srv/AddTwoInts",
            "--count",
            "1",
        ],
    );
    assert_eq!(echo.line(), no_publishers(service));
    let _publisher = rclpy_event_publisher(87, service);
    let line: serde_json::Value = serde_json::from_str(&echo.line()).expect("json");
    assert_eq!(
        line,
        serde_json::json!({
            "info": {
                "event_type": "REQUEST_SENT",
                "stamp": {"sec": 100, "nanosec": 100_000_000},
                "client_gid": "01.10.ab.cd.00.00.00.00.00.00.00.00.00.00.00.05",
                "sequence_number": 7
            },
            "request": [{"a": 2, "b": 3}],
            "response": []
        })
    );
}
