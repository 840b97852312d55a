//! `horus-ros service echo --passive` against a real rclpy (Jazzy, rmw_fastrtps_cpp) server and
//! client of `std_srvs/srv/SetBool` with introspection off: the requests and replies, paired,
//! with their values; `--json`; and what an rclpy node's graph API sees meanwhile.
//!
//! Run inside the private network namespace (`scripts/isolated`), on each backend
//! (`HORUS_ROS_BACKEND`): on the rustdds backend the rmw_fastrtps traffic is paired; on the
//! Cyclone backend (Cyclone DDS reports no sample identities) it is printed unpaired, saying why.

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{cli_peer_script, Peer, Streaming};
use serde_json::{json, Value};

const WAIT: Duration = Duration::from_secs(20);
/// rclpy takes a second or two to start.
const RCLPY_START: Duration = Duration::from_secs(20);

/// Whether this run's backend reports sample identities (rustdds does, Cyclone DDS does not).
fn pairs_fast_rtps() -> bool {
    !std::env::var("HORUS_ROS_BACKEND").is_ok_and(|b| b.eq_ignore_ascii_case("cyclone"))
}

/// A running `horus-ros service echo --passive`, its stdout lines on a channel.
struct Echo(Streaming);

impl Echo {
    fn start(domain: u32, global: &[&str], args: &[&str]) -> Self {
        let process = Streaming::spawn(
            Command::new(env!("CARGO_BIN_EXE_horus-ros"))
                .arg("--domain-id")
                .arg(domain.to_string())
                .args(global)
                .args(["service", "echo", "--passive"])
                .args(args)
                .env_remove("ROS_DOMAIN_ID")
                .env("RUST_LOG", "error")
                .stderr(Stdio::inherit()),
        )
        .expect("start horus-ros service echo --passive");
        Self(process)
    }

    /// The lines up to the end of the next record (`---`).
    fn record(&mut self) -> String {
        self.0.until(WAIT, |line| line == "---")
    }

    /// Everything up to the end of output (the process exits after `--count` records).
    fn rest(&mut self) -> String {
        self.0.rest(WAIT)
    }
}

/// An rclpy node that serves `service` and calls it every 0.2 s (introspection off).
fn rclpy_pair(domain: u32, service: &str) -> Peer {
    let d = domain.to_string();
    let args = [d.as_str(), "flipper", service, "60", "--client"];
    Peer::start_path(&cli_peer_script("jazzy_set_bool.py"), &args, RCLPY_START)
}

/// An rclpy node reporting its graph API's view of `service`: at start, each time its graph
/// changes, and on request ([`reports_until_now`]).
fn rclpy_watch(domain: u32, service: &str) -> Peer {
    let d = domain.to_string();
    let args = [d.as_str(), "watcher", service, "60"];
    Peer::start_path(
        &cli_peer_script("jazzy_service_watch.py"),
        &args,
        RCLPY_START,
    )
}

/// The watcher's next report, if one comes by `deadline`.
fn report_by(watch: &mut Peer, deadline: Instant) -> Option<Value> {
    let line = watch.line_by(deadline)?;
    Some(serde_json::from_str(&line).unwrap_or_else(|e| panic!("watcher printed {line:?}: {e}")))
}

/// Waits until the watcher sees the rclpy node's server and client of `/flip` (its reports come
/// as rclpy's graph changes, at most [`WAIT`]); returns that report.
fn settled(watch: &mut Peer) -> Value {
    let deadline = Instant::now() + WAIT;
    let mut last = Value::Null;
    loop {
        let Some(r) = report_by(watch, deadline) else {
            panic!("the rclpy pair was not seen within {WAIT:?}; last report: {last}");
        };
        let pair = json!({"servers": ["/flip"], "clients": ["/flip"]});
        if r["services"] == 1 && r["clients"] == 1 && r["by_node"]["/flipper"] == pair {
            return r;
        }
        last = r;
    }
}

/// Asks the watcher for a report now (tagged `request`) and returns every report it printed
/// since the last one read, up to that answer: the view after each graph change meanwhile, and
/// the view now.
fn reports_until_now(watch: &mut Peer, request: &str) -> Vec<Value> {
    watch.send(request);
    let deadline = Instant::now() + WAIT;
    let mut got = Vec::new();
    loop {
        let r = report_by(watch, deadline)
            .unwrap_or_else(|| panic!("the watcher did not answer {request:?} within {WAIT:?}"));
        let answer = r["request"] == request;
        got.push(r);
        if answer {
            return got;
        }
    }
}

/// Splits YAML output into records (`---` ends each).
fn records(out: &str) -> Vec<String> {
    out.split_inclusive("---\n").map(str::to_owned).collect()
}

/// `field: value` of a YAML record's top level.
fn top<'a>(record: &'a str, field: &str) -> Option<&'a str> {
    record
        .lines()
        .find_map(|l| l.strip_prefix(&format!("{field}: ")))
}

#[test]
fn passive_echo_pairs_an_rclpy_services_calls_without_introspection() {
    let domain = 221;
    let _pair = rclpy_pair(domain, "/flip");
    let mut watch = rclpy_watch(domain, "/flip");
    let before = settled(&mut watch);

    let mut echo = Echo::start(
        domain,
        &[],
        &["/flip", "--count", "15", "--reply-timeout", "1"],
    );
    // What rclpy sees while the echo runs (it runs for three seconds or more: 15 calls at 5/s): its
    // view once the first record is printed (the echo's endpoints are up), and after each graph
    // change until the echo has ended.
    let mut out = echo.record();
    let mut during = reports_until_now(&mut watch, "echo running");
    out.push_str(&echo.rest());
    during.extend(reports_until_now(&mut watch, "echo ended"));
    let recs = records(&out);
    assert_eq!(recs.len(), 15, "15 records:\n{out}");

    if pairs_fast_rtps() {
        let paired: Vec<&String> = recs
            .iter()
            .filter(|r| top(r, "status") == Some("paired"))
            .collect();
        // The server's reply writer sends only to the readers it has matched when it writes
        // (VOLATILE): until it has matched ours (its discovery of our reader, which we cannot
        // observe), replies pass us by. So the first calls may go unpaired, and from the first
        // paired one on every call is paired.
        let first = recs
            .iter()
            .position(|r| top(r, "status") == Some("paired"))
            .unwrap_or_else(|| panic!("no call paired:\n{out}"));
        assert!(
            recs[first..]
                .iter()
                .all(|r| top(r, "status") == Some("paired")),
            "every call paired once the first was:\n{out}"
        );
        assert!(paired.len() >= 4, "most calls paired:\n{out}");
        let mut seqs = Vec::new();
        for r in &paired {
            assert_eq!(top(r, "convention"), Some("rmw_fastrtps"), "{r}");
            let data = r
                .lines()
                .skip_while(|l| *l != "request:")
                .nth(1)
                .and_then(|l| l.strip_prefix("  data: "))
                .unwrap_or_else(|| panic!("no request data in\n{r}"));
            let want = format!(
                "response:\n  success: {data}\n  message: {}\n",
                if data == "true" { "set" } else { "unset" }
            );
            assert!(r.contains(&want), "the reply of data {data}:\n{r}");
            let latency: f64 = top(r, "latency")
                .and_then(|l| l.parse().ok())
                .unwrap_or_else(|| panic!("no latency in\n{r}"));
            assert!((0.0..1.0).contains(&latency), "latency {latency}:\n{r}");
            // The client is the rclpy client's reply reader (a Fast DDS GUID: 01.0f.…).
            assert!(
                top(r, "client").is_some_and(|c| c.starts_with("01.0f.") && c.len() == 47),
                "{r}"
            );
            seqs.push(
                top(r, "sequence_number")
                    .and_then(|s| s.parse::<i64>().ok())
                    .unwrap_or_else(|| panic!("no sequence number in\n{r}")),
            );
        }
        // One call after another: consecutive sequence numbers.
        assert!(
            seqs.windows(2).all(|w| w[1] == w[0] + 1),
            "sequence numbers {seqs:?}"
        );
        // Anything unpaired is a reply to a call made before the echo started.
        for r in &recs {
            let status = top(r, "status");
            assert!(
                matches!(status, Some("paired" | "response_only")),
                "unexpected record:\n{r}"
            );
        }
    } else {
        for r in &recs {
            let status = top(r, "status");
            assert!(
                matches!(status, Some("request_only" | "response_only")),
                "Fast DDS traffic cannot be paired on the Cyclone backend:\n{r}"
            );
            assert_eq!(top(r, "convention"), Some("rmw_fastrtps"), "{r}");
            assert!(
                top(r, "note").is_some_and(|n| n.contains("HORUS_ROS_BACKEND=rustdds")),
                "{r}"
            );
            let decoded = if status == Some("request_only") {
                r.contains("request:\n  data: ")
            } else {
                r.contains("response:\n  success: ") && r.contains("\n  message: ")
            };
            assert!(decoded, "the message is still decoded:\n{r}");
        }
    }

    // rclpy's view while the echo ran: no server or client of any node but the rclpy one; the
    // service's types unchanged. rmw_fastrtps counts servers as writers and clients as readers
    // on rr/<service>Reply, nodes or not: the echo's reply reader and the reply writer that
    // keeps the service available to rmw_fastrtps clients are counted there (and the calls
    // went on: the records above).
    assert!(!during.is_empty());
    for r in &during {
        assert_eq!(r["by_node"], before["by_node"], "{r}");
        assert_eq!(r["types"], before["types"], "{r}");
        for count in ["services", "clients"] {
            let n = r[count].as_u64().unwrap_or(0);
            assert!((1..=2).contains(&n), "{count}: {r}");
        }
    }
    println!(
        "servers/clients counted by rclpy while the echo ran: {:?}",
        during
            .iter()
            .map(|r| r["clients"].clone())
            .collect::<Vec<_>>()
    );
}

#[test]
fn passive_echo_json_prints_one_object_per_call() {
    let domain = 222;
    let _pair = rclpy_pair(domain, "/flip");
    let mut watch = rclpy_watch(domain, "/flip");
    settled(&mut watch);
    drop(watch);

    let mut echo = Echo::start(
        domain,
        &["--json"],
        &[
            "/flip",
            "std_srvs/srv/SetBool",
            "--count",
            "4",
            "--reply-timeout",
            "1",
        ],
    );
    let out = echo.rest();
    let docs: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l:?}: {e}")))
        .collect();
    assert_eq!(docs.len(), 4, "{out}");
    for d in &docs {
        for key in [
            "status",
            "convention",
            "client",
            "sequence_number",
            "stamp",
            "latency",
            "request",
            "response",
            "note",
        ] {
            assert!(d.get(key).is_some(), "no {key} in {d}");
        }
        assert_eq!(d["convention"], "rmw_fastrtps", "{d}");
        if pairs_fast_rtps() && d["status"] == "paired" {
            let data = d["request"]["data"].as_bool().expect("request.data");
            assert_eq!(d["response"]["success"], data, "{d}");
            assert_eq!(
                d["response"]["message"],
                if data { "set" } else { "unset" },
                "{d}"
            );
            assert!(d["latency"].as_f64().is_some_and(|l| l >= 0.0), "{d}");
            assert!(d["sequence_number"].as_i64().is_some_and(|s| s > 0), "{d}");
            assert!(d["stamp"]["sec"].as_i64().is_some_and(|s| s > 0), "{d}");
        } else if !pairs_fast_rtps() {
            assert!(d["note"].as_str().is_some(), "{d}");
            assert!(d["client"].is_null() && d["latency"].is_null(), "{d}");
        }
    }
    if pairs_fast_rtps() {
        assert!(
            docs.iter().filter(|d| d["status"] == "paired").count() >= 3,
            "{out}"
        );
    }
}
