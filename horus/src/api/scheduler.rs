//! The [`Scheduler`]: registers nodes, initializes them lazily, ticks them in order at their
//! rates with timing, budget, deadline and watchdog checks, routes failures through their
//! policies, and shuts them down in registration order.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use horus_ros_rmw::signal_handler::{self, ShutdownSignal, SignalHook};

use crate::api::clock::{Clock, StopHandle, SystemClock};
use crate::api::error::{BuildError, Error, Result, SchedulerError};
use crate::api::metrics::{ms, NodeMetrics, NodeTiming, TickStats, TimingReport};
use crate::api::node::{Node, NodeHealthState, NodeState, TopicMetadata};
use crate::api::policy::{FailurePolicy, Miss};
use crate::api::ros::ProcessRos;
use crate::api::runtime::{swap_current, with_current, NodeRuntime};
use crate::api::units::Frequency;
use crate::hlog;

/// How long `shutdown()` of one node may take before the scheduler detaches it and goes on.
pub const SHUTDOWN_TIMEOUT: Duration = Duration::from_secs(3);

/// The default scheduler rate when `tick_rate` is not given.
pub const DEFAULT_TICK_RATE_HZ: f64 = 100.0;

/// Per-node settings given through [`NodeBuilder`].
#[derive(Clone, Debug)]
struct NodeConfig {
    order: u32,
    period: Option<Duration>,
    rate_hz: Option<f64>,
    budget: Option<Duration>,
    deadline: Option<Duration>,
    on_miss: Miss,
    failure_policy: FailurePolicy,
}

impl Default for NodeConfig {
    fn default() -> Self {
        Self {
            order: 100,
            period: None,
            rate_hz: None,
            budget: None,
            deadline: None,
            on_miss: Miss::Warn,
            failure_policy: FailurePolicy::Fatal,
        }
    }
}

struct Entry {
    node: Option<Box<dyn Node>>,
    name: String,
    config: NodeConfig,
    state: NodeState,
    runtime: Arc<NodeRuntime>,
    /// A second strong handle of `runtime`, lent to the thread as its current node for each
    /// tick ([`swap_current`]): no reference counting per tick.
    lent: Option<Arc<NodeRuntime>>,
    stats: TickStats,
    /// The last `init` succeeded (shutdown is due at exit).
    live: bool,
    init_time: Option<Duration>,
    next_due: Duration,
    last_fed: Duration,
    restarts: u32,
    restart_at: Option<Duration>,
    consecutive_failures: u32,
    cooldown_until: Option<Duration>,
    skip_next: bool,
    publishers: Vec<TopicMetadata>,
    subscribers: Vec<TopicMetadata>,
    shutdown: String,
}

impl Entry {
    fn metrics(&self, now: Duration) -> NodeMetrics {
        let s = &self.stats;
        NodeMetrics {
            name: self.name.clone(),
            order: self.config.order,
            total_ticks: s.total,
            successful_ticks: s.ok,
            failed_ticks: s.failed,
            avg_tick_duration_ms: ms(s.avg()),
            max_tick_duration_ms: ms(s.max),
            min_tick_duration_ms: s.min.map(ms).unwrap_or(0.0),
            last_tick_duration_ms: ms(s.last),
            messages_sent: self.runtime.sent.load(std::sync::atomic::Ordering::Relaxed),
            messages_received: self
                .runtime
                .received
                .load(std::sync::atomic::Ordering::Relaxed),
            errors_count: s.errors,
            warnings_count: s.warnings,
            uptime_seconds: self
                .init_time
                .map(|t| now.saturating_sub(t).as_secs_f64())
                .unwrap_or(0.0),
        }
    }
}

/// Whether the scheduler's nodes join a ROS 2 graph.
enum RosMode {
    /// Each node becomes a ROS node of a context made from the environment and `--ros-args`.
    FromEnvironment,
    /// Each node becomes a ROS node of this context.
    Context(horus_ros_rmw::Context),
    /// No ROS side (tests of scheduling, benchmarks).
    Off,
}

/// Runs [`Node`]s: `init` once (lazily), `tick` in order at their rates, `shutdown` at exit.
///
/// ```no_run
/// use horus::prelude::*;
///
/// struct Hello;
/// impl Node for Hello {
///     fn tick(&mut self) { hlog!(info, "hello"); }
/// }
///
/// fn main() -> Result<()> {
///     let mut sched = Scheduler::new().tick_rate(10_u64.hz());
///     sched.add(Hello).order(0).build()?;
///     sched.run()
/// }
/// ```
pub struct Scheduler {
    tick_period: Duration,
    watchdog: Option<Duration>,
    shutdown_timeout: Duration,
    print_report: bool,
    clock: Arc<dyn Clock>,
    stop: StopHandle,
    entries: Vec<Entry>,
    exec_order: Vec<usize>,
    ros_mode: RosMode,
    ros: Option<ProcessRos>,
    started: bool,
    finished: bool,
    next_cycle: Duration,
}

impl Default for Scheduler {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for Scheduler {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scheduler")
            .field("nodes", &self.node_names())
            .field("tick_period", &self.tick_period)
            .field("watchdog", &self.watchdog)
            .finish()
    }
}

impl Scheduler {
    /// A scheduler at 100 Hz, no watchdog, on the system clock; its nodes join the ROS 2 graph
    /// of a context configured from the environment and the process's `--ros-args`.
    pub fn new() -> Self {
        Self {
            tick_period: Duration::from_millis(10),
            watchdog: None,
            shutdown_timeout: SHUTDOWN_TIMEOUT,
            print_report: true,
            clock: Arc::new(SystemClock::new()),
            stop: StopHandle::default(),
            entries: Vec::new(),
            exec_order: Vec::new(),
            ros_mode: RosMode::FromEnvironment,
            ros: None,
            started: false,
            finished: false,
            next_cycle: Duration::ZERO,
        }
    }

    /// The scheduler's cycle rate: nodes without a rate of their own tick once per cycle.
    /// An invalid frequency (zero, negative, not finite) keeps the current rate.
    pub fn tick_rate(mut self, rate: Frequency) -> Self {
        if let Some(p) = rate.period() {
            self.tick_period = p;
        }
        self
    }

    /// The watchdog timeout: a node not fed (no successful tick shorter than the timeout) for
    /// 1× is `Warning`, 2× `Unhealthy` (skipped), 3× `Isolated` (`enter_safe_state()`, skipped
    /// until `is_safe_state()`).
    pub fn watchdog(mut self, timeout: Duration) -> Self {
        self.watchdog = Some(timeout);
        self
    }

    /// The time source (a [`ManualClock`](crate::ManualClock) in tests).
    pub fn clock(mut self, clock: Arc<dyn Clock>) -> Self {
        self.clock = clock;
        self
    }

    /// How long one node's `shutdown()` may take before it is detached (default 3 s).
    pub fn shutdown_timeout(mut self, timeout: Duration) -> Self {
        self.shutdown_timeout = timeout;
        self
    }

    /// Whether the timing report is printed (stderr) when the scheduler stops (default true).
    pub fn print_report(mut self, print: bool) -> Self {
        self.print_report = print;
        self
    }

    /// Run the nodes without a ROS 2 side (no DDS): for tests of scheduling and benchmarks.
    pub fn without_ros(mut self) -> Self {
        self.ros_mode = RosMode::Off;
        self
    }

    /// Make each node a ROS node of `context` (default: one made from the environment).
    pub fn context(mut self, context: horus_ros_rmw::Context) -> Self {
        self.ros_mode = RosMode::Context(context);
        self
    }

    /// Registers `node`; configure it on the returned builder and finish with
    /// [`build`](NodeBuilder::build).
    pub fn add<N: Node + 'static>(&mut self, node: N) -> NodeBuilder<'_> {
        NodeBuilder {
            scheduler: self,
            node: Box::new(node),
            config: NodeConfig::default(),
        }
    }

    /// A handle that stops [`run`](Self::run) from anywhere.
    pub fn stop_handle(&self) -> StopHandle {
        self.stop.clone()
    }

    /// Asks the scheduler to stop: `run` returns once every node's `shutdown` ran; after
    /// `tick_once`, the next `tick_once` (or dropping the scheduler) shuts the nodes down.
    pub fn stop(&self) {
        self.stop.stop();
    }

    /// The node names, in registration order.
    pub fn node_names(&self) -> Vec<String> {
        self.entries.iter().map(|e| e.name.clone()).collect()
    }

    /// A node's metrics.
    pub fn get_node_metrics(&self, name: &str) -> Option<NodeMetrics> {
        let now = self.clock.now();
        self.entry(name).map(|e| e.metrics(now))
    }

    /// A node's lifecycle state.
    pub fn node_state(&self, name: &str) -> Option<NodeState> {
        self.entry(name).map(|e| e.state.clone())
    }

    /// A node's watchdog health.
    pub fn node_health(&self, name: &str) -> Option<NodeHealthState> {
        self.entry(name).map(|e| e.runtime.health.load())
    }

    /// The topics a node reported (`publishers()`, `subscribers()`) after its `init`.
    pub fn node_topics(&self, name: &str) -> Option<(Vec<TopicMetadata>, Vec<TopicMetadata>)> {
        self.entry(name)
            .map(|e| (e.publishers.clone(), e.subscribers.clone()))
    }

    /// The ROS 2 node behind a scheduled node (once its `init` has begun on a scheduler that
    /// joins the graph).
    pub fn ros_node(&self, name: &str) -> Option<horus_ros_rmw::Node> {
        self.entry(name)
            .and_then(|e| e.runtime.ros())
            .map(|r| r.node().clone())
    }

    /// The timing report (what is printed at exit).
    pub fn timing_report(&self) -> TimingReport {
        let now = self.clock.now();
        TimingReport {
            nodes: self
                .entries
                .iter()
                .map(|e| NodeTiming {
                    metrics: e.metrics(now),
                    deadline_misses: e.stats.deadline_misses,
                    budget_overruns: e.stats.budget_overruns,
                    shutdown: e.shutdown.clone(),
                })
                .collect(),
        }
    }

    fn entry(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// Runs until Ctrl+C, SIGTERM or [`stop`](Self::stop); then runs every node's `shutdown`
    /// (registration order) and prints the timing report. Returns the error that stopped it, if
    /// a node's failure or deadline policy did.
    pub fn run(&mut self) -> Result<()> {
        let _signals = stop_on_signals(&self.stop);
        let mut outcome = self.start();
        while outcome.is_ok() && !self.stop.is_stopped() {
            outcome = self.cycle(false);
            if outcome.is_err() || self.stop.is_stopped() {
                break;
            }
            let wake = self.next_wake();
            self.clock.wait_until(wake, &self.stop);
        }
        self.finish();
        outcome.map_err(Error::from)
    }

    /// One cycle, for tests: initializes the nodes on the first call, then ticks every node
    /// without a rate of its own, and those with one that are due. After a stop (or a fatal
    /// failure) it shuts the nodes down instead.
    pub fn tick_once(&mut self) -> Result<()> {
        if self.finished {
            return Ok(());
        }
        if self.stop.is_stopped() {
            self.finish();
            return Ok(());
        }
        let outcome = self.start().and_then(|()| self.cycle(true));
        if outcome.is_err() || self.stop.is_stopped() {
            self.finish();
        }
        outcome.map_err(Error::from)
    }

    /// Lazy start: the ROS side, then every node's `init` in execution order.
    fn start(&mut self) -> Result<(), SchedulerError> {
        if self.started {
            return Ok(());
        }
        self.started = true;
        let mode = std::mem::replace(&mut self.ros_mode, RosMode::Off);
        self.ros = match mode {
            RosMode::Off => None,
            RosMode::FromEnvironment => Some(ProcessRos::from_environment()?),
            RosMode::Context(c) => Some(ProcessRos::new(c)),
        };
        let now = self.clock.now();
        self.next_cycle = now;
        for k in 0..self.exec_order.len() {
            let i = self.exec_order[k];
            self.init_node(i, now)?;
        }
        Ok(())
    }

    /// Calls `init` of node `i` (first time or restart) and applies its policy on failure.
    fn init_node(&mut self, i: usize, now: Duration) -> Result<(), SchedulerError> {
        let restarting = self.entries[i].restart_at.take().is_some();
        if self.entries[i].runtime.ros().is_none() {
            if let Some(ros) = &self.ros {
                let rt = Arc::clone(&self.entries[i].runtime);
                let ros_node = ros.attach(&rt.name).map_err(SchedulerError::Ros)?;
                *rt.ros.lock().unwrap_or_else(|p| p.into_inner()) = Some(ros_node);
            }
        }
        let e = &mut self.entries[i];
        let Some(node) = e.node.as_mut() else {
            return Ok(());
        };
        e.state = NodeState::Initializing;
        let result = with_current(&e.runtime, || {
            catch_unwind(AssertUnwindSafe(|| node.init()))
        });
        let error = match result {
            Ok(Ok(())) => {
                e.live = true;
                e.state = NodeState::Running;
                if e.init_time.is_none() {
                    e.init_time = Some(now);
                }
                e.last_fed = now;
                e.next_due = now;
                e.runtime.health.store(NodeHealthState::Healthy);
                if !restarting {
                    e.publishers = node.publishers();
                    e.subscribers = node.subscribers();
                }
                if restarting {
                    with_current(&e.runtime, || {
                        hlog!(info, "restarted (restart {})", e.restarts)
                    });
                }
                return Ok(());
            }
            Ok(Err(err)) => err.to_string(),
            Err(panic) => format!("init panicked: {}", panic_message(&*panic)),
        };
        e.live = false;
        e.stats.errors += 1;
        e.state = NodeState::Error(error.clone());
        with_current(&e.runtime, || hlog!(error, "init failed: {}", error));
        match e.config.failure_policy {
            FailurePolicy::Fatal => Err(SchedulerError::InitFailed {
                node: e.name.clone(),
                error,
            }),
            FailurePolicy::Restart {
                max_restarts,
                initial_backoff,
            } => schedule_restart(e, now, max_restarts, initial_backoff, error),
            // Never ticked, never shut down; the others go on.
            FailurePolicy::Skip { .. } | FailurePolicy::Ignore => Ok(()),
        }
    }

    /// When `run` should wake next: the next cycle, a rate node's next tick, a restart or the
    /// end of a cooldown.
    fn next_wake(&self) -> Duration {
        let mut wake = self.next_cycle;
        for e in &self.entries {
            if e.live && e.config.period.is_some() {
                wake = wake.min(e.next_due);
            }
            if let Some(t) = e.restart_at {
                wake = wake.min(t);
            }
            if let Some(t) = e.cooldown_until {
                wake = wake.min(t);
            }
        }
        wake
    }

    /// One pass over the nodes in execution order.
    fn cycle(&mut self, force: bool) -> Result<(), SchedulerError> {
        let cycle_start = self.clock.now();
        let cycle_due = force || cycle_start >= self.next_cycle;
        if cycle_due {
            let planned = self.next_cycle;
            self.next_cycle = if planned + self.tick_period > cycle_start {
                planned + self.tick_period
            } else {
                cycle_start + self.tick_period
            };
        }
        // One clock read per tick end serves as "now" for the next node.
        let mut now = cycle_start;
        for k in 0..self.exec_order.len() {
            let i = self.exec_order[k];
            if let Some(t) = self.entries[i].restart_at {
                if now < t {
                    continue;
                }
                self.init_node(i, now)?;
                if !self.entries[i].live {
                    continue;
                }
            }
            let clock = &*self.clock;
            now = step(
                &mut self.entries[i],
                clock,
                self.watchdog,
                now,
                cycle_start,
                cycle_due || force,
            )?;
        }
        Ok(())
    }

    /// Shuts every live node down (registration order, each within the timeout), leaves the
    /// graph, prints the report. Idempotent.
    fn finish(&mut self) {
        if self.finished {
            return;
        }
        self.finished = true;
        if self.started {
            for i in 0..self.entries.len() {
                self.shutdown_node(i);
            }
        }
        // Leave the graph: the nodes (and the topics they own) first, then each ROS node.
        for e in &mut self.entries {
            e.node = None;
        }
        for e in &self.entries {
            e.runtime
                .ros
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .take();
        }
        self.ros = None;
        if self.print_report && self.started {
            eprint!("{}", self.timing_report());
        }
    }

    fn shutdown_node(&mut self, i: usize) {
        let timeout = self.shutdown_timeout;
        let e = &mut self.entries[i];
        if !e.live {
            e.shutdown = "not run".to_owned();
            return;
        }
        let Some(mut node) = e.node.take() else {
            return;
        };
        e.state = NodeState::Stopping;
        let runtime = Arc::clone(&e.runtime);
        let (tx, rx) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name(format!("horus-shutdown-{}", e.name))
            .spawn(move || {
                let result = with_current(&runtime, || {
                    catch_unwind(AssertUnwindSafe(|| node.shutdown()))
                });
                let _ = tx.send((node, result));
            });
        if let Err(err) = spawned {
            e.shutdown = format!("error: could not start its shutdown thread: {err}");
            e.stats.errors += 1;
            return;
        }
        let name = e.name.clone();
        let outcome = match rx.recv_timeout(timeout) {
            Ok((node, result)) => {
                e.node = Some(node);
                match result {
                    Ok(Ok(())) => "ok".to_owned(),
                    Ok(Err(err)) => format!("error: {err}"),
                    Err(panic) => format!("panicked: {}", panic_message(&*panic)),
                }
            }
            Err(_) => format!("timed out after {:.3} s (detached)", timeout.as_secs_f64()),
        };
        if outcome != "ok" {
            e.stats.errors += 1;
            with_current(&e.runtime, || {
                hlog!(error, "shutdown of {}: {}", name, outcome)
            });
        }
        e.live = false;
        e.state = NodeState::Stopped;
        e.shutdown = outcome;
    }
}

impl Drop for Scheduler {
    fn drop(&mut self) {
        self.finish();
    }
}

/// One node's part of a cycle; `now` is the latest clock reading. Returns the clock reading at
/// its end (the tick's end, or `now` when it did not tick).
fn step(
    e: &mut Entry,
    clock: &dyn Clock,
    watchdog: Option<Duration>,
    now: Duration,
    cycle_start: Duration,
    cycle_due: bool,
) -> Result<Duration, SchedulerError> {
    if !e.live {
        return Ok(now);
    }
    if let Some(until) = e.cooldown_until {
        if now < until {
            return Ok(now);
        }
        e.cooldown_until = None;
    }
    // Due?
    let due = match e.config.period {
        Some(period) => {
            if now < e.next_due {
                return Ok(now);
            }
            let due = e.next_due;
            e.next_due = if due + period > now {
                due + period
            } else {
                now + period
            };
            due
        }
        None => {
            if !cycle_due {
                return Ok(now);
            }
            cycle_start
        }
    };
    let Some(node) = e.node.as_mut() else {
        return Ok(now);
    };
    // Health: recovery of an isolated node, then the watchdog.
    let health = e.runtime.health.load();
    if health == NodeHealthState::Isolated {
        let safe = with_current(&e.runtime, || {
            catch_unwind(AssertUnwindSafe(|| node.is_safe_state())).unwrap_or(false)
        });
        if !safe {
            return Ok(now);
        }
        e.runtime.health.store(NodeHealthState::Healthy);
        e.last_fed = now;
        with_current(&e.runtime, || hlog!(info, "safe state confirmed, resuming"));
    } else if let Some(timeout) = watchdog {
        let starved = now.saturating_sub(e.last_fed);
        let level = if starved >= timeout * 3 {
            NodeHealthState::Isolated
        } else if starved >= timeout * 2 {
            NodeHealthState::Unhealthy
        } else if starved >= timeout {
            NodeHealthState::Warning
        } else {
            NodeHealthState::Healthy
        };
        if level != health {
            e.runtime.health.store(level);
            match level {
                NodeHealthState::Warning => {
                    e.stats.warnings += 1;
                    with_current(&e.runtime, || {
                        hlog!(warn, "watchdog: not fed for {:.3} ms", ms(starved))
                    });
                }
                NodeHealthState::Unhealthy => {
                    e.stats.warnings += 1;
                    with_current(&e.runtime, || {
                        hlog!(warn, "watchdog: unhealthy, skipping ticks")
                    });
                }
                NodeHealthState::Isolated => {
                    e.stats.errors += 1;
                    with_current(&e.runtime, || {
                        hlog!(error, "watchdog: isolated, entering safe state");
                        let _ = catch_unwind(AssertUnwindSafe(|| node.enter_safe_state()));
                    });
                }
                NodeHealthState::Healthy => {}
            }
        }
        if level >= NodeHealthState::Unhealthy {
            return Ok(now);
        }
    }
    if e.skip_next {
        e.skip_next = false;
        return Ok(now);
    }
    // The tick, with the node current on this thread.
    swap_current(&mut e.lent);
    let result = catch_unwind(AssertUnwindSafe(|| node.tick()));
    let end = clock.now();
    swap_current(&mut e.lent);
    let start = now;
    let took = end.saturating_sub(start);
    e.stats.record(took);
    match result {
        Ok(()) => {
            e.stats.ok += 1;
            e.consecutive_failures = 0;
            if matches!(e.state, NodeState::Crashed(_)) {
                e.state = NodeState::Running;
            }
            if watchdog.is_none_or(|w| took < w) {
                e.last_fed = end;
            }
            if let Some(budget) = e.config.budget {
                if took > budget {
                    e.stats.warnings += 1;
                    e.stats.budget_overruns += 1;
                    with_current(&e.runtime, || {
                        hlog!(
                            warn,
                            "tick took {:.3} ms, over its budget of {:.3} ms",
                            ms(took),
                            ms(budget)
                        )
                    });
                }
            }
            if let Some(deadline) = e.config.deadline {
                let late = end.saturating_sub(due);
                if late > deadline {
                    e.stats.warnings += 1;
                    e.stats.deadline_misses += 1;
                    let over = ms(late - deadline);
                    match e.config.on_miss {
                        Miss::Warn => with_current(&e.runtime, || {
                            hlog!(warn, "deadline missed by {:.3} ms", over)
                        }),
                        Miss::Skip => {
                            e.skip_next = true;
                            with_current(&e.runtime, || {
                                hlog!(
                                    warn,
                                    "deadline missed by {:.3} ms: skipping next tick",
                                    over
                                )
                            });
                        }
                        Miss::SafeMode => {
                            e.runtime.health.store(NodeHealthState::Isolated);
                            with_current(&e.runtime, || {
                                hlog!(
                                    warn,
                                    "deadline missed by {:.3} ms: entering safe state",
                                    over
                                );
                                let _ = catch_unwind(AssertUnwindSafe(|| node.enter_safe_state()));
                            });
                        }
                        Miss::Stop => {
                            with_current(&e.runtime, || {
                                hlog!(
                                    error,
                                    "deadline missed by {:.3} ms: stopping the scheduler",
                                    over
                                )
                            });
                            return Err(SchedulerError::DeadlineMissed {
                                node: e.name.clone(),
                                late_ms: over,
                            });
                        }
                    }
                }
            }
            Ok(end)
        }
        Err(panic) => {
            let message = panic_message(&*panic);
            e.stats.failed += 1;
            e.stats.errors += 1;
            e.state = NodeState::Crashed(message.clone());
            with_current(&e.runtime, || {
                if catch_unwind(AssertUnwindSafe(|| node.on_error(&message))).is_err() {
                    hlog!(error, "on_error panicked too");
                }
            });
            match e.config.failure_policy {
                FailurePolicy::Fatal => Err(SchedulerError::NodeFailed {
                    node: e.name.clone(),
                    error: message,
                }),
                FailurePolicy::Restart {
                    max_restarts,
                    initial_backoff,
                } => schedule_restart(e, end, max_restarts, initial_backoff, message).map(|()| end),
                FailurePolicy::Skip {
                    max_failures,
                    cooldown,
                } => {
                    e.consecutive_failures += 1;
                    if e.consecutive_failures >= max_failures {
                        e.consecutive_failures = 0;
                        e.cooldown_until = Some(end + cooldown);
                        with_current(&e.runtime, || {
                            hlog!(
                                warn,
                                "{} consecutive failures: skipped for {:.3} ms",
                                max_failures,
                                ms(cooldown)
                            )
                        });
                    }
                    Ok(end)
                }
                FailurePolicy::Ignore => Ok(end),
            }
        }
    }
}

fn schedule_restart(
    e: &mut Entry,
    now: Duration,
    max_restarts: u32,
    initial_backoff: Duration,
    error: String,
) -> Result<(), SchedulerError> {
    if e.restarts >= max_restarts {
        return Err(SchedulerError::RestartsExhausted {
            node: e.name.clone(),
            restarts: e.restarts,
            error,
        });
    }
    e.restarts += 1;
    let wait = FailurePolicy::restart_backoff(initial_backoff, e.restarts);
    e.restart_at = Some(now + wait);
    with_current(&e.runtime, || {
        hlog!(
            warn,
            "restart {} of {} in {:.3} ms",
            e.restarts,
            max_restarts,
            ms(wait)
        )
    });
    Ok(())
}

/// The message of a caught panic.
fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = panic.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = panic.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-string payload".to_owned()
    }
}

/// Configures one node; [`build`](Self::build) registers it.
#[must_use = "a node is registered only by .build()"]
pub struct NodeBuilder<'a> {
    scheduler: &'a mut Scheduler,
    node: Box<dyn Node>,
    config: NodeConfig,
}

impl NodeBuilder<'_> {
    /// Execution order: lower ticks first (ties: registration order). Default 100.
    pub fn order(mut self, order: u32) -> Self {
        self.config.order = order;
        self
    }

    /// The node's own rate (default: once per scheduler cycle).
    pub fn rate(mut self, rate: Frequency) -> Self {
        self.config.rate_hz = Some(rate.hz());
        self.config.period = rate.period();
        self
    }

    /// Expected worst tick time: a longer tick counts as a budget overrun (a warning).
    pub fn budget(mut self, budget: Duration) -> Self {
        self.config.budget = Some(budget);
        self
    }

    /// Latest completion of a tick after it was due; a later one is a deadline miss, handled
    /// by [`on_miss`](Self::on_miss).
    pub fn deadline(mut self, deadline: Duration) -> Self {
        self.config.deadline = Some(deadline);
        self
    }

    /// What a deadline miss does (default [`Miss::Warn`]).
    pub fn on_miss(mut self, miss: Miss) -> Self {
        self.config.on_miss = miss;
        self
    }

    /// What a failure does (default [`FailurePolicy::Fatal`]).
    pub fn failure_policy(mut self, policy: FailurePolicy) -> Self {
        self.config.failure_policy = policy;
        self
    }

    /// Registers the node. Fails on a duplicate name, a name that cannot be a ROS node name, an
    /// invalid rate, or a scheduler that has already started.
    pub fn build(self) -> Result<(), BuildError> {
        let name = self.node.name().to_owned();
        let s = self.scheduler;
        if s.started {
            return Err(BuildError::AlreadyStarted(name));
        }
        if s.entries.iter().any(|e| e.name == name) {
            return Err(BuildError::DuplicateName(name));
        }
        if let Some(hz) = self.config.rate_hz {
            if self.config.period.is_none() {
                return Err(BuildError::InvalidRate { name, hz });
            }
        }
        if let Err(reason) = crate::api::names::ros_node_name(&name) {
            return Err(BuildError::InvalidName { name, reason });
        }
        let index = s.entries.len();
        let runtime = NodeRuntime::new(name.clone());
        s.entries.push(Entry {
            node: Some(self.node),
            lent: Some(Arc::clone(&runtime)),
            runtime,
            name,
            config: self.config,
            state: NodeState::Uninitialized,
            stats: TickStats::default(),
            live: false,
            init_time: None,
            next_due: Duration::ZERO,
            last_fed: Duration::ZERO,
            restarts: 0,
            restart_at: None,
            consecutive_failures: 0,
            cooldown_until: None,
            skip_next: false,
            publishers: Vec::new(),
            subscribers: Vec::new(),
            shutdown: "not run".to_owned(),
        });
        s.exec_order.push(index);
        let entries = &s.entries;
        s.exec_order.sort_by_key(|&i| (entries[i].config.order, i));
        Ok(())
    }
}

/// SIGINT (Ctrl+C), SIGTERM and SIGHUP stop the scheduler while the returned hook lives: through
/// the process's one signal thread (`horus_ros_rmw::signal_handler`), which also shuts the ROS
/// contexts down. The hook tells it that the program handles these signals, so every node's
/// `shutdown` runs (and may still publish) before the process leaves the graph; a second signal
/// ends the process at once, after the participants' goodbye.
fn stop_on_signals(stop: &StopHandle) -> Option<SignalHook> {
    let state = stop.downgrade();
    let hook = signal_handler::on_signal(
        &[
            ShutdownSignal::Interrupt,
            ShutdownSignal::Terminate,
            ShutdownSignal::Hangup,
        ],
        move |_| {
            if let Some(state) = state.upgrade() {
                StopHandle::from_inner(state).stop();
            }
        },
    );
    hook.inspect_err(|e| tracing::warn!("signals will not stop the scheduler: {e}"))
        .ok()
}
