//! Reliability benchmark (not a test). Opens DDS participants: run it only inside a private
//! network namespace, e.g. `scripts/bench` or
//! `scripts/isolated cargo bench -p horus-ros-services --features cyclone --bench reliability`.
//! It refuses to run when it can see a network interface other than `lo` up.
//!
//! On each backend (rustdds, and Cyclone DDS when built with the feature `cyclone`) it prints:
//! 1. **Many clients**: 8, then 64 blocking `ServiceClient`s (8 per `Context`, i.e. 8 per DDS
//!    participant, as 8 processes would have) each making N sequential AddTwoInts calls with a
//!    2 s timeout against one `ServiceServer` in its own `Context`: calls per second over the
//!    wall time, p50 / p99 / max latency, calls lost (any error) and misrouted (a reply with
//!    another call's sum).
//! 2. **Hostile peers**: the p50 / p99 of one good client's calls (one every 5 ms for a phase of
//!    5 s), alone, then while
//!    a stalling peer sends requests on the request topic at 10 Hz naming a reply reader that
//!    does not exist (rmw_fastrtps convention; on the Cyclone backend an rmw_cyclonedds header
//!    from a participant with no reply reader), then after it stopped, then while a garbage
//!    peer writes random bodies of 0 B to 1 MiB on the request topic.
//! 3. **Idle cost**: the CPU time and the thread count of a process holding a context and a
//!    node, then the same with `NodeServices` (7 servers) started, each over 10 s of idleness
//!    (from `/proc/self/stat`, in a child process of its own), and the wake-ups per second of
//!    our own threads (named `horus-…`) and of the DDS stack's threads: context switches from
//!    `/proc/self/task/*/status` (a thread that sleeps until an event has none while idle).
//!
//! Environment: `HORUS_BENCH_RELIABILITY_CALLS` (N, calls per client; default 300),
//! `HORUS_BENCH_RELIABILITY_PER_CONTEXT` (clients per context, default 8),
//! `HORUS_BENCH_RELIABILITY_CLIENTS` (comma-separated client counts of part 1; default `8,64`),
//! `HORUS_BENCH_RELIABILITY_PHASE_SECS` (length of each hostile-peer phase; default 5),
//! `HORUS_BENCH_RELIABILITY_ONLY` (comma-separated subset of `clients,hostile,idle`),
//! `HORUS_BENCH_RELIABILITY_BACKENDS` (comma-separated subset of `rustdds,cyclone`).
//! The Cyclone DDS variants run with the environment's `CYCLONEDDS_URI`; when it is unset, the
//! bench sets a loopback-only configuration.

use horus_ros_test_support::bench::{env_usize, percentile};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Barrier};
use std::thread;
use std::time::{Duration, Instant};

use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Backend, Gid, RawEndpointSpec, RawWriter, SampleId};
use horus_ros_services::prelude::*;
use horus_ros_services::NodeServices;

const DEFAULT_CALLS: usize = 300;
/// How long each hostile-peer phase lasts by default.
const DEFAULT_PHASE_SECS: usize = 5;
/// The good client calls once per period (a steady load, not a saturating one).
const GOOD_CALL_PERIOD: Duration = Duration::from_millis(5);
const CALL_TIMEOUT: Duration = Duration::from_secs(2);
const DISCOVERY_TIMEOUT: Duration = Duration::from_secs(30);
const DEFAULT_CLIENTS_PER_CONTEXT: usize = 8;
/// Whole-run limit: a stalled run aborts the bench instead of hanging it.
const WATCHDOG: Duration = Duration::from_secs(600);
const IDLE_MEASURE: Duration = Duration::from_secs(10);
/// Linux reports /proc CPU times in USER_HZ ticks, 100 per second on every architecture's ABI.
const USER_HZ: f64 = 100.0;
const IDLE_CHILD_ENV: &str = "HORUS_BENCH_RELIABILITY_IDLE_CHILD";
const CYCLONE_LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

fn refuse_outside_namespace() {
    horus_ros_test_support::bench::refuse_outside_namespace(
        "reliability",
        "scripts/isolated cargo bench -p horus-ros-services --features cyclone --bench reliability",
    );
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn context(backend: Backend, domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .backend(backend)
        .build()
        .expect("context")
}

fn adder(node: &Node, name: &str) -> ServiceServer<AddTwoInts> {
    ServiceServer::<AddTwoInts>::builder()
        .node(node)
        .name(name)
        .on_request(|req| {
            Ok(AddTwoIntsResponse {
                sum: req.a.wrapping_add(req.b),
            })
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

// ---------------------------------------------------------------------------------------------
// 1. Many clients.

struct ManyClients {
    clients: usize,
    calls: usize,
    wall: Duration,
    latencies: Vec<Duration>,
    lost: usize,
    misrouted: usize,
    errors: Vec<String>,
}

fn many_clients(
    backend: Backend,
    domain: u32,
    clients: usize,
    per_context: usize,
    calls: usize,
) -> ManyClients {
    let service = "/reliability_add";
    let server_node = context(backend, domain)
        .create_node("reliability_server", "/")
        .expect("node");
    let server = adder(&server_node, service);
    let contexts = clients.div_ceil(per_context);
    let nodes: Vec<Node> = (0..contexts)
        .map(|i| {
            context(backend, domain)
                .create_node(&format!("reliability_clients_{i}"), "/")
                .expect("node")
        })
        .collect();
    let start_line = Arc::new(Barrier::new(clients + 1));
    let workers: Vec<_> = (0..clients)
        .map(|k| {
            let node = nodes[k / per_context].clone();
            let start_line = Arc::clone(&start_line);
            thread::spawn(move || {
                let mut c = client(&node, service);
                let ready = c.wait_for_service(DISCOVERY_TIMEOUT);
                start_line.wait();
                assert!(ready, "client {k} never saw the server");
                let (mut latencies, mut lost, mut misrouted, mut errors) =
                    (Vec::with_capacity(calls), 0, 0, Vec::new());
                for i in 0..calls as i64 {
                    let a = k as i64 * 1_000_000;
                    let t = Instant::now();
                    match c.call(AddTwoIntsRequest { a, b: i }, CALL_TIMEOUT) {
                        Ok(r) if r.sum == a + i => latencies.push(t.elapsed()),
                        Ok(_) => misrouted += 1,
                        Err(e) => {
                            lost += 1;
                            if errors.len() < 3 {
                                errors.push(format!("client {k} call {i}: {e}"));
                            }
                        }
                    }
                }
                (latencies, lost, misrouted, errors)
            })
        })
        .collect();
    start_line.wait();
    let start = Instant::now();
    let mut out = ManyClients {
        clients,
        calls,
        wall: Duration::ZERO,
        latencies: Vec::new(),
        lost: 0,
        misrouted: 0,
        errors: Vec::new(),
    };
    for w in workers {
        let (latencies, lost, misrouted, errors) = w.join().expect("client thread");
        out.latencies.extend(latencies);
        out.lost += lost;
        out.misrouted += misrouted;
        out.errors.extend(errors);
    }
    out.wall = start.elapsed();
    out.latencies.sort_unstable();
    drop(server);
    out
}

fn print_many(backend: Backend, r: &ManyClients) {
    let total = r.clients * r.calls;
    println!(
        "  {backend:>8} {:>3} clients x {} calls: {:>7.0} calls/s, p50 {:>7.2} ms, p99 {:>7.2} ms, \
         max {:>8.2} ms, lost {} of {total}, misrouted {}",
        r.clients,
        r.calls,
        r.latencies.len() as f64 / r.wall.as_secs_f64().max(1e-9),
        ms(percentile(&r.latencies, 50.0)),
        ms(percentile(&r.latencies, 99.0)),
        ms(r.latencies.last().copied().unwrap_or_default()),
        r.lost,
        r.misrouted,
    );
    for e in r.errors.iter().take(3) {
        println!("           e.g. {e}");
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Hostile peers.

/// A raw writer of our own on the service's request topic, in a context of its own with no reply
/// reader: the hostile peer.
fn hostile_writer(node: &Node, service: &str) -> RawWriter {
    let name = ServiceName::new(service).expect("service name");
    let mut qos = Qos::services_default();
    qos.depth = 256;
    node.create_raw_writer(&RawEndpointSpec {
        dds_topic_name: name.to_dds_request_topic_name(false),
        dds_type_name: AddTwoIntsRequest::dds_type_name(),
        type_hash: AddTwoIntsRequest::type_hash(),
        qos,
        service_id: None,
    })
    .expect("raw writer")
}

/// A well-formed AddTwoInts request that no reply can reach: on a backend that carries
/// related_sample_identity, in the rmw_fastrtps convention naming a reply reader that does not
/// exist; else with an rmw_cyclonedds header (from a participant without a reply reader).
fn write_stalling_request(writer: &RawWriter, backend: Backend, n: i64) {
    let body = horus_ros_msgs::cdr::to_cdr_body(&AddTwoIntsRequest { a: n, b: n }).expect("cdr");
    if backend
        .capabilities()
        .is_some_and(|c| c.carries_sample_identity)
    {
        let mut ghost = [0u8; 16];
        ghost[..12].copy_from_slice(&writer.gid().as_bytes()[..12]);
        ghost[12..].copy_from_slice(&[0x7f, 0xff, 0x00, 0x04]);
        let related = SampleId {
            writer: Gid::from_bytes(ghost),
            sequence_number: SampleId::UNKNOWN_SEQUENCE_NUMBER,
        };
        let _ = writer.write(body, Some(related), None);
    } else {
        let mut framed = 0x0123_4567_89ab_cdefu64.to_le_bytes().to_vec();
        framed.extend_from_slice(&n.to_le_bytes());
        framed.extend_from_slice(&body);
        let _ = writer.write(framed, None, None);
    }
}

/// xorshift64*: reproducible garbage without a dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A length from 0 B to `max`, spread over every order of magnitude.
    fn length(&mut self, max: usize) -> usize {
        let bits = (self.next() % (usize::BITS - max.leading_zeros()) as u64) as u32;
        (self.next() as usize % (1usize << bits).max(1)).min(max)
    }

    fn bytes(&mut self, len: usize) -> Vec<u8> {
        (0..len).map(|_| self.next() as u8).collect()
    }
}

/// What a hostile peer does each time (given a counter).
type PeerAction = Box<dyn FnMut(i64) + Send>;

/// Runs `peer` on its own thread (every `period`) while `good` makes sequential calls for
/// `phase`, one every [`GOOD_CALL_PERIOD`]; returns the good client's sorted latencies and its
/// failures.
fn measure_with_peer(
    good: &mut ServiceClient<AddTwoInts>,
    phase: Duration,
    peer: Option<(Duration, PeerAction)>,
) -> (Vec<Duration>, usize) {
    let stop = Arc::new(AtomicBool::new(false));
    let peer = peer.map(|(period, mut act)| {
        let stop = Arc::clone(&stop);
        thread::spawn(move || {
            let mut n = 0;
            while !stop.load(Ordering::SeqCst) {
                act(n);
                n += 1;
                thread::sleep(period);
            }
        })
    });
    let mut latencies = Vec::new();
    let mut failed = 0;
    let start = Instant::now();
    let mut i = 0;
    while start.elapsed() < phase {
        let t = Instant::now();
        match good.call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT) {
            Ok(r) if r.sum == i + 1 => latencies.push(t.elapsed()),
            _ => failed += 1,
        }
        i += 1;
        thread::sleep(GOOD_CALL_PERIOD.saturating_sub(t.elapsed()));
    }
    stop.store(true, Ordering::SeqCst);
    if let Some(p) = peer {
        p.join().expect("peer thread");
    }
    latencies.sort_unstable();
    (latencies, failed)
}

fn hostile(backend: Backend, domain: u32, phase: Duration) {
    let service = "/reliability_hostile";
    let server_node = context(backend, domain)
        .create_node("hostile_server", "/")
        .expect("node");
    let _server = adder(&server_node, service);
    let good_node = context(backend, domain)
        .create_node("good_client", "/")
        .expect("node");
    let mut good = client(&good_node, service);
    assert!(good.wait_for_service(DISCOVERY_TIMEOUT), "no server");
    let peer_node = context(backend, domain)
        .create_node("hostile_peer", "/")
        .expect("node");
    let writer = Arc::new(hostile_writer(&peer_node, service));
    // The peer's writer must be matched with the server's reader before its samples count.
    let _ = measure_with_peer(&mut good, Duration::from_millis(500), None);
    let report = |what: &str, (latencies, failed): (Vec<Duration>, usize)| {
        println!(
            "  {backend:>8} good client, {what:<34}: p50 {:>7.2} ms, p99 {:>7.2} ms, max {:>8.2} \
             ms, failed {failed} of {}",
            ms(percentile(&latencies, 50.0)),
            ms(percentile(&latencies, 99.0)),
            ms(latencies.last().copied().unwrap_or_default()),
            latencies.len() + failed,
        );
    };
    report("alone", measure_with_peer(&mut good, phase, None));
    let w = Arc::clone(&writer);
    report(
        "with a stalling peer at 10 Hz",
        measure_with_peer(
            &mut good,
            phase,
            Some((
                Duration::from_millis(100),
                Box::new(move |n| write_stalling_request(&w, backend, n)),
            )),
        ),
    );
    report(
        "after the stalling peer stopped",
        measure_with_peer(&mut good, phase, None),
    );
    let w = Arc::clone(&writer);
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    report(
        "with a garbage peer at 100 Hz",
        measure_with_peer(
            &mut good,
            phase,
            Some((
                Duration::from_millis(10),
                Box::new(move |_| {
                    let len = rng.length(1 << 20);
                    let _ = w.write(rng.bytes(len), None, None);
                }),
            )),
        ),
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Idle cost, measured in a child process.

/// (CPU seconds used by this process so far, threads now).
fn cpu_and_threads() -> (f64, usize) {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the parenthesised command name: state is field 3, utime 14, stime 15.
    let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i - 3)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    let threads = fields.get(20 - 3).and_then(|f| f.parse().ok()).unwrap_or(0);
    ((ticks(14) + ticks(15)) / USER_HZ, threads)
}

/// Context switches so far of each thread of this process, by thread id: (name, switches).
fn thread_switches() -> std::collections::BTreeMap<u32, (String, u64)> {
    let mut out = std::collections::BTreeMap::new();
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return out;
    };
    for task in tasks.flatten() {
        let Some(tid) = task.file_name().to_str().and_then(|t| t.parse().ok()) else {
            continue;
        };
        let name = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        let status = std::fs::read_to_string(task.path().join("status")).unwrap_or_default();
        let switches = status
            .lines()
            .filter(|l| l.contains("ctxt_switches"))
            .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
            .sum();
        out.insert(tid, (name.trim().to_owned(), switches));
    }
    out
}

/// Wake-ups per second over `elapsed` between two [`thread_switches`], split into our own
/// threads (`horus-…`) and the others (the DDS stack's), with the busiest of ours.
fn wakeups(
    before: &std::collections::BTreeMap<u32, (String, u64)>,
    after: &std::collections::BTreeMap<u32, (String, u64)>,
    elapsed: Duration,
    measuring_thread: u32,
) -> String {
    let (mut ours, mut dds) = (0u64, 0u64);
    let mut busiest: Vec<(u64, String)> = Vec::new();
    for (tid, (name, switches)) in after {
        if *tid == measuring_thread {
            continue;
        }
        let delta = switches.saturating_sub(before.get(tid).map_or(0, |(_, s)| *s));
        if name.starts_with("horus-") {
            ours += delta;
            if delta > 0 {
                busiest.push((delta, name.clone()));
            }
        } else {
            dds += delta;
        }
    }
    busiest.sort_by(|a, b| b.cmp(a));
    let per_second = |n: u64| n as f64 / elapsed.as_secs_f64();
    let busiest: Vec<String> = busiest
        .iter()
        .take(3)
        .map(|(n, name)| format!("{name} {:.1}/s", per_second(*n)))
        .collect();
    format!(
        "wake-ups/s: ours {:.1}{}, DDS stack {:.1}",
        per_second(ours),
        if busiest.is_empty() {
            String::new()
        } else {
            format!(" ({})", busiest.join(", "))
        },
        per_second(dds)
    )
}

/// The kernel's id of the calling thread.
fn current_tid() -> u32 {
    std::fs::read_link("/proc/thread-self")
        .ok()
        .and_then(|p| p.file_name()?.to_str()?.parse().ok())
        .unwrap_or(0)
}

fn idle_child(backend: Backend) {
    let node = context(backend, 71)
        .create_node("idle_node", "/")
        .expect("node");
    let me = current_tid();
    let measure = |label: &str| {
        thread::sleep(Duration::from_secs(1));
        let (cpu0, _) = cpu_and_threads();
        let switches0 = thread_switches();
        let t = Instant::now();
        thread::sleep(IDLE_MEASURE);
        let elapsed = t.elapsed();
        let switches1 = thread_switches();
        let (cpu1, threads) = cpu_and_threads();
        println!(
            "  {backend:>8} idle {label:<28}: {:>5.2} % of one CPU, {threads} threads, {}",
            100.0 * (cpu1 - cpu0) / elapsed.as_secs_f64(),
            wakeups(&switches0, &switches1, elapsed, me)
        );
    };
    measure("context + node");
    let services = NodeServices::start(&node).expect("node services");
    measure("context + node + NodeServices");
    drop(services);
}

fn idle(backend: Backend) {
    let exe = std::env::current_exe().expect("current exe");
    let out = std::process::Command::new(exe)
        .env(IDLE_CHILD_ENV, backend.to_string())
        .output()
        .expect("idle child");
    print!("{}", String::from_utf8_lossy(&out.stdout));
    if !out.status.success() {
        println!(
            "  {backend:>8} idle measurement failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

fn main() {
    refuse_outside_namespace();
    if std::env::var_os("CYCLONEDDS_URI").is_none() {
        std::env::set_var("CYCLONEDDS_URI", CYCLONE_LOOPBACK);
    }
    if let Ok(backend) = std::env::var(IDLE_CHILD_ENV) {
        idle_child(backend.parse().expect("backend"));
        return;
    }
    thread::spawn(|| {
        thread::sleep(WATCHDOG);
        eprintln!("reliability: stalled for {WATCHDOG:?}; aborting");
        std::process::exit(3);
    });
    let calls = env_usize("HORUS_BENCH_RELIABILITY_CALLS", DEFAULT_CALLS);
    let per_context = env_usize(
        "HORUS_BENCH_RELIABILITY_PER_CONTEXT",
        DEFAULT_CLIENTS_PER_CONTEXT,
    );
    let client_counts: Vec<usize> = std::env::var("HORUS_BENCH_RELIABILITY_CLIENTS")
        .ok()
        .map(|v| v.split(',').filter_map(|n| n.trim().parse().ok()).collect())
        .filter(|v: &Vec<usize>| !v.is_empty())
        .unwrap_or_else(|| vec![8, 64]);
    let phase = Duration::from_secs(env_usize(
        "HORUS_BENCH_RELIABILITY_PHASE_SECS",
        DEFAULT_PHASE_SECS,
    ) as u64);
    let only = std::env::var("HORUS_BENCH_RELIABILITY_ONLY").unwrap_or_default();
    let wanted = |v: &str| only.is_empty() || only.split(',').any(|o| o.trim() == v);
    let backends: Vec<Backend> = Backend::ALL
        .iter()
        .copied()
        .filter(|b| b.is_available() && *b != Backend::Zenoh)
        .filter(|b| {
            std::env::var("HORUS_BENCH_RELIABILITY_BACKENDS").map_or(true, |only| {
                only.split(',').any(|o| o.trim() == b.to_string())
            })
        })
        .collect();
    println!(
        "reliability: backends {}; CPUs {}",
        backends
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", "),
        thread::available_parallelism().map_or(0, |n| n.get())
    );
    let mut domain = 72;
    if wanted("clients") {
        println!("many clients ({per_context} per context), one server, {CALL_TIMEOUT:?} timeout:");
        for &backend in &backends {
            for &clients in &client_counts {
                domain += 1;
                print_many(
                    backend,
                    &many_clients(backend, domain, clients, per_context, calls),
                );
            }
        }
    }
    if wanted("hostile") {
        println!(
            "one good client (a call every {GOOD_CALL_PERIOD:?} for {phase:?} per phase) and a \
             hostile peer:"
        );
        for &backend in &backends {
            domain += 1;
            hostile(backend, domain, phase);
        }
    }
    if wanted("idle") {
        println!("idle process ({IDLE_MEASURE:?} each, /proc/self/stat):");
        for &backend in &backends {
            idle(backend);
        }
    }
}
