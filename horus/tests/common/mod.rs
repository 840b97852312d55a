//! What the chatter tests against independent DDS implementations share: a context on a
//! domain of its own, and a HORUS talker and listener on `/chatter` run by a scheduler on a
//! thread of their own.

mod chatter_nodes;

use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use chatter_nodes::{Listener, Talker};
use horus::prelude::*;
use horus::ros::{Arguments, Context};
use horus::StopHandle;

/// How long any one wait of these tests may take.
pub const LIMIT: Duration = Duration::from_secs(30);

/// A context on `domain`, ignoring the process's arguments.
pub fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .arguments(Arguments::default())
        .build()
        .expect("context")
}

/// A scheduler running on a thread of its own; [`stop`](Self::stop) ends it.
pub struct Running<T> {
    stop: StopHandle,
    thread: JoinHandle<T>,
}

impl<T> Running<T> {
    /// Stops the scheduler and returns what its thread returned.
    pub fn stop(self) -> T {
        self.stop.stop();
        self.thread.join().expect("scheduler thread")
    }
}

/// Runs `node` alone in a scheduler on `domain` at `rate_hz`, on a thread of its own, which
/// returns `then(how run ended, the scheduler)`.
fn run_alone<T: Send + 'static>(
    domain: u32,
    rate_hz: u64,
    node: impl Node + 'static,
    then: impl FnOnce(std::result::Result<(), String>, &Scheduler) -> T + Send + 'static,
) -> Running<T> {
    let mut sched = Scheduler::new()
        .context(context(domain))
        .tick_rate(rate_hz.hz())
        .print_report(false);
    sched.add(node).build().expect("node");
    let stop = sched.stop_handle();
    let thread = std::thread::spawn(move || {
        let outcome = sched.run().map_err(|e| e.to_string());
        then(outcome, &sched)
    });
    Running { stop, thread }
}

/// Runs a HORUS talker on `domain` at 20 Hz; its thread returns how `run` ended.
pub fn run_talker(domain: u32) -> Running<std::result::Result<(), String>> {
    run_alone(domain, 20, Talker::on_chatter(), |outcome, _| outcome)
}

/// What a listener's thread returns: how `run` ended and the listener's metrics.
pub type ListenerOutcome = (std::result::Result<(), String>, Option<NodeMetrics>);

/// Runs a HORUS listener on `domain` at 100 Hz; what it hears arrives on the receiver.
pub fn run_listener(domain: u32) -> (Running<ListenerOutcome>, mpsc::Receiver<String>) {
    let (tx, heard) = mpsc::channel();
    let running = run_alone(domain, 100, Listener::new(tx), |outcome, sched| {
        (outcome, sched.get_node_metrics("listener"))
    });
    (running, heard)
}

/// The first `n` messages heard, waiting at most [`LIMIT`] in all.
pub fn hear(heard: &mpsc::Receiver<String>, n: usize) -> Vec<String> {
    let deadline = Instant::now() + LIMIT;
    let mut got = Vec::new();
    while got.len() < n {
        match heard.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(m) => got.push(m),
            Err(_) => panic!("heard only {got:?}"),
        }
    }
    got
}
