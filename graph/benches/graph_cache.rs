//! Benchmark of the graph cache (not a test; `cargo bench -p horus-ros-graph`).
//!
//! Builds a synthetic ROS 2 graph of 1,000 participants and 10,000 endpoints the way DDS
//! discovery feeds it (participant, its readers and writers, then its `ros_discovery_info`),
//! then prints the ingest time, the memory it takes (process RSS before/after, approximate)
//! and the median / p99 latency of every query, next to the cost of a trivial linear scan
//! over 10,000 entries measured in the same run. Goal (issue 3): `servers_info_by_service`
//! ≤ 5 µs at this size.

use std::hint::black_box;
use std::time::{Duration, Instant};

use horus_ros_graph::{participant_gid_from_prefix, EndpointEntry, Gid, GraphCache};
use horus_ros_msgs::rmw_dds_common::{NodeEntitiesInfo, ParticipantEntitiesInfo};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::{EndpointKind, Qos};

const PARTICIPANTS: usize = 1_000;
const ENDPOINTS_PER_PARTICIPANT: usize = 10;
const TOPIC_POOL: usize = 1_000;
const SERVICE_POOL: usize = 1_500;
const GOAL: Duration = Duration::from_micros(5);

const MESSAGE_TYPES: [&str; 8] = [
    "std_msgs::msg::dds_::String_",
    "sensor_msgs::msg::dds_::Image_",
    "sensor_msgs::msg::dds_::LaserScan_",
    "geometry_msgs::msg::dds_::Twist_",
    "nav_msgs::msg::dds_::Odometry_",
    "tf2_msgs::msg::dds_::TFMessage_",
    "sensor_msgs::msg::dds_::Imu_",
    "std_msgs::msg::dds_::Header_",
];
const SERVICE_TYPES: [&str; 4] = [
    "example_interfaces::srv::dds_::AddTwoInts_",
    "std_srvs::srv::dds_::SetBool_",
    "std_srvs::srv::dds_::Trigger_",
    "rcl_interfaces::srv::dds_::GetParameters_",
];
const LOG_TYPE: &str = "rcl_interfaces::msg::dds_::Log_";
const DISCOVERY_TYPE: &str = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

/// xorshift64: a deterministic graph on every run.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

/// A type hash made from a small number (the value's bytes are arbitrary but distinct).
fn type_hash(n: usize) -> TypeHash {
    let mut value = [0u8; 32];
    for (i, v) in value.iter_mut().enumerate() {
        *v = (n as u8).wrapping_mul(31).wrapping_add(i as u8);
    }
    TypeHash::rihs01(value)
}

/// What one participant announces: itself, its endpoints, its `ros_discovery_info`.
struct ParticipantInput {
    gid: Gid,
    enclave: Option<String>,
    endpoints: Vec<EndpointEntry>,
    info: ParticipantEntitiesInfo,
}

/// Names that exist in the generated graph, to query.
#[derive(Default)]
struct Names {
    nodes: Vec<(String, String)>,
    topics: Vec<String>,
    services: Vec<String>,
}

fn generate() -> (Vec<ParticipantInput>, Names) {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut names = Names::default();
    let mut served = vec![false; SERVICE_POOL];
    let mut topic_used = vec![false; TOPIC_POOL];
    let mut inputs = Vec::with_capacity(PARTICIPANTS);
    for p in 0..PARTICIPANTS {
        let mut prefix = [0x01, 0x0f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        prefix[2..4].copy_from_slice(&(p as u16).to_be_bytes());
        prefix[4..8].copy_from_slice(&(rng.below(1 << 30) as u32).to_be_bytes());
        let participant_gid = participant_gid_from_prefix(prefix);
        let mut entity = 0u32;
        let mut endpoints = Vec::with_capacity(ENDPOINTS_PER_PARTICIPANT);
        let mut add = |topic: String, ty: &str, kind: EndpointKind, qos: Qos, hash| {
            entity += 1;
            let mut data = [0u8; 16];
            data[..12].copy_from_slice(&prefix);
            data[12..15].copy_from_slice(&entity.to_be_bytes()[1..]);
            data[15] = match kind {
                EndpointKind::Writer => 0x03,
                EndpointKind::Reader => 0x04,
            };
            let gid = Gid::from_bytes(data);
            endpoints.push(EndpointEntry {
                gid,
                participant_gid,
                dds_topic_name: topic,
                dds_type_name: ty.to_owned(),
                qos,
                type_hash: hash,
                kind,
            });
            gid
        };
        // The rmw's own ros_discovery_info reader and writer, listed by no node.
        let discovery = "ros_discovery_info".to_owned();
        add(
            discovery.clone(),
            DISCOVERY_TYPE,
            EndpointKind::Reader,
            Qos::default_profile(),
            TypeHash::ZERO,
        );
        add(
            discovery,
            DISCOVERY_TYPE,
            EndpointKind::Writer,
            Qos::default_profile(),
            TypeHash::ZERO,
        );
        let namespace = format!("/robot{}", p % 50);
        let mut nodes: Vec<NodeEntitiesInfo> = (0..1 + rng.below(3))
            .map(|n| NodeEntitiesInfo {
                node_namespace: namespace.clone(),
                node_name: format!("node_{p}_{n}"),
                reader_gid_seq: Vec::new(),
                writer_gid_seq: Vec::new(),
            })
            .collect();
        // Every node logs to /rosout.
        for node in &mut nodes {
            let gid = add(
                "rt/rosout".to_owned(),
                LOG_TYPE,
                EndpointKind::Writer,
                Qos::rosout_default(),
                type_hash(100),
            );
            node.writer_gid_seq.push(gid);
            names
                .nodes
                .push((node.node_name.clone(), node.node_namespace.clone()));
        }
        let mut left = ENDPOINTS_PER_PARTICIPANT - 2 - nodes.len();
        while left > 0 {
            let n = rng.below(nodes.len());
            if left >= 2 && rng.below(10) < 4 {
                // A service server (rq reader + rr writer) or client (rr reader + rq writer).
                let is_server = rng.below(2) == 0;
                let mut s = rng.below(SERVICE_POOL);
                if !is_server {
                    // Clients call a served service when there is one nearby.
                    if let Some(k) = (0..20).map(|k| (s + k) % SERVICE_POOL).find(|k| served[*k]) {
                        s = k;
                    }
                }
                let service = format!("/robot{}/svc{s}", s % 50);
                let ty = SERVICE_TYPES[s % SERVICE_TYPES.len()];
                let (request, reply) = (format!("{ty}Request_"), format!("{ty}Response_"));
                let (rq, rr) = (format!("rq{service}Request"), format!("rr{service}Reply"));
                let qos = Qos::services_default();
                let (req_hash, rep_hash) = (type_hash(200 + 2 * s), type_hash(201 + 2 * s));
                let node = &mut nodes[n];
                if is_server {
                    let r = add(rq, &request, EndpointKind::Reader, qos, req_hash);
                    let w = add(rr, &reply, EndpointKind::Writer, qos, rep_hash);
                    node.reader_gid_seq.push(r);
                    node.writer_gid_seq.push(w);
                    if !served[s] {
                        served[s] = true;
                        names.services.push(service);
                    }
                } else {
                    let r = add(rr, &reply, EndpointKind::Reader, qos, rep_hash);
                    let w = add(rq, &request, EndpointKind::Writer, qos, req_hash);
                    node.reader_gid_seq.push(r);
                    node.writer_gid_seq.push(w);
                }
                left -= 2;
            } else {
                let t = rng.below(TOPIC_POOL);
                let topic = format!("rt/robot{}/topic{t}", t % 50);
                let ty = t % MESSAGE_TYPES.len();
                let qos = if ty < 3 {
                    Qos::sensor_data()
                } else {
                    Qos::default_profile()
                };
                let kind = if rng.below(2) == 0 {
                    EndpointKind::Writer
                } else {
                    EndpointKind::Reader
                };
                let gid = add(topic, MESSAGE_TYPES[ty], kind, qos, type_hash(ty));
                match kind {
                    EndpointKind::Writer => nodes[n].writer_gid_seq.push(gid),
                    EndpointKind::Reader => nodes[n].reader_gid_seq.push(gid),
                }
                if !topic_used[t] {
                    topic_used[t] = true;
                    names.topics.push(format!("/robot{}/topic{t}", t % 50));
                }
                left -= 1;
            }
        }
        inputs.push(ParticipantInput {
            gid: participant_gid,
            enclave: Some("/".to_owned()),
            endpoints,
            info: ParticipantEntitiesInfo {
                gid: participant_gid,
                node_entities_info_seq: nodes,
            },
        });
    }
    (inputs, names)
}

/// Feeds a cache as discovery would; returns it and the time taken.
fn ingest(inputs: Vec<ParticipantInput>) -> (GraphCache, Duration) {
    let start = Instant::now();
    let mut g = GraphCache::new();
    for (i, ty) in SERVICE_TYPES.iter().enumerate() {
        let ros = ty.replace("::dds_::", "/").replace("::", "/");
        g.set_service_type_hash(ros.trim_end_matches('_'), type_hash(50 + i));
    }
    for input in inputs {
        g.add_participant(input.gid, input.enclave);
        for e in input.endpoints {
            g.add_entity(e);
        }
        g.update_participant_entities(input.info);
    }
    (g, start.elapsed())
}

/// Resident set size of this process in bytes (Linux `/proc/self/statm`), if readable.
fn rss_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096)
}

/// Per-call latency statistics.
struct Stats {
    median: Duration,
    p99: Duration,
    batch: usize,
    samples: usize,
}

/// Times `f(i)` for i = 0, 1, 2, …: each sample is a batch of calls long enough (≥ 2 µs) for
/// the clock's own cost not to matter, divided by its size. Stops after 2,000 samples or
/// ~250 ms.
fn measure(mut f: impl FnMut(usize)) -> Stats {
    let mut i = 0usize;
    // Warm up, and size the batch.
    let start = Instant::now();
    let mut calls = 0usize;
    while start.elapsed() < Duration::from_millis(20) && calls < 2_000 {
        f(i);
        i += 1;
        calls += 1;
    }
    let per_call = start.elapsed().as_nanos() as f64 / calls as f64;
    let batch = ((2_000.0 / per_call).ceil() as usize).max(1);
    let mut samples = Vec::with_capacity(2_000);
    let budget = Instant::now();
    while samples.len() < 2_000 && budget.elapsed() < Duration::from_millis(250) {
        let t = Instant::now();
        for _ in 0..batch {
            f(i);
            i += 1;
        }
        samples.push(t.elapsed() / batch as u32);
    }
    samples.sort();
    let at = |q: f64| samples[((samples.len() - 1) as f64 * q).round() as usize];
    Stats {
        median: at(0.5),
        p99: at(0.99),
        batch,
        samples: samples.len(),
    }
}

/// Consumes a query's result (dropped inside the timed call, as a caller would).
fn sink<T>(_result: T) {}

fn fmt_duration(d: Duration) -> String {
    let ns = d.as_nanos();
    if ns < 10_000 {
        format!("{ns} ns")
    } else if ns < 10_000_000 {
        format!("{:.1} µs", ns as f64 / 1_000.0)
    } else {
        format!("{:.1} ms", ns as f64 / 1_000_000.0)
    }
}

fn row(name: &str, s: &Stats) {
    println!(
        "{name:<44} {:>10} {:>10} {:>7} {:>8}",
        fmt_duration(s.median),
        fmt_duration(s.p99),
        s.batch,
        s.samples
    );
}

fn main() {
    // `cargo bench` passes `--bench`; any other argument is ignored.
    let rss_before = rss_bytes();
    let (inputs, names) = generate();
    let endpoint_count: usize = inputs.iter().map(|p| p.endpoints.len()).sum();
    let node_count: usize = inputs
        .iter()
        .map(|p| p.info.node_entities_info_seq.len())
        .sum();
    // The baseline scans a copy of the (topic, kind) of every endpoint.
    let scan: Vec<(String, EndpointKind)> = inputs
        .iter()
        .flat_map(|p| p.endpoints.iter())
        .map(|e| (e.dds_topic_name.clone(), e.kind))
        .collect();
    let numbers: Vec<u64> = (0..endpoint_count as u64).collect();
    let rss_inputs = rss_bytes();
    let (g, first_ingest) = ingest(inputs);
    let rss_after = rss_bytes();
    let mut ingests = vec![first_ingest];
    for _ in 0..4 {
        let (again, t) = ingest(generate().0);
        black_box(&again);
        ingests.push(t);
    }
    ingests.sort();
    let ingest_median = ingests[ingests.len() / 2];

    println!();
    println!(
        "graph: {PARTICIPANTS} participants, {node_count} nodes, {endpoint_count} endpoints, \
         {} topics, {} served services",
        names.topics.len(),
        names.services.len()
    );
    println!(
        "ingest: {} total (median of {}), {} per endpoint",
        fmt_duration(ingest_median),
        ingests.len(),
        fmt_duration(ingest_median / endpoint_count as u32)
    );
    match (rss_before, rss_inputs, rss_after) {
        (Some(before), Some(_), Some(after)) => println!(
            "memory: RSS {:.1} MiB before generating the inputs, {:.1} MiB with the cache built \
             (inputs moved into it): ≈ {:.1} MiB, ≈ {} bytes per endpoint (approximate)",
            before as f64 / 1_048_576.0,
            after as f64 / 1_048_576.0,
            after.saturating_sub(before) as f64 / 1_048_576.0,
            after.saturating_sub(before) / endpoint_count as u64
        ),
        _ => println!("memory: /proc/self/statm not readable"),
    }
    println!();
    println!(
        "{:<44} {:>10} {:>10} {:>7} {:>8}",
        "query (per call)", "median", "p99", "batch", "samples"
    );
    println!("{}", "-".repeat(83));

    let node = |i: usize| &names.nodes[(i * 7919) % names.nodes.len()];
    let topic = |i: usize| &names.topics[(i * 7919) % names.topics.len()];
    let service = |i: usize| &names.services[(i * 7919) % names.services.len()];

    let baseline = measure(|i| {
        let target = &scan[i % scan.len()].0;
        black_box(
            scan.iter()
                .filter(|(t, k)| *k == EndpointKind::Writer && t == target)
                .count(),
        );
    });
    row("baseline: scan 10,000 (topic, kind) ==", &baseline);
    let sum = measure(|i| {
        black_box(numbers.iter().fold(i as u64, |a, b| a.wrapping_add(*b)));
    });
    row("baseline: sum 10,000 u64", &sum);

    row("node_names", &measure(|_| sink(black_box(g.node_names()))));
    row("node_count", &measure(|_| sink(black_box(g.node_count()))));
    row(
        "topic_names_and_types(false)",
        &measure(|_| sink(black_box(g.topic_names_and_types(false)))),
    );
    row(
        "service_names_and_types(false)",
        &measure(|_| sink(black_box(g.service_names_and_types(false)))),
    );
    row(
        "publisher_names_and_types_by_node",
        &measure(|i| {
            let (n, ns) = node(i);
            sink(black_box(g.publisher_names_and_types_by_node(n, ns)));
        }),
    );
    row(
        "subscription_names_and_types_by_node",
        &measure(|i| {
            let (n, ns) = node(i);
            sink(black_box(g.subscription_names_and_types_by_node(n, ns)));
        }),
    );
    row(
        "service_names_and_types_by_node",
        &measure(|i| {
            let (n, ns) = node(i);
            sink(black_box(g.service_names_and_types_by_node(n, ns)));
        }),
    );
    row(
        "client_names_and_types_by_node",
        &measure(|i| {
            let (n, ns) = node(i);
            sink(black_box(g.client_names_and_types_by_node(n, ns)));
        }),
    );
    row(
        "count_publishers",
        &measure(|i| sink(black_box(g.count_publishers(topic(i))))),
    );
    row(
        "count_subscribers",
        &measure(|i| sink(black_box(g.count_subscribers(topic(i))))),
    );
    row(
        "count_services",
        &measure(|i| sink(black_box(g.count_services(service(i))))),
    );
    row(
        "count_clients",
        &measure(|i| sink(black_box(g.count_clients(service(i))))),
    );
    row(
        "publishers_info_by_topic",
        &measure(|i| sink(black_box(g.publishers_info_by_topic(topic(i), false)))),
    );
    row(
        "subscriptions_info_by_topic",
        &measure(|i| sink(black_box(g.subscriptions_info_by_topic(topic(i), false)))),
    );
    let rosout = g.publishers_info_by_topic("/rosout", false).len();
    row(
        &format!("publishers_info_by_topic(/rosout: {rosout})"),
        &measure(|_| sink(black_box(g.publishers_info_by_topic("/rosout", false)))),
    );
    let servers = measure(|i| sink(black_box(g.servers_info_by_service(service(i), false))));
    row("servers_info_by_service", &servers);
    row(
        "clients_info_by_service",
        &measure(|i| sink(black_box(g.clients_info_by_service(service(i), false)))),
    );
    row(
        "service_is_available",
        &measure(|i| sink(black_box(g.service_is_available(service(i))))),
    );
    row(
        "servers_info_by_service (unknown name)",
        &measure(|i| {
            sink(black_box(
                g.servers_info_by_service(&format!("/none{}", i % 64), false),
            ))
        }),
    );
    println!("{}", "-".repeat(83));
    println!(
        "servers_info_by_service median {} vs goal {}: {} ({:.1}x the goal; a 10,000-entry scan \
         takes {} here)",
        fmt_duration(servers.median),
        fmt_duration(GOAL),
        if servers.median <= GOAL {
            "MET"
        } else {
            "NOT MET"
        },
        servers.median.as_nanos() as f64 / GOAL.as_nanos() as f64,
        fmt_duration(baseline.median),
    );
}
