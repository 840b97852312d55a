//! Service round-trip benchmark (not a test). Opens DDS participants: run it only inside a private
//! network namespace, e.g. `scripts/bench` or
//! `scripts/isolated cargo bench -p horus-ros-services --bench service_roundtrip`.
//! It refuses to run when it can see a network interface other than `lo` up.
//!
//! Measures, in one run and interleaved in rounds (so every variant sees the same machine
//! state), N sequential request/reply round trips after a warm-up each of:
//! 1. a raw UDP ping-pong on 127.0.0.1 (two threads, blocking receive, 20-byte payload = the
//!    CDR size of an AddTwoInts request), the floor any transport over loopback UDP sits on;
//! 2. horus-ros `ServiceClient::call` to a `ServiceServer` (AddTwoInts), server and client in
//!    two processes (the server in a child process of this bench), in two `Context`s of one
//!    process (two DDS participants), and in one `Context`,
//!    on each backend: rustdds, and Cyclone DDS when built with the feature `cyclone`
//!    (`cargo bench -p horus-ros-services --features cyclone`; scripts/bench does);
//! 3. ros2-client 0.12's own service API (`ServiceMapping::Enhanced`, two ros2-client contexts,
//!    `async_send_request` / `async_receive_response` against `async_receive_request` /
//!    `async_send_response`, each side driven by a minimal thread-parking executor).
//!
//! Then prints p50 / p99 / calls per second of each, each as a ratio to the raw UDP baseline of
//! the same run, and the goals: on Cyclone DDS p50 ≤ 1.3× and p99 ≤ 2× raw UDP, on rustdds p50
//! ≤ 0.5× ros2-client's, and throughput horus / ros2-client ≥ 3.
//!
//! Last, the **first call**: a client (context of its own) calls a service whose server does not
//! exist yet; then a server (another context) starts; the time from the server's `build()` to
//! the call's reply, 5 times per backend (goals: ≤ 50 ms on Cyclone DDS, ≤ 150 ms on rustdds).
//!
//! Then **concurrent clients**: 1, 4 and 16 clients (a thread and a client object each, N
//! sequential calls each after a warm-up) calling one server at once, server and clients in two
//! contexts, on each backend and with ros2-client: calls per second over the wall time, and
//! horus-ros / ros2-client (goal ≥ 3).
//!
//! The Cyclone DDS variants run with the environment's `CYCLONEDDS_URI`; when it is unset, the
//! bench sets a loopback-only configuration (interface `lo`, multicast allowed), since the
//! private namespace has no other interface.
//!
//! Environment: `HORUS_BENCH_CALLS` (measured calls per variant, default 30000),
//! `HORUS_BENCH_ROUNDS` (default 10), `HORUS_BENCH_ONLY` (comma-separated subset of
//! `udp,horusp,horus2,horus1,cyclonep,cyclone2,cyclone1,ros2,first,concurrent`, for profiling one
//! variant; the ratio and goal lines need the baselines), `HORUS_BENCH_CONCURRENT_CALLS` (calls
//! per client of the concurrent part, default 500).

use horus_ros_test_support::bench::{env_usize, loadavg, percentile};
use std::future::Future;
use std::net::UdpSocket;
use std::pin::pin;
use std::sync::Arc;
use std::task::{Poll, Wake, Waker};
use std::thread::{self, JoinHandle, Thread};
use std::time::{Duration, Instant};

use horus_ros_rmw::Backend;
use horus_ros_services::prelude::*;
use serde::{Deserialize, Serialize};

const DEFAULT_CALLS: usize = 30_000;
const DEFAULT_ROUNDS: usize = 10;
/// Calls per client in the concurrent-clients part.
const DEFAULT_CONCURRENT_CALLS: usize = 500;
/// Warm-up calls per variant (after discovery), not measured.
const WARMUP: usize = 500;
/// Whole-run limit: a stalled variant aborts the bench instead of hanging it.
const WATCHDOG: Duration = Duration::from_secs(300);
const CALL_TIMEOUT: Duration = Duration::from_secs(5);
const DISCOVERY_TIMEOUT: Duration = Duration::from_secs(20);
/// Domains used (one per DDS variant, so they cannot see each other).
const DOMAIN_HORUS_TWO: u32 = 61;
const DOMAIN_HORUS_ONE: u32 = 62;
const DOMAIN_ROS2_CLIENT: u16 = 63;
const DOMAIN_CYCLONE_TWO: u32 = 64;
const DOMAIN_CYCLONE_ONE: u32 = 65;
const DOMAIN_HORUS_PROCESSES: u32 = 66;
const DOMAIN_CYCLONE_PROCESSES: u32 = 67;
/// Set in the server child of a two-process variant: `<backend> <domain>`.
const SERVER_CHILD_ENV: &str = "HORUS_BENCH_SERVER_CHILD";
const SERVICE: &str = "/bench_add_two_ints";
/// The Cyclone DDS configuration used when `CYCLONEDDS_URI` is unset: loopback, with multicast.
const CYCLONE_LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";
/// The UDP payload: CDR encapsulation (4) + two int64 (16), as an AddTwoInts request.
const UDP_PAYLOAD: usize = 20;
/// `a` of the request that tells the ros2-client server thread to stop.
const STOP: i64 = i64::MIN;

// ---------------------------------------------------------------------------------------------
// Refuse to run where DDS could reach a real network.

fn refuse_outside_namespace() {
    horus_ros_test_support::bench::refuse_outside_namespace(
        "service_roundtrip",
        "scripts/isolated cargo bench -p horus-ros-services --bench service_roundtrip (build it outside first: cargo bench -p horus-ros-services --no-run)",
    );
}

// ---------------------------------------------------------------------------------------------
// Statistics.

struct Stats {
    name: String,
    samples: Vec<Duration>,
    round_p50: Vec<Duration>,
}

impl Stats {
    fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            samples: Vec::new(),
            round_p50: Vec::new(),
        }
    }

    fn add_round(&mut self, mut round: Vec<Duration>) {
        round.sort_unstable();
        self.round_p50.push(percentile(&round, 50.0));
        self.samples.extend(round);
    }

    fn sorted(&self) -> Vec<Duration> {
        let mut s = self.samples.clone();
        s.sort_unstable();
        s
    }

    fn p50(&self) -> Duration {
        percentile(&self.sorted(), 50.0)
    }

    fn p99(&self) -> Duration {
        percentile(&self.sorted(), 99.0)
    }

    /// Sequential calls per second over the time the calls took.
    fn per_second(&self) -> f64 {
        let total: Duration = self.samples.iter().sum();
        self.samples.len() as f64 / total.as_secs_f64().max(1e-9)
    }
}

fn micros(d: Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

/// Times `calls` sequential calls of `call`.
fn measure(calls: usize, mut call: impl FnMut(i64)) -> Vec<Duration> {
    let mut samples = Vec::with_capacity(calls);
    for i in 0..calls {
        let start = Instant::now();
        call(i as i64);
        samples.push(start.elapsed());
    }
    samples
}

// ---------------------------------------------------------------------------------------------
// 1. Raw UDP ping-pong on 127.0.0.1.

struct UdpPingPong {
    socket: UdpSocket,
    echo: Option<JoinHandle<()>>,
    buf: [u8; 64],
}

impl UdpPingPong {
    fn start() -> std::io::Result<Self> {
        let server = UdpSocket::bind("127.0.0.1:0")?;
        let socket = UdpSocket::bind("127.0.0.1:0")?;
        socket.connect(server.local_addr()?)?;
        let echo = thread::Builder::new()
            .name("udp-echo".into())
            .spawn(move || {
                let mut buf = [0u8; 64];
                // Blocking receive; a 1-byte datagram means stop.
                while let Ok((n, from)) = server.recv_from(&mut buf) {
                    if n == 1 || server.send_to(&buf[..n], from).is_err() {
                        break;
                    }
                }
            })?;
        Ok(Self {
            socket,
            echo: Some(echo),
            buf: [0u8; 64],
        })
    }

    fn round_trip(&mut self, i: i64) {
        let mut payload = [0u8; UDP_PAYLOAD];
        payload[..4].copy_from_slice(&[0, 1, 0, 0]);
        payload[4..12].copy_from_slice(&i.to_le_bytes());
        self.socket.send(&payload).expect("udp send");
        let n = self.socket.recv(&mut self.buf).expect("udp recv");
        assert_eq!(n, UDP_PAYLOAD, "udp echo");
    }
}

impl Drop for UdpPingPong {
    fn drop(&mut self) {
        let _ = self.socket.send(&[0]);
        if let Some(echo) = self.echo.take() {
            let _ = echo.join();
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. horus-ros.

struct Horus {
    client: ServiceClient<AddTwoInts>,
    // Kept alive for the client; dropped after it.
    _server: Server,
    _nodes: Vec<Node>,
}

/// Where the server of a variant runs.
enum Server {
    /// Kept alive while the variant runs.
    InProcess { _server: ServiceServer<AddTwoInts> },
    /// A child process serving until its stdin closes.
    Child(std::process::Child),
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Self::Child(child) = self {
            // Closing its stdin ends it.
            drop(child.stdin.take());
            let _ = child.wait();
        }
    }
}

/// Where server and client run.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layout {
    OneContext,
    TwoContexts,
    TwoProcesses,
}

fn context(backend: Backend, domain: u32) -> Result<Context, String> {
    Context::builder()
        .domain_id(domain)
        .backend(backend)
        .build()
        .map_err(|e| format!("context: {e}"))
}

fn add_two_ints_server(node: &Node) -> Result<ServiceServer<AddTwoInts>, String> {
    ServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(SERVICE)
        .on_request(|req| {
            Ok(AddTwoIntsResponse {
                sum: req.a.wrapping_add(req.b),
            })
        })
        .build()
        .map_err(|e| format!("server: {e}"))
}

/// The server child of a two-process variant: serves until its stdin closes.
fn server_child(spec: &str) {
    let mut parts = spec.split_whitespace();
    let backend: Backend = parts
        .next()
        .and_then(|b| b.parse().ok())
        .expect("backend in HORUS_BENCH_SERVER_CHILD");
    let domain: u32 = parts
        .next()
        .and_then(|d| d.parse().ok())
        .expect("domain in HORUS_BENCH_SERVER_CHILD");
    let node = context(backend, domain)
        .and_then(|c| {
            c.create_node("bench_server", "/")
                .map_err(|e| e.to_string())
        })
        .expect("server node");
    let _server = add_two_ints_server(&node).expect("server");
    println!("serving");
    let mut rest = String::new();
    let _ = std::io::Read::read_to_string(&mut std::io::stdin(), &mut rest);
}

impl Horus {
    fn start(backend: Backend, domain: u32, layout: Layout) -> Result<Self, String> {
        let client_context = context(backend, domain)?;
        let client_node = client_context
            .create_node("bench_client", "/")
            .map_err(|e| format!("node: {e}"))?;
        let mut nodes = vec![client_node.clone()];
        let server = match layout {
            Layout::TwoProcesses => {
                let exe = std::env::current_exe().map_err(|e| e.to_string())?;
                let mut child = std::process::Command::new(exe)
                    .env(SERVER_CHILD_ENV, format!("{backend} {domain}"))
                    .stdin(std::process::Stdio::piped())
                    .stdout(std::process::Stdio::piped())
                    .spawn()
                    .map_err(|e| format!("server process: {e}"))?;
                let mut line = String::new();
                if let Some(out) = child.stdout.take() {
                    let _ =
                        std::io::BufRead::read_line(&mut std::io::BufReader::new(out), &mut line);
                }
                if line.trim() != "serving" {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err("the server process did not start".to_owned());
                }
                Server::Child(child)
            }
            Layout::TwoContexts | Layout::OneContext => {
                let server_context = if layout == Layout::TwoContexts {
                    context(backend, domain)?
                } else {
                    client_context.clone()
                };
                let server_node = server_context
                    .create_node("bench_server", "/")
                    .map_err(|e| format!("node: {e}"))?;
                let server = add_two_ints_server(&server_node)?;
                nodes.push(server_node);
                Server::InProcess { _server: server }
            }
        };
        let client = ServiceClient::<AddTwoInts>::builder()
            .node(&client_node)
            .name(SERVICE)
            .build()
            .map_err(|e| format!("client: {e}"))?;
        if !client.wait_for_service(DISCOVERY_TIMEOUT) {
            return Err(format!(
                "no server within {DISCOVERY_TIMEOUT:?} (wait_for_service)"
            ));
        }
        let mut bench = Self {
            client,
            _server: server,
            _nodes: nodes,
        };
        for i in 0..WARMUP {
            bench.call(i as i64);
        }
        Ok(bench)
    }

    fn call(&mut self, i: i64) {
        let reply = self
            .client
            .call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT)
            .expect("horus-ros call");
        assert_eq!(reply.sum, i + 1, "horus-ros reply");
    }
}

// ---------------------------------------------------------------------------------------------
// 3. ros2-client's own service API.

#[derive(Debug, Clone, Serialize, Deserialize)]
struct R2Request {
    a: i64,
    b: i64,
}
impl ros2_client::Message for R2Request {}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct R2Response {
    sum: i64,
}
impl ros2_client::Message for R2Response {}

/// Wakes the thread blocked in [`block_on`].
struct ThreadWaker(Thread);

impl Wake for ThreadWaker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

/// A minimal executor: polls `future` on this thread, parking between wake-ups (what
/// `futures::executor::block_on` and `smol::block_on` do for one future), giving up (`None`)
/// at `deadline` if there is one: ros2-client's awaited calls have no time limit of their own,
/// and a lost reply must not hang the bench.
fn block_on<F: Future>(future: F, deadline: Option<Instant>) -> Option<F::Output> {
    let mut future = pin!(future);
    let waker = Waker::from(Arc::new(ThreadWaker(thread::current())));
    let mut cx = std::task::Context::from_waker(&waker);
    loop {
        if let Poll::Ready(output) = future.as_mut().poll(&mut cx) {
            return Some(output);
        }
        match deadline {
            None => thread::park(),
            Some(deadline) => {
                let left = deadline.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    return None;
                }
                thread::park_timeout(left);
            }
        }
    }
}

/// Ends a ros2-client server thread: a STOP request is answered like any other, then the
/// thread returns. If it is not answered the thread is left behind (joining it would hang).
fn stop_ros2_server(
    client: &ros2_client::Client<R2Request, R2Response>,
    server_thread: JoinHandle<Result<u64, String>>,
) {
    if let Err(e) = ros2_call(client, STOP) {
        eprintln!("ros2-client server thread not stopped: {e}");
        return;
    }
    match server_thread.join() {
        Ok(Ok(_)) => {}
        Ok(Err(e)) => eprintln!("ros2-client server thread: {e}"),
        Err(_) => eprintln!("ros2-client server thread panicked"),
    }
}

struct Ros2Client {
    client: ros2_client::Client<R2Request, R2Response>,
    server_thread: Option<JoinHandle<Result<u64, String>>>,
    // Dropped last (after the client).
    _client_node: ros2_client::Node,
    _contexts: Vec<ros2_client::Context>,
}

/// ros2-client's side of a measurement: a server thread in one context, `clients` clients in
/// another, each answered once.
struct Ros2Setup {
    clients: Vec<ros2_client::Client<R2Request, R2Response>>,
    server_thread: JoinHandle<Result<u64, String>>,
    client_node: ros2_client::Node,
    contexts: Vec<ros2_client::Context>,
}

fn ros2_setup(domain: u16, clients: usize) -> Result<Ros2Setup, String> {
    use ros2_client::qos::{Durability, History, WhenFull};
    use ros2_client::{
        Context, ContextOptions, Name, NodeName, NodeOptions, QosProfile, ServiceMapping,
        ServiceTypeName,
    };
    // rmw `services_default`: reliable, volatile, keep last 10.
    let qos = QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: 10 });
    let name = Name::new("/", "bench_add_two_ints").map_err(|e| format!("name: {e:?}"))?;
    let type_name = ServiceTypeName::new("example_interfaces", "AddTwoInts");
    let options = || {
        NodeOptions::new()
            .enable_rosout(false)
            .start_parameter_services(false)
    };
    let context = || {
        Context::with_options(ContextOptions::new().domain_id(domain))
            .map_err(|e| format!("context: {e:?}"))
    };
    let server_context = context()?;
    let client_context = context()?;
    let mut server_node = server_context
        .new_node(
            NodeName::new("/", "bench_server").map_err(|e| format!("{e:?}"))?,
            options(),
        )
        .map_err(|e| format!("server node: {e:?}"))?;
    let mut client_node = client_context
        .new_node(
            NodeName::new("/", "bench_client").map_err(|e| format!("{e:?}"))?,
            options(),
        )
        .map_err(|e| format!("client node: {e:?}"))?;
    let server = server_node
        .create_server::<R2Request, R2Response>(
            ServiceMapping::Enhanced,
            &name,
            &type_name,
            qos.clone(),
            qos.clone(),
        )
        .map_err(|e| format!("create_server: {e:?}"))?;
    let clients = (0..clients)
        .map(|_| {
            client_node
                .create_client::<R2Request, R2Response>(
                    ServiceMapping::Enhanced,
                    &name,
                    &type_name,
                    qos.clone(),
                    qos.clone(),
                )
                .map_err(|e| format!("create_client: {e:?}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    // The server loop: receive, add, reply, until a STOP request (which is answered too).
    let server_thread = thread::Builder::new()
        .name("ros2-client-srv".into())
        .spawn(move || {
            let _node = server_node;
            let serve = async {
                let mut served = 0u64;
                loop {
                    let (id, req) = server
                        .async_receive_request()
                        .await
                        .map_err(|e| format!("async_receive_request: {e:?}"))?;
                    let response = R2Response {
                        sum: req.a.wrapping_add(req.b),
                    };
                    server
                        .async_send_response(id, response)
                        .await
                        .map_err(|e| format!("async_send_response: {e:?}"))?;
                    if req.a == STOP {
                        return Ok(served);
                    }
                    served += 1;
                }
            };
            // No deadline: the server waits for requests until STOP.
            block_on(serve, None).unwrap_or_else(|| Err("the server loop ended".to_owned()))
        })
        .map_err(|e| format!("spawn: {e}"))?;
    let setup = Ros2Setup {
        clients,
        server_thread,
        client_node,
        contexts: vec![server_context, client_context],
    };
    for client in &setup.clients {
        ros2_wait_until_answered(client)?;
    }
    Ok(setup)
}

/// No Spinner runs (it would only add graph processing), so `wait_for_service` cannot be
/// used: send probes with the non-blocking API until one is answered. Requests written before
/// the server's reader matched are lost (volatile), hence the repeats.
fn ros2_wait_until_answered(
    client: &ros2_client::Client<R2Request, R2Response>,
) -> Result<(), String> {
    let deadline = Instant::now() + DISCOVERY_TIMEOUT;
    while Instant::now() < deadline {
        let id = client
            .send_request(R2Request { a: -1, b: 1 })
            .map_err(|e| format!("send_request: {e:?}"))?;
        let probe_end = Instant::now() + Duration::from_millis(200);
        while Instant::now() < probe_end {
            match client.receive_response() {
                Ok(Some((rid, _))) if rid == id => return Ok(()),
                Ok(_) => thread::sleep(Duration::from_millis(1)),
                Err(e) => return Err(format!("receive_response: {e:?}")),
            }
        }
    }
    Err(format!(
        "no reply from the ros2-client server within {DISCOVERY_TIMEOUT:?}"
    ))
}

/// One awaited call `i + 1` through ros2-client's async API, checked.
fn ros2_call(client: &ros2_client::Client<R2Request, R2Response>, i: i64) -> Result<(), String> {
    let call = async {
        let id = client
            .async_send_request(R2Request { a: i, b: 1 })
            .await
            .map_err(|e| format!("async_send_request: {e:?}"))?;
        client
            .async_receive_response(id)
            .await
            .map(|r| r.sum)
            .map_err(|e| format!("async_receive_response: {e:?}"))
    };
    let sum = block_on(call, Some(Instant::now() + CALL_TIMEOUT))
        .ok_or_else(|| format!("no reply within {CALL_TIMEOUT:?}"))??;
    if sum != i.wrapping_add(1) {
        return Err(format!("wrong sum {sum} for {i} + 1"));
    }
    Ok(())
}

impl Ros2Client {
    fn start() -> Result<Self, String> {
        let mut setup = ros2_setup(DOMAIN_ROS2_CLIENT, 1)?;
        let client = setup
            .clients
            .pop()
            .ok_or_else(|| "no ros2-client client".to_owned())?;
        let mut bench = Self {
            client,
            server_thread: Some(setup.server_thread),
            _client_node: setup.client_node,
            _contexts: setup.contexts,
        };
        for i in 0..WARMUP {
            bench.call(i as i64)?;
        }
        Ok(bench)
    }

    fn call(&mut self, i: i64) -> Result<(), String> {
        ros2_call(&self.client, i)
    }
}

impl Drop for Ros2Client {
    fn drop(&mut self) {
        if let Some(thread) = self.server_thread.take() {
            stop_ros2_server(&self.client, thread);
        }
    }
}

// ---------------------------------------------------------------------------------------------

fn verdict(met: bool) -> &'static str {
    if met {
        "MET"
    } else {
        "NOT MET"
    }
}

/// One horus-ros variant: its name in `HORUS_BENCH_ONLY`, backend, domain and where server and
/// client run.
struct HorusVariant {
    key: &'static str,
    backend: Backend,
    domain: u32,
    layout: Layout,
}

const HORUS_VARIANTS: [HorusVariant; 6] = [
    HorusVariant {
        key: "horusp",
        backend: Backend::RustDds,
        domain: DOMAIN_HORUS_PROCESSES,
        layout: Layout::TwoProcesses,
    },
    HorusVariant {
        key: "horus2",
        backend: Backend::RustDds,
        domain: DOMAIN_HORUS_TWO,
        layout: Layout::TwoContexts,
    },
    HorusVariant {
        key: "horus1",
        backend: Backend::RustDds,
        domain: DOMAIN_HORUS_ONE,
        layout: Layout::OneContext,
    },
    HorusVariant {
        key: "cyclonep",
        backend: Backend::Cyclone,
        domain: DOMAIN_CYCLONE_PROCESSES,
        layout: Layout::TwoProcesses,
    },
    HorusVariant {
        key: "cyclone2",
        backend: Backend::Cyclone,
        domain: DOMAIN_CYCLONE_TWO,
        layout: Layout::TwoContexts,
    },
    HorusVariant {
        key: "cyclone1",
        backend: Backend::Cyclone,
        domain: DOMAIN_CYCLONE_ONE,
        layout: Layout::OneContext,
    },
];

impl HorusVariant {
    fn name(&self) -> String {
        format!(
            "horus-ros {}, {}",
            self.backend,
            match self.layout {
                Layout::TwoProcesses => "2 processes",
                Layout::TwoContexts => "2 contexts",
                Layout::OneContext => "1 context",
            }
        )
    }
}

/// `value / baseline` as `12.3×`, or `n/a`.
fn times(value: f64, baseline: f64) -> String {
    if value > 0.0 && baseline > 0.0 {
        let ratio = value / baseline;
        if ratio < 1.0 {
            format!("{ratio:.3}×")
        } else {
            format!("{ratio:.2}×")
        }
    } else {
        "n/a".to_owned()
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Throughput with concurrent clients.

/// How many clients call at once.
const CONCURRENT_CLIENTS: [usize; 3] = [1, 4, 16];
/// Domains of the concurrent measurements: horus-ros on rustdds, on Cyclone DDS, ros2-client.
const DOMAIN_CONCURRENT_RUSTDDS: u32 = 69;
const DOMAIN_CONCURRENT_CYCLONE: u32 = 70;
const DOMAIN_CONCURRENT_ROS2: u16 = 71;
/// Unmeasured calls each client makes first.
const CONCURRENT_WARMUP: usize = 50;

/// Runs `clients` callers at once, each on a thread of its own: `prepare(k)` builds caller
/// `k`'s call (unmeasured, warm-up included) and `call(i)` makes its `i`-th call. Returns calls
/// per second over the wall time from the moment all are prepared.
fn calls_per_second<C, F>(clients: usize, calls: usize, prepare: F) -> Result<f64, String>
where
    F: Fn(usize) -> Result<C, String> + Sync,
    C: FnMut(i64) -> Result<(), String>,
{
    let start_line = std::sync::Barrier::new(clients + 1);
    let prepare = &prepare;
    let start_line = &start_line;
    thread::scope(|scope| {
        let workers: Vec<_> = (0..clients)
            .map(|k| {
                scope.spawn(move || {
                    let caller = prepare(k);
                    start_line.wait();
                    let mut call = caller?;
                    for i in 0..calls {
                        call((k * calls + i) as i64)?;
                    }
                    Ok::<(), String>(())
                })
            })
            .collect();
        start_line.wait();
        let start = Instant::now();
        for worker in workers {
            worker
                .join()
                .map_err(|_| "a client thread panicked".to_owned())??;
        }
        Ok((clients * calls) as f64 / start.elapsed().as_secs_f64())
    })
}

/// horus-ros: one server in a context of its own, `clients` `ServiceClient`s in another.
fn horus_concurrent(backend: Backend, clients: usize, calls: usize) -> Result<f64, String> {
    let domain = match backend {
        Backend::RustDds => DOMAIN_CONCURRENT_RUSTDDS,
        Backend::Cyclone => DOMAIN_CONCURRENT_CYCLONE,
        other => return Err(format!("not measured on {other} yet")),
    };
    let server_node = context(backend, domain)?
        .create_node("bench_server", "/")
        .map_err(|e| format!("node: {e}"))?;
    let _server = add_two_ints_server(&server_node)?;
    let client_node = context(backend, domain)?
        .create_node("bench_clients", "/")
        .map_err(|e| format!("node: {e}"))?;
    calls_per_second(clients, calls, |_| {
        let mut client = ServiceClient::<AddTwoInts>::builder()
            .node(&client_node)
            .name(SERVICE)
            .build()
            .map_err(|e| format!("client: {e}"))?;
        if !client.wait_for_service(DISCOVERY_TIMEOUT) {
            return Err(format!("no server within {DISCOVERY_TIMEOUT:?}"));
        }
        let mut call = move |i: i64| {
            let reply = client
                .call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT)
                .map_err(|e| format!("call: {e}"))?;
            if reply.sum != i.wrapping_add(1) {
                return Err(format!("wrong sum {} for {i} + 1", reply.sum));
            }
            Ok(())
        };
        for i in 0..CONCURRENT_WARMUP {
            call(-(i as i64) - 2)?;
        }
        Ok(call)
    })
}

/// ros2-client: its server thread in one context, `clients` clients in another.
fn ros2_concurrent(clients: usize, calls: usize) -> Result<f64, String> {
    let setup = ros2_setup(DOMAIN_CONCURRENT_ROS2, clients)?;
    let result = calls_per_second(clients, calls, |k| {
        let client = &setup.clients[k];
        for i in 0..CONCURRENT_WARMUP {
            ros2_call(client, -(i as i64) - 2)?;
        }
        Ok(move |i: i64| ros2_call(client, i))
    });
    if let Some(client) = setup.clients.first() {
        stop_ros2_server(client, setup.server_thread);
    }
    result
}

fn concurrent(calls: usize) {
    println!();
    println!(
        "concurrent clients: N clients (a thread and a client each, {calls} sequential calls \
         each) on one server, server and clients in two contexts; calls per second over the \
         wall time"
    );
    for clients in CONCURRENT_CLIENTS {
        let ros2 = ros2_concurrent(clients, calls);
        match &ros2 {
            Ok(r) => println!("  {clients:>2} clients: ros2-client Enhanced  {r:>9.0} calls/s"),
            Err(e) => println!("  {clients:>2} clients: ros2-client Enhanced  failed: {e}"),
        }
        for backend in Backend::ALL
            .iter()
            .copied()
            .filter(|b| b.is_available() && *b != Backend::Zenoh)
        {
            match (horus_concurrent(backend, clients, calls), &ros2) {
                (Ok(h), Ok(r)) => println!(
                    "  {clients:>2} clients: horus-ros {backend:<8}   {h:>9.0} calls/s, \
                     {:.2}× ros2-client (goal ≥ 3) {}",
                    h / r,
                    verdict(h / r >= 3.0)
                ),
                (Ok(h), Err(_)) => println!(
                    "  {clients:>2} clients: horus-ros {backend:<8}   {h:>9.0} calls/s \
                     (goal ≥ 3× ros2-client) NOT MEASURED"
                ),
                (Err(e), _) => {
                    println!("  {clients:>2} clients: horus-ros {backend:<8}   failed: {e}")
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4. The first call after the server appears.

const DOMAIN_FIRST_CALL: u32 = 68;
const FIRST_CALL_REPEATS: usize = 5;

/// The time from a server's `build()` to the reply of a call that was waiting for it.
fn first_call(backend: Backend, repeat: usize) -> Result<Duration, String> {
    let name = format!("/first_call_{repeat}");
    let client_node = context(backend, DOMAIN_FIRST_CALL)?
        .create_node("first_client", "/")
        .map_err(|e| e.to_string())?;
    let server_node = context(backend, DOMAIN_FIRST_CALL)?
        .create_node("first_server", "/")
        .map_err(|e| e.to_string())?;
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&client_node)
        .name(name.clone())
        .build()
        .map_err(|e| format!("client: {e}"))?;
    let (started_tx, started_rx) = std::sync::mpsc::channel::<Instant>();
    let caller = thread::spawn(move || {
        let reply = client.call(AddTwoIntsRequest { a: 1, b: 2 }, DISCOVERY_TIMEOUT);
        (reply, Instant::now())
    });
    let server_thread = thread::spawn(move || {
        let started = Instant::now();
        let server = ServiceServer::<AddTwoInts>::builder()
            .node(&server_node)
            .name(name)
            .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
            .build();
        let _ = started_tx.send(started);
        server
    });
    let (reply, replied) = caller.join().map_err(|_| "caller panicked".to_owned())?;
    let _server = server_thread
        .join()
        .map_err(|_| "server thread panicked".to_owned())?
        .map_err(|e| format!("server: {e}"))?;
    let started = started_rx.recv().map_err(|e| e.to_string())?;
    let reply = reply.map_err(|e| format!("first call: {e}"))?;
    if reply.sum != 3 {
        return Err(format!("first call: wrong sum {}", reply.sum));
    }
    Ok(replied.saturating_duration_since(started))
}

fn first_calls() {
    println!();
    println!(
        "first call: a waiting client's reply after its server's build(), {FIRST_CALL_REPEATS} times"
    );
    for backend in Backend::ALL
        .iter()
        .copied()
        .filter(|b| b.is_available() && *b != Backend::Zenoh)
    {
        let goal = match backend {
            Backend::Cyclone => Duration::from_millis(50),
            Backend::RustDds => Duration::from_millis(150),
            _ => continue,
        };
        let mut times = Vec::new();
        for repeat in 0..FIRST_CALL_REPEATS {
            match first_call(backend, repeat) {
                Ok(t) => times.push(t),
                Err(e) => println!("  {backend:>8}: {e}"),
            }
        }
        times.sort();
        let Some(max) = times.last().copied() else {
            continue;
        };
        let median = times[times.len() / 2];
        println!(
            "  {backend:>8}: median {:.1} ms, max {:.1} ms (goal ≤ {} ms) {}",
            median.as_secs_f64() * 1e3,
            max.as_secs_f64() * 1e3,
            goal.as_millis(),
            verdict(median <= goal)
        );
    }
}

fn main() {
    refuse_outside_namespace();
    // Before any thread starts (Cyclone DDS reads it when a context creates its domain).
    let cyclone_uri_set = std::env::var_os("CYCLONEDDS_URI").is_some();
    if !cyclone_uri_set {
        std::env::set_var("CYCLONEDDS_URI", CYCLONE_LOOPBACK);
    }
    if let Ok(spec) = std::env::var(SERVER_CHILD_ENV) {
        server_child(&spec);
        return;
    }
    thread::spawn(|| {
        thread::sleep(WATCHDOG);
        eprintln!("service_roundtrip: stalled for {WATCHDOG:?}; aborting");
        std::process::exit(3);
    });

    let calls = env_usize("HORUS_BENCH_CALLS", DEFAULT_CALLS);
    let rounds = env_usize("HORUS_BENCH_ROUNDS", DEFAULT_ROUNDS).min(calls);
    let per_round = calls / rounds;
    let calls = per_round * rounds;
    let cpus = thread::available_parallelism().map_or(0, |n| n.get());
    println!("service_roundtrip: sequential AddTwoInts round trips over loopback");
    println!(
        "  {calls} measured calls per variant ({rounds} interleaved rounds of {per_round}), \
         {WARMUP} warm-up calls each after discovery"
    );
    println!(
        "  CPUs: {cpus}; load average at start: {}; whether the machine was otherwise idle is \
         unknown (other processes may share these CPUs)",
        loadavg()
    );
    println!(
        "  backends: {}; Cyclone DDS configuration: {}",
        Backend::ALL
            .iter()
            .map(|b| if b.is_available() {
                b.to_string()
            } else {
                format!("{b} (not built in: feature `{b}`)")
            })
            .collect::<Vec<_>>()
            .join(", "),
        if cyclone_uri_set {
            "CYCLONEDDS_URI from the environment"
        } else {
            "loopback only (CYCLONEDDS_URI was unset)"
        }
    );

    let setup_start = Instant::now();
    let only = std::env::var("HORUS_BENCH_ONLY").unwrap_or_default();
    let wanted = |v: &str| only.is_empty() || only.split(',').any(|o| o.trim() == v);
    let mut failed_setup = false;
    let mut udp = wanted("udp").then(|| {
        let mut udp = UdpPingPong::start().expect("UDP ping-pong on 127.0.0.1");
        for i in 0..WARMUP {
            udp.round_trip(i as i64);
        }
        udp
    });
    // (stats, the running variant, why it is not measured)
    let mut horus: Vec<(Stats, Option<Horus>, Option<String>)> = HORUS_VARIANTS
        .iter()
        .map(|v| {
            let stats = Stats::new(v.name());
            if !wanted(v.key) {
                return (stats, None, Some("not asked for (HORUS_BENCH_ONLY)".into()));
            }
            if !v.backend.is_available() {
                return (
                    stats,
                    None,
                    Some("not built in (build with --features cyclone)".into()),
                );
            }
            match Horus::start(v.backend, v.domain, v.layout) {
                Ok(h) => (stats, Some(h), None),
                Err(e) => {
                    println!("  {} could not be benchmarked: {e}", v.name());
                    failed_setup = true;
                    (stats, None, Some(format!("setup failed: {e}")))
                }
            }
        })
        .collect();
    let mut ros2 = if wanted("ros2") {
        match Ros2Client::start() {
            Ok(r) => Some(r),
            Err(e) => {
                println!("  ros2-client could not be benchmarked: {e}");
                None
            }
        }
    } else {
        None
    };
    println!(
        "  setup (discovery + warm-up of all variants): {:.2} s",
        setup_start.elapsed().as_secs_f64()
    );

    let mut udp_stats = Stats::new("raw UDP ping-pong 127.0.0.1");
    let mut ros2_stats = Stats::new("ros2-client Enhanced, 2 ctx");
    let mut ros2_error = None;
    let run_start = Instant::now();
    for _ in 0..rounds {
        if let Some(u) = udp.as_mut() {
            udp_stats.add_round(measure(per_round, |i| u.round_trip(i)));
        }
        for (stats, h, _) in &mut horus {
            if let Some(h) = h.as_mut() {
                stats.add_round(measure(per_round, |i| h.call(i)));
            }
        }
        if let Some(r) = ros2.as_mut() {
            let mut failed = None;
            let samples = measure(per_round, |i| {
                if failed.is_none() {
                    failed = r.call(i).err();
                }
            });
            match failed {
                None => ros2_stats.add_round(samples),
                Some(e) => {
                    ros2_error = Some(e);
                    ros2 = None;
                }
            }
        }
    }
    let run_time = run_start.elapsed();
    drop(ros2);
    // Last variant first (as before: one context, then two).
    for (_, h, _) in horus.iter_mut().rev() {
        drop(h.take());
    }
    drop(udp);

    println!(
        "  measured part: {:.2} s; load average at end: {}",
        run_time.as_secs_f64(),
        loadavg()
    );
    println!();
    println!(
        "  {:<32} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11}   p50 per round (µs)",
        "variant", "p50 µs", "p99 µs", "calls/s", "p50/UDP", "p99/UDP", "calls/s/UDP"
    );
    let (udp_p50, udp_p99, udp_rate) = if udp_stats.samples.is_empty() {
        (0.0, 0.0, 0.0)
    } else {
        (
            micros(udp_stats.p50()),
            micros(udp_stats.p99()),
            udp_stats.per_second(),
        )
    };
    let rows = std::iter::once((&udp_stats, None))
        .chain(horus.iter().map(|(s, _, why)| (s, why.as_deref())))
        .chain(std::iter::once((&ros2_stats, None)));
    for (s, why) in rows {
        if s.samples.is_empty() {
            println!("  {:<32} {:>9}   {}", s.name, "n/a", why.unwrap_or(""));
            continue;
        }
        let rounds: Vec<String> = s
            .round_p50
            .iter()
            .map(|d| format!("{:.0}", micros(*d)))
            .collect();
        let (p50, p99, rate) = (micros(s.p50()), micros(s.p99()), s.per_second());
        println!(
            "  {:<32} {:>9.1} {:>9.1} {:>9.0} {:>9} {:>9} {:>11}   {}",
            s.name,
            p50,
            p99,
            rate,
            times(p50, udp_p50),
            times(p99, udp_p99),
            times(rate, udp_rate),
            rounds.join(" ")
        );
    }
    if let Some(e) = &ros2_error {
        println!("  ros2-client failed during the run: {e}");
    }
    // The baseline's rounds can differ a lot (on a small VM: both threads on one CPU or woken
    // across CPUs); then say so, with the p50 ratios against its fastest round as well.
    let udp_rounds = (
        udp_stats.round_p50.iter().min().copied(),
        udp_stats.round_p50.iter().max().copied(),
    );
    let mut unstable_floor = None;
    if let (Some(fastest), Some(slowest)) = udp_rounds {
        if slowest > fastest * 2 {
            unstable_floor = Some(micros(fastest));
            let fastest_us = micros(fastest);
            println!(
                "  note: the UDP baseline's round p50s range from {fastest_us:.1} to {:.1} µs \
                 (thread placement on the CPUs); p50 against its fastest round:",
                micros(slowest)
            );
            for (s, _, _) in &horus {
                if !s.samples.is_empty() {
                    println!(
                        "    {:<32} {:>9}",
                        s.name,
                        times(micros(s.p50()), fastest_us)
                    );
                }
            }
            if !ros2_stats.samples.is_empty() {
                println!(
                    "    {:<32} {:>9}",
                    ros2_stats.name,
                    times(micros(ros2_stats.p50()), fastest_us)
                );
            }
        }
    }
    println!();

    // Goals: Cyclone DDS p50 ≤ 1.3× and p99 ≤ 2× raw UDP; rustdds p50 ≤ 0.5× ros2-client's.
    for ((s, _, _), v) in horus.iter().zip(&HORUS_VARIANTS) {
        if s.samples.is_empty() || udp_stats.samples.is_empty() {
            println!("  p50 goal: n/a NOT MEASURED   [{}]", s.name);
            continue;
        }
        match v.backend {
            Backend::Cyclone => {
                let p50 = micros(s.p50()) / udp_p50;
                let p99 = micros(s.p99()) / udp_p99;
                let caveat = unstable_floor.map_or(String::new(), |floor| {
                    format!(
                        " (baseline unstable; p50 against its fastest round {:.2}: {})",
                        micros(s.p50()) / floor,
                        verdict(micros(s.p50()) / floor <= 1.3)
                    )
                });
                println!(
                    "  p50/udp = {p50:.2} (goal ≤ 1.3) {}, p99/udp = {p99:.2} (goal ≤ 2) {}{caveat}   [{}]",
                    verdict(p50 <= 1.3),
                    verdict(p99 <= 2.0),
                    s.name
                );
            }
            Backend::RustDds => {
                if ros2_stats.samples.is_empty() {
                    println!(
                        "  p50/ros2-client = n/a (goal ≤ 0.5) NOT MEASURED   [{}]",
                        s.name
                    );
                    continue;
                }
                let ratio = micros(s.p50()) / micros(ros2_stats.p50());
                println!(
                    "  p50/ros2-client = {ratio:.2} (goal ≤ 0.5) {}   [{}]",
                    verdict(ratio <= 0.5),
                    s.name
                );
            }
            _ => {}
        }
    }
    for (s, _, _) in &horus {
        if s.samples.is_empty() || ros2_stats.samples.is_empty() {
            println!(
                "  throughput ratio horus/ros2-client = n/a (goal ≥ 3) NOT MEASURED   [{}]",
                s.name
            );
            continue;
        }
        let ratio = s.per_second() / ros2_stats.per_second();
        println!(
            "  throughput ratio horus/ros2-client = {ratio:.2} (goal ≥ 3) {}   [{}]",
            verdict(ratio >= 3.0),
            s.name
        );
    }
    if wanted("first") {
        first_calls();
    }
    if wanted("concurrent") {
        concurrent(env_usize(
            "HORUS_BENCH_CONCURRENT_CALLS",
            DEFAULT_CONCURRENT_CALLS,
        ));
    }
    if failed_setup {
        std::process::exit(1);
    }
}
