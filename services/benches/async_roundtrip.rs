//! Awaited versus blocking service calls (feature `tokio`; not a test). Opens DDS participants:
//! run it only inside a private network namespace, e.g. `scripts/bench` or
//! `scripts/isolated cargo bench -p horus-ros-services --bench async_roundtrip`. It refuses to
//! run when it can see a network interface other than `lo` up.
//!
//! Per backend (rustdds; Cyclone DDS when built with the feature `cyclone`, as scripts/bench does),
//! server and clients in two `Context`s (two DDS participants, as two processes would have),
//! blocking `ServiceServer`s (AddTwoInts; one for the sequential calls, one for the 16 clients:
//! on the Cyclone backend a server sends each reply to every reply reader of its service), in one
//! run and interleaved in rounds so that every variant sees the same machine state:
//! 1. sequential round trips: blocking `ServiceClient::call` versus `AsyncServiceClient::call(..)
//!    .await` from a task of a tokio multi-thread runtime: p50, p99, calls per second, and the
//!    ratio awaited / blocking of the p50s (goal: within 10 %, i.e. ≤ 1.10);
//! 2. 16 clients calling at once, each its own client, sequential calls each: 16 std threads
//!    calling blocking versus 16 tokio tasks awaiting: calls per second in all, and the ratio;
//! 3. for information, the same 16 awaited clients against an async server (handlers on the
//!    runtime: `AsyncServiceServer::builder`).
//!
//! Environment: `HORUS_BENCH_ASYNC_CALLS` (measured sequential calls per variant, default
//! 20000), `HORUS_BENCH_ASYNC_ROUNDS` (default 10), `HORUS_BENCH_ASYNC_CONCURRENT_CALLS` (calls
//! per client in each concurrent round, default 300), `HORUS_BENCH_ASYNC_WORKERS` (the runtime's
//! worker threads, default one per CPU as `#[tokio::main]`); `CYCLONEDDS_URI` (a loopback one is set if
//! unset).

use horus_ros_test_support::bench::{env_usize, percentile};
use std::sync::{Arc, Barrier};
use std::thread;
use std::time::{Duration, Instant};

use horus_ros_rmw::Backend;
use horus_ros_services::prelude::*;

const WARMUP: usize = 500;
const CALL_TIMEOUT: Duration = Duration::from_secs(10);
const DISCOVERY_TIMEOUT: Duration = Duration::from_secs(20);
const WATCHDOG: Duration = Duration::from_secs(400);
const CLIENTS: usize = 16;
/// Domains used (one per backend).
const DOMAIN_RUSTDDS: u32 = 66;
const DOMAIN_CYCLONE: u32 = 67;
/// The Cyclone DDS configuration used when `CYCLONEDDS_URI` is unset: loopback, with multicast.
const CYCLONE_LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

fn refuse_outside_namespace() {
    horus_ros_test_support::bench::refuse_outside_namespace(
        "async_roundtrip",
        "scripts/isolated cargo bench -p horus-ros-services --bench async_roundtrip",
    );
}

fn micros(d: Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

#[derive(Default)]
struct Latencies(Vec<Duration>);

impl Latencies {
    fn summary(&self) -> (Duration, Duration, f64) {
        let mut sorted = self.0.clone();
        sorted.sort_unstable();
        let total: Duration = sorted.iter().sum();
        (
            percentile(&sorted, 50.0),
            percentile(&sorted, 99.0),
            sorted.len() as f64 / total.as_secs_f64().max(1e-9),
        )
    }
}

/// One backend's endpoints: the servers, a blocking client, an awaited client, and the 16 of
/// each for the concurrent rounds.
struct Setup {
    _servers: Vec<ServiceServer<AddTwoInts>>,
    _async_server: AsyncServiceServer<AddTwoInts>,
    blocking: ServiceClient<AddTwoInts>,
    awaited: Arc<AsyncServiceClient<AddTwoInts>>,
    blocking_many: Vec<ServiceClient<AddTwoInts>>,
    awaited_many: Vec<Arc<AsyncServiceClient<AddTwoInts>>>,
    awaited_many_async_server: Vec<Arc<AsyncServiceClient<AddTwoInts>>>,
    _nodes: Vec<Node>,
}

fn check(reply: Result<AddTwoIntsResponse, ServiceError>, i: i64) {
    match reply {
        Ok(r) if r.sum == i + 1 => {}
        other => panic!("call {i}: {other:?}"),
    }
}

impl Setup {
    fn start(
        runtime: &tokio::runtime::Runtime,
        backend: Backend,
        domain: u32,
    ) -> Result<Self, String> {
        let context = || {
            Context::builder()
                .domain_id(domain)
                .backend(backend)
                .build()
                .map_err(|e| format!("context: {e}"))
        };
        let (server_context, client_context) = (context()?, context()?);
        let server_node = server_context
            .create_node("bench_server", "/")
            .map_err(|e| format!("node: {e}"))?;
        let client_node = client_context
            .create_node("bench_client", "/")
            .map_err(|e| format!("node: {e}"))?;
        // One service for the sequential calls, another for the 16 clients: on the Cyclone
        // backend a server sends each reply to every reply reader of the service.
        let blocking_server = |name: &str| {
            ServiceServer::<AddTwoInts>::builder()
                .node(&server_node)
                .name(name)
                .on_request(|req| {
                    Ok(AddTwoIntsResponse {
                        sum: req.a.wrapping_add(req.b),
                    })
                })
                .build()
                .map_err(|e| format!("server: {e}"))
        };
        let servers = vec![
            blocking_server("/bench_async")?,
            blocking_server("/bench_async_many")?,
        ];
        let async_server = AsyncServiceServer::<AddTwoInts>::builder()
            .node(&server_node)
            .name("/bench_async_handlers")
            .on_request(|req| async move {
                Ok(AddTwoIntsResponse {
                    sum: req.a.wrapping_add(req.b),
                })
            })
            .runtime(runtime.handle().clone())
            .build()
            .map_err(|e| format!("async server: {e}"))?;
        let blocking_client = |name: &str| {
            ServiceClient::<AddTwoInts>::builder()
                .node(&client_node)
                .name(name)
                .build()
                .map_err(|e| format!("client: {e}"))
        };
        let awaited_client = |name: &str| {
            AsyncServiceClient::<AddTwoInts>::builder()
                .node(&client_node)
                .name(name)
                .build()
                .map(Arc::new)
                .map_err(|e| format!("client: {e}"))
        };
        let setup = Self {
            blocking: blocking_client("/bench_async")?,
            awaited: awaited_client("/bench_async")?,
            blocking_many: (0..CLIENTS)
                .map(|_| blocking_client("/bench_async_many"))
                .collect::<Result<_, _>>()?,
            awaited_many: (0..CLIENTS)
                .map(|_| awaited_client("/bench_async_many"))
                .collect::<Result<_, _>>()?,
            awaited_many_async_server: (0..CLIENTS)
                .map(|_| awaited_client("/bench_async_handlers"))
                .collect::<Result<_, _>>()?,
            _servers: servers,
            _async_server: async_server,
            _nodes: vec![server_node, client_node],
        };
        runtime.block_on(async {
            let waits = setup
                .awaited_many
                .iter()
                .chain(&setup.awaited_many_async_server)
                .chain(std::iter::once(&setup.awaited))
                .map(|c| c.wait_for_service_async(DISCOVERY_TIMEOUT));
            for ready in futures_util::future::join_all(waits).await {
                if !ready {
                    return Err(format!("no server within {DISCOVERY_TIMEOUT:?}"));
                }
            }
            Ok(())
        })?;
        for c in &setup.blocking_many {
            if !c.wait_for_service(DISCOVERY_TIMEOUT) {
                return Err(format!("no server within {DISCOVERY_TIMEOUT:?}"));
            }
        }
        Ok(setup)
    }

    fn blocking_round(&mut self, calls: usize) -> Vec<Duration> {
        let mut samples = Vec::with_capacity(calls);
        for i in 0..calls as i64 {
            let start = Instant::now();
            let reply = self
                .blocking
                .call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT);
            samples.push(start.elapsed());
            check(reply, i);
        }
        samples
    }

    fn awaited_round(&self, runtime: &tokio::runtime::Runtime, calls: usize) -> Vec<Duration> {
        let client = Arc::clone(&self.awaited);
        // From a task of the runtime (not block_on's thread), as an application's code runs.
        runtime
            .block_on(runtime.spawn(async move {
                let mut samples = Vec::with_capacity(calls);
                for i in 0..calls as i64 {
                    let start = Instant::now();
                    let reply = client
                        .call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT)
                        .await;
                    samples.push(start.elapsed());
                    check(reply, i);
                }
                samples
            }))
            .expect("awaited round")
    }

    /// 16 threads, each calling with its own blocking client: calls per second in all.
    fn blocking_concurrent(&mut self, per_client: usize) -> f64 {
        let start_line = Arc::new(Barrier::new(CLIENTS + 1));
        let elapsed = thread::scope(|scope| {
            for client in &mut self.blocking_many {
                let start_line = Arc::clone(&start_line);
                scope.spawn(move || {
                    start_line.wait();
                    for i in 0..per_client as i64 {
                        check(
                            client.call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT),
                            i,
                        );
                    }
                });
            }
            start_line.wait();
            Instant::now()
        })
        .elapsed();
        (CLIENTS * per_client) as f64 / elapsed.as_secs_f64()
    }

    /// 16 tasks, each awaiting calls of its own client: calls per second in all.
    fn awaited_concurrent(
        runtime: &tokio::runtime::Runtime,
        clients: &[Arc<AsyncServiceClient<AddTwoInts>>],
        per_client: usize,
    ) -> f64 {
        let start = Instant::now();
        runtime.block_on(async {
            let tasks: Vec<_> = clients
                .iter()
                .map(|client| {
                    let client = Arc::clone(client);
                    tokio::spawn(async move {
                        for i in 0..per_client as i64 {
                            check(
                                client
                                    .call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT)
                                    .await,
                                i,
                            );
                        }
                    })
                })
                .collect();
            for task in tasks {
                task.await.expect("task");
            }
        });
        (clients.len() * per_client) as f64 / start.elapsed().as_secs_f64()
    }
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

fn main() {
    refuse_outside_namespace();
    if std::env::var_os("CYCLONEDDS_URI").is_none() {
        std::env::set_var("CYCLONEDDS_URI", CYCLONE_LOOPBACK);
    }
    thread::spawn(|| {
        thread::sleep(WATCHDOG);
        eprintln!("async_roundtrip: stalled for {WATCHDOG:?}; aborting");
        std::process::exit(3);
    });
    let calls = env_usize("HORUS_BENCH_ASYNC_CALLS", 20_000);
    let rounds = env_usize("HORUS_BENCH_ASYNC_ROUNDS", 10).min(calls);
    let per_client = env_usize("HORUS_BENCH_ASYNC_CONCURRENT_CALLS", 300);
    // As `#[tokio::main]` makes it: one worker per CPU, unless told otherwise.
    let workers = env_usize(
        "HORUS_BENCH_ASYNC_WORKERS",
        thread::available_parallelism().map_or(2, usize::from),
    );
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(workers)
        .enable_all()
        .build()
        .expect("tokio runtime");
    let mut backends = vec![(Backend::RustDds, DOMAIN_RUSTDDS)];
    if cfg!(feature = "cyclone") {
        backends.push((Backend::Cyclone, DOMAIN_CYCLONE));
    } else {
        println!("(Cyclone DDS: not built; cargo bench -p horus-ros-services --features cyclone)");
    }
    println!(
        "async_roundtrip: {calls} sequential calls per variant in {rounds} rounds, {CLIENTS} \
         concurrent clients × {per_client} calls per round; tokio multi-thread runtime with \
         {workers} workers; load {}",
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    for (backend, domain) in backends {
        let mut setup = match Setup::start(&runtime, backend, domain) {
            Ok(setup) => setup,
            Err(e) => {
                println!("{backend}: could not start: {e}");
                continue;
            }
        };
        setup.blocking_round(WARMUP);
        setup.awaited_round(&runtime, WARMUP);
        let (mut blocking, mut awaited) = (Latencies::default(), Latencies::default());
        let (mut blocking_many, mut awaited_many, mut awaited_async_server) =
            (Vec::new(), Vec::new(), Vec::new());
        for round in 0..rounds {
            let n = calls / rounds;
            // Alternate which goes first.
            if round % 2 == 0 {
                blocking.0.extend(setup.blocking_round(n));
                awaited.0.extend(setup.awaited_round(&runtime, n));
            } else {
                awaited.0.extend(setup.awaited_round(&runtime, n));
                blocking.0.extend(setup.blocking_round(n));
            }
            blocking_many.push(setup.blocking_concurrent(per_client));
            awaited_many.push(Setup::awaited_concurrent(
                &runtime,
                &setup.awaited_many,
                per_client,
            ));
            awaited_async_server.push(Setup::awaited_concurrent(
                &runtime,
                &setup.awaited_many_async_server,
                per_client,
            ));
        }
        let (bp50, bp99, bps) = blocking.summary();
        let (ap50, ap99, aps) = awaited.summary();
        let ratio = micros(ap50) / micros(bp50).max(1e-9);
        println!("\n== {backend} (2 contexts) ==");
        println!(
            "  blocking call        p50 {:8.1} µs  p99 {:8.1} µs  {:9.0} calls/s",
            micros(bp50),
            micros(bp99),
            bps
        );
        println!(
            "  awaited call (tokio) p50 {:8.1} µs  p99 {:8.1} µs  {:9.0} calls/s",
            micros(ap50),
            micros(ap99),
            aps
        );
        println!(
            "  ratio awaited / blocking p50: {ratio:.3} (goal ≤ 1.10: {})",
            if ratio <= 1.10 { "MET" } else { "NOT MET" }
        );
        let (bm, am, asm) = (
            median(blocking_many),
            median(awaited_many),
            median(awaited_async_server),
        );
        println!("  {CLIENTS} blocking threads          {bm:9.0} calls/s (median of rounds)");
        println!(
            "  {CLIENTS} awaited tasks             {am:9.0} calls/s (ratio {:.3})",
            am / bm.max(1e-9)
        );
        println!(
            "  {CLIENTS} awaited tasks, async server {asm:9.0} calls/s (ratio {:.3})",
            asm / bm.max(1e-9)
        );
    }
}
