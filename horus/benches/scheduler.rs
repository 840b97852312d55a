//! HORUS scheduler benchmark (figures, not assertions):
//!
//! 1. Scheduler overhead per empty tick and node, for 1, 10 and 100 nodes (no ROS side;
//!    `tick_once` in a loop; least and median of 5 batches). Goal: < 100 ns per node.
//! 2. Tick jitter at 1 kHz: how far each interval between two ticks is from 1 ms (p50/p99/max
//!    of |interval − 1 ms|) for the scheduler's `run`, a plain `thread::sleep(1 ms)` loop and a
//!    busy loop to each next millisecond, in the same run.
//! 3. Round trips: a `Topic` ping-pong between two nodes' topics in one process and across
//!    processes, against an AddTwoInts service round trip (same backend: `HORUS_ROS_BACKEND`).
//!
//! Run it inside the network namespace: `scripts/bench` does (or `scripts/isolated cargo bench
//! -p horus-ros-nodes --bench scheduler`). `HORUS_BENCH_ROUNDS` sets the round trips (default
//! 2000).

use std::time::{Duration, Instant};

use horus::msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
use horus::prelude::*;
use horus::ros::{ServiceClient, ServiceServer};

struct Empty(String);

impl Node for Empty {
    fn name(&self) -> &str {
        &self.0
    }
    fn tick(&mut self) {}
}

/// Nanoseconds per node per empty tick, in 5 batches of `tick_once` calls: (least, median).
/// The least is the scheduler's own cost; the median shows how much a busy machine adds.
fn overhead(nodes: usize) -> (f64, f64) {
    let mut sched = Scheduler::new().without_ros().print_report(false);
    for i in 0..nodes {
        sched.add(Empty(format!("n{i}"))).build().expect("node");
    }
    sched.tick_once().expect("tick");
    let cycles = (400_000 / nodes).max(200);
    let mut batches: Vec<f64> = (0..5)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..cycles {
                sched.tick_once().expect("tick");
            }
            start.elapsed().as_nanos() as f64 / (cycles * nodes) as f64
        })
        .collect();
    batches.sort_by(f64::total_cmp);
    (batches[0], batches[2])
}

fn percentiles(mut v: Vec<Duration>) -> String {
    v.sort();
    let at = |q: f64| v[((v.len() - 1) as f64 * q) as usize].as_secs_f64() * 1e6;
    format!(
        "p50 {:>8.1} µs  p99 {:>8.1} µs  max {:>8.1} µs",
        at(0.5),
        at(0.99),
        at(1.0)
    )
}

/// |interval − 1 ms| for each pair of consecutive instants.
fn interval_errors(times: &[Instant]) -> Vec<Duration> {
    let period = Duration::from_millis(1);
    times
        .windows(2)
        .map(|w| (w[1] - w[0]).abs_diff(period))
        .collect()
}

struct Recorder {
    times: Vec<Instant>,
    n: u32,
    stop: horus::StopHandle,
}

impl Node for Recorder {
    fn name(&self) -> &str {
        "recorder"
    }
    fn tick(&mut self) {
        self.times.push(Instant::now());
        self.n += 1;
        if self.n >= 2000 {
            self.stop.stop();
        }
    }
}

fn jitter() {
    const N: u32 = 2000;
    let period = Duration::from_millis(1);
    // The scheduler.
    let mut sched = Scheduler::new()
        .without_ros()
        .print_report(false)
        .tick_rate(1000_u64.hz());
    let stop = sched.stop_handle();
    let (tx, rx) = std::sync::mpsc::channel();
    struct Send(std::sync::mpsc::Sender<Vec<Instant>>, Recorder);
    impl Node for Send {
        fn name(&self) -> &str {
            "recorder"
        }
        fn tick(&mut self) {
            self.1.tick();
            if self.1.n >= 2000 {
                let _ = self.0.send(std::mem::take(&mut self.1.times));
            }
        }
    }
    sched
        .add(Send(
            tx,
            Recorder {
                times: Vec::new(),
                n: 0,
                stop,
            },
        ))
        .build()
        .expect("node");
    sched.run().expect("run");
    let sched_times = rx.recv().expect("samples");
    // thread::sleep(1 ms) loop.
    let mut sleep_times = Vec::new();
    for _ in 0..N {
        sleep_times.push(Instant::now());
        std::thread::sleep(period);
    }
    // Busy loop to each next millisecond.
    let start = Instant::now();
    let mut busy_times = Vec::new();
    for i in 0..N {
        let planned = start + period * i;
        while Instant::now() < planned {
            std::hint::spin_loop();
        }
        busy_times.push(Instant::now());
    }
    println!("tick jitter at 1 kHz, |interval - 1 ms| ({N} ticks):");
    println!(
        "  scheduler run()      {}",
        percentiles(interval_errors(&sched_times))
    );
    println!(
        "  thread::sleep loop   {}",
        percentiles(interval_errors(&sleep_times))
    );
    println!(
        "  busy loop            {}",
        percentiles(interval_errors(&busy_times))
    );
}

fn rounds() -> usize {
    std::env::var("HORUS_BENCH_ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(2000)
}

/// Echoes `<prefix>/ping` to `<prefix>/pong` `count` times (the other process of the cross-process
/// round trip, and the in-process one on a thread).
fn pong(prefix: &str, count: usize) {
    let ping = Topic::<Int64>::new(&format!("{prefix}/ping")).expect("topic");
    let pong = Topic::<Int64>::new(&format!("{prefix}/pong")).expect("topic");
    ping.connect_subscriber().expect("subscribe");
    for _ in 0..count {
        match ping.recv_timeout(Duration::from_secs(30)) {
            Some(m) => pong.send(m),
            None => return,
        }
    }
}

fn topic_round_trips(prefix: &str, n: usize) -> Vec<Duration> {
    let ping = Topic::<Int64>::new(&format!("{prefix}/ping")).expect("topic");
    let pong = Topic::<Int64>::new(&format!("{prefix}/pong")).expect("topic");
    pong.connect_subscriber().expect("subscribe");
    // Until the echo is there (discovery), then the measured rounds.
    let mut i = 0;
    loop {
        i += 1;
        ping.send(Int64 { data: -i });
        if pong.recv_timeout(Duration::from_millis(100)).is_some() {
            break;
        }
    }
    while pong.recv_timeout(Duration::from_millis(200)).is_some() {}
    let mut rtts = Vec::with_capacity(n);
    for k in 0..n {
        let t = Instant::now();
        ping.send(Int64 { data: k as i64 });
        loop {
            match pong.recv_timeout(Duration::from_secs(5)) {
                Some(m) if m.data == k as i64 => break,
                Some(_) => continue,
                None => panic!("round trip {k} lost"),
            }
        }
        rtts.push(t.elapsed());
    }
    rtts
}

fn service_round_trips(n: usize) -> Vec<Duration> {
    let _server = ServiceServer::<AddTwoInts>::builder()
        .name("/bench/add_two_ints")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .name("/bench/add_two_ints")
        .build()
        .expect("client");
    assert!(client.wait_for_service(Duration::from_secs(30)));
    let _ = client.call(AddTwoIntsRequest { a: 0, b: 0 }, Duration::from_secs(5));
    (0..n)
        .map(|k| {
            let t = Instant::now();
            client
                .call(
                    AddTwoIntsRequest { a: k as i64, b: 1 },
                    Duration::from_secs(5),
                )
                .expect("call");
            t.elapsed()
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--pong") {
        let count = args.get(i + 1).and_then(|c| c.parse().ok()).unwrap_or(0);
        pong("/bench/remote", count);
        return;
    }
    if args.iter().any(|a| a == "--list") {
        return;
    }
    println!("scheduler overhead per empty tick and node (tick_once, no ROS; 5 batches):");
    for nodes in [1, 10, 100] {
        let (least, median) = overhead(nodes);
        println!("  {nodes:>3} nodes: {least:>7.1} ns least, {median:>7.1} ns median");
    }
    jitter();
    let n = rounds();
    let backend = std::env::var("HORUS_ROS_BACKEND").unwrap_or_else(|_| "rustdds".into());
    println!("round trips on the {backend} backend ({n} rounds, sequential):");
    let echo = std::thread::spawn(move || pong("/bench/local", n + 10_000));
    println!(
        "  Topic, one process      {}",
        percentiles(topic_round_trips("/bench/local", n))
    );
    drop(echo);
    let mut other = std::process::Command::new(std::env::current_exe().expect("exe"))
        .args(["--pong", &(n + 10_000).to_string()])
        .spawn()
        .expect("echo process");
    println!(
        "  Topic, two processes    {}",
        percentiles(topic_round_trips("/bench/remote", n))
    );
    let _ = other.kill();
    let _ = other.wait();
    println!(
        "  service, one process    {}",
        percentiles(service_round_trips(n))
    );
}
