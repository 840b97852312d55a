//! `horus-ros service bench`: round-trip latency and throughput of any live server, of any
//! type (compiled in, or described by the server's node through `~/get_type_description`).
//!
//! ```text
//! service bench /add_two_ints (example_interfaces/srv/AddTwoInts): 1000 calls, 1 client, 10 warm-up calls each
//! round trip: p50 95.1 µs, p99 210.3 µs, max 1.02 ms
//! throughput: 9876 calls/s (0.101 s)
//! failed:     0
//! ```
//!
//! Each client is a [`DynamicServiceClient`] of its own on the CLI's node, on a thread of its
//! own, making its share of the calls one after the other; the same request (from `values`,
//! as `service call` fills it) every time. Warm-up calls are made and not measured.

use std::time::{Duration, Instant};

use serde_json::json;

use super::call::{call_error, Opened, Target};
use crate::session::Session;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `service bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Name of the ROS service to benchmark (e.g. '/add_two_ints').
    pub service_name: String,
    /// Values to fill the service request with in YAML format (e.g. '{a: 1, b: 2}'), otherwise
    /// the request has default values.
    #[arg(default_value = "{}")]
    pub values: String,
    /// Type of the service (e.g. 'example_interfaces/srv/AddTwoInts'); by default, the one type
    /// the graph lists for it.
    #[arg(long = "type", value_name = "TYPE")]
    pub service_type: Option<String>,
    /// Calls to measure, in all.
    #[arg(short = 'n', long, value_name = "N", default_value_t = 1000,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub calls: u64,
    /// Clients calling at once (each on a thread of its own).
    #[arg(short = 'c', long, value_name = "CLIENTS", default_value_t = 1,
          value_parser = clap::value_parser!(u64).range(1..=1024))]
    pub clients: u64,
    /// Calls each client makes first, not measured.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub warmup: u64,
    /// Longest wait for a server to appear, and for each reply, in seconds.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 10.0,
        allow_negative_numbers = true,
        value_parser = crate::args::seconds
    )]
    pub timeout: f64,
}

/// What one client measured.
#[derive(Default)]
struct ClientRun {
    latencies: Vec<Duration>,
    failures: Vec<String>,
}

/// Runs `service bench`.
pub fn run(global: &Global, args: &BenchArgs) -> Result<(), CliError> {
    let timeout = Duration::from_secs_f64(args.timeout);
    let opened = match &args.service_type {
        Some(service_type) => {
            let target = Target::prepare(service_type, &args.values)?;
            target.open(global, &args.service_name, timeout)?
        }
        None => {
            let session = Session::open(global)?;
            let service_type = graph_type(&session, &args.service_name, timeout)?;
            let target = Target::prepare(&service_type, &args.values)?;
            target.open_in(session, &args.service_name, timeout)?
        }
    };
    // Every client first checks that the server answers and that the reply decodes.
    let mut clients = Vec::new();
    for _ in 0..args.clients {
        let mut client = opened.client()?;
        let reply = client
            .call(opened.body.clone(), timeout)
            .map_err(|e| call_error(e, &opened.service, timeout))?;
        opened.response_repr(&reply)?;
        clients.push(client);
    }
    let per_client = split(args.calls, args.clients);
    let started = Instant::now();
    let runs: Vec<ClientRun> = std::thread::scope(|scope| {
        let handles: Vec<_> = clients
            .into_iter()
            .zip(per_client)
            .map(|(mut client, calls)| {
                let opened = &opened;
                scope.spawn(move || {
                    let mut run = ClientRun::default();
                    for i in 0..args.warmup + calls {
                        let start = Instant::now();
                        let result = client.call(opened.body.clone(), timeout);
                        let took = start.elapsed();
                        if i < args.warmup {
                            continue;
                        }
                        match result {
                            Ok(_) => run.latencies.push(took),
                            Err(e) => run
                                .failures
                                .push(call_error(e, &opened.service, timeout).message),
                        }
                    }
                    run
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_default())
            .collect()
    });
    let elapsed = started.elapsed();
    report(global, &opened, args, &runs, elapsed)
}

/// The type of `service_name` from the graph: the one type its servers have.
fn graph_type(
    session: &Session,
    service_name: &str,
    timeout: Duration,
) -> Result<String, CliError> {
    let service = horus_ros_rmw::names::ServiceName::expand(
        service_name,
        session.node.name(),
        session.node.namespace(),
    )
    .map_err(|e| CliError::new(format!("Invalid service name '{service_name}': {e}")))?;
    let types = |session: &Session| -> Vec<String> {
        session.graph.read(|c| {
            c.servers_info_by_service(service.as_str(), false)
                .map(|servers| {
                    let mut types: Vec<String> =
                        servers.into_iter().map(|s| s.service_type).collect();
                    types.sort();
                    types.dedup();
                    types
                })
                .unwrap_or_default()
        })
    };
    let deadline = Instant::now() + timeout;
    loop {
        let seen = session.graph.generation();
        match types(session).as_slice() {
            [one] => return Ok(one.clone()),
            [] => {}
            many => {
                return Err(CliError::new(format!(
                    "Servers of {service} have several types ({}): choose one with --type",
                    many.join(", ")
                )))
            }
        }
        let now = Instant::now();
        if now >= deadline {
            return Err(CliError::new(format!(
                "No server of {service} appeared within {} s",
                timeout.as_secs_f64()
            )));
        }
        session
            .graph
            .wait_for_graph_change_since(seen, deadline - now);
    }
}

/// `calls` split over `clients` as evenly as can be.
fn split(calls: u64, clients: u64) -> Vec<u64> {
    (0..clients)
        .map(|i| calls / clients + u64::from(i < calls % clients))
        .collect()
}

/// The `q` quantile (0..=1) of sorted `values`, nearest rank.
fn quantile(sorted: &[Duration], q: f64) -> Duration {
    if sorted.is_empty() {
        return Duration::ZERO;
    }
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// A duration in µs below 1 ms, else in ms.
fn human(d: Duration) -> String {
    let us = d.as_secs_f64() * 1e6;
    if us < 1000.0 {
        format!("{us:.1} µs")
    } else {
        format!("{:.2} ms", us / 1000.0)
    }
}

fn report(
    global: &Global,
    opened: &Opened,
    args: &BenchArgs,
    runs: &[ClientRun],
    elapsed: Duration,
) -> Result<(), CliError> {
    let mut latencies: Vec<Duration> = runs.iter().flat_map(|r| r.latencies.clone()).collect();
    latencies.sort();
    let failures: Vec<&String> = runs.iter().flat_map(|r| &r.failures).collect();
    let (p50, p99) = (quantile(&latencies, 0.5), quantile(&latencies, 0.99));
    let max = latencies.last().copied().unwrap_or_default();
    let calls_per_s = latencies.len() as f64 / elapsed.as_secs_f64().max(f64::EPSILON);
    if global.json {
        return names::print_json(&json!({
            "service": opened.service.as_str(),
            "type": opened.service_type,
            "clients": args.clients,
            "calls": args.calls,
            "warmup": args.warmup,
            "succeeded": latencies.len(),
            "failed": failures.len(),
            "p50_us": p50.as_secs_f64() * 1e6,
            "p99_us": p99.as_secs_f64() * 1e6,
            "max_us": max.as_secs_f64() * 1e6,
            "calls_per_s": calls_per_s,
            "seconds": elapsed.as_secs_f64(),
        }));
    }
    println!(
        "service bench {} ({}): {} calls, {} client{}, {} warm-up call{} each",
        opened.service,
        opened.service_type,
        args.calls,
        args.clients,
        if args.clients == 1 { "" } else { "s" },
        args.warmup,
        if args.warmup == 1 { "" } else { "s" },
    );
    println!(
        "round trip: p50 {}, p99 {}, max {}",
        human(p50),
        human(p99),
        human(max)
    );
    println!(
        "throughput: {calls_per_s:.0} calls/s ({:.3} s)",
        elapsed.as_secs_f64()
    );
    println!("failed:     {}", failures.len());
    if let Some(first) = failures.first() {
        println!("first failure: {first}");
    }
    if failures.is_empty() {
        Ok(())
    } else {
        Err(CliError::new(format!(
            "{} of {} calls failed",
            failures.len(),
            args.calls
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calls_are_split_evenly() {
        assert_eq!(split(10, 3), vec![4, 3, 3]);
        assert_eq!(split(2, 4), vec![1, 1, 0, 0]);
        assert_eq!(split(8, 1), vec![8]);
    }

    #[test]
    fn quantiles_are_nearest_rank() {
        let v: Vec<Duration> = (1..=100).map(Duration::from_micros).collect();
        assert_eq!(quantile(&v, 0.5), Duration::from_micros(50));
        assert_eq!(quantile(&v, 0.99), Duration::from_micros(99));
        assert_eq!(quantile(&v, 1.0), Duration::from_micros(100));
        assert_eq!(quantile(&[], 0.5), Duration::ZERO);
    }

    #[test]
    fn durations_read_as_people_write_them() {
        assert_eq!(human(Duration::from_nanos(95_140)), "95.1 µs");
        assert_eq!(human(Duration::from_micros(1_020)), "1.02 ms");
    }
}
