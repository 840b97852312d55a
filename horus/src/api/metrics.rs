//! [`NodeMetrics`] (per-node counters) and the [`TimingReport`] printed at exit.

use std::fmt;
use std::time::Duration;

/// Performance counters of one node ([`Scheduler::get_node_metrics`](crate::Scheduler::get_node_metrics)).
#[derive(Clone, Debug, PartialEq)]
pub struct NodeMetrics {
    /// Node name.
    pub name: String,
    /// Execution order (`.order(..)`).
    pub order: u32,
    /// Ticks called (successful or not).
    pub total_ticks: u64,
    /// Ticks that completed without a panic.
    pub successful_ticks: u64,
    /// Ticks that panicked.
    pub failed_ticks: u64,
    /// Running average tick time (ms).
    pub avg_tick_duration_ms: f64,
    /// Worst tick time (ms).
    pub max_tick_duration_ms: f64,
    /// Best tick time (ms; 0 before the first tick).
    pub min_tick_duration_ms: f64,
    /// Most recent tick time (ms).
    pub last_tick_duration_ms: f64,
    /// Messages published through the node's [`Topic`](crate::Topic)s.
    pub messages_sent: u64,
    /// Messages received through the node's [`Topic`](crate::Topic)s.
    pub messages_received: u64,
    /// Errors: panics in tick, failed init/restart/shutdown.
    pub errors_count: u64,
    /// Warnings: watchdog warnings, budget overruns, deadline misses.
    pub warnings_count: u64,
    /// Time since `init` succeeded (s; 0 before).
    pub uptime_seconds: f64,
}

/// Tick-time statistics the scheduler keeps per node.
#[derive(Clone, Debug, Default)]
pub(crate) struct TickStats {
    pub(crate) total: u64,
    pub(crate) ok: u64,
    pub(crate) failed: u64,
    pub(crate) sum: Duration,
    pub(crate) max: Duration,
    pub(crate) min: Option<Duration>,
    pub(crate) last: Duration,
    pub(crate) errors: u64,
    pub(crate) warnings: u64,
    pub(crate) deadline_misses: u64,
    pub(crate) budget_overruns: u64,
}

impl TickStats {
    pub(crate) fn record(&mut self, d: Duration) {
        self.total += 1;
        self.sum += d;
        self.max = self.max.max(d);
        self.min = Some(self.min.map_or(d, |m| m.min(d)));
        self.last = d;
    }

    pub(crate) fn avg(&self) -> Duration {
        if self.total == 0 {
            Duration::ZERO
        } else {
            self.sum / u32::try_from(self.total).unwrap_or(u32::MAX)
        }
    }
}

pub(crate) fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// One line of the [`TimingReport`].
#[derive(Clone, Debug, PartialEq)]
pub struct NodeTiming {
    /// The node's metrics at exit.
    pub metrics: NodeMetrics,
    /// Deadline misses.
    pub deadline_misses: u64,
    /// Budget overruns.
    pub budget_overruns: u64,
    /// How its shutdown ended (`ok`, `error: …`, `panicked: …`, `timed out`, `not run`).
    pub shutdown: String,
}

/// What the scheduler prints when it stops: per node, ticks, tick times, failures, misses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimingReport {
    /// One entry per node, in registration order.
    pub nodes: Vec<NodeTiming>,
}

impl fmt::Display for TimingReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<24} {:>10} {:>8} {:>10} {:>10} {:>10} {:>7} {:>7}  shutdown",
            "node", "ticks", "failed", "avg ms", "min ms", "max ms", "misses", "budget"
        )?;
        for n in &self.nodes {
            let m = &n.metrics;
            writeln!(
                f,
                "{:<24} {:>10} {:>8} {:>10.4} {:>10.4} {:>10.4} {:>7} {:>7}  {}",
                m.name,
                m.total_ticks,
                m.failed_ticks,
                m.avg_tick_duration_ms,
                m.min_tick_duration_ms,
                m.max_tick_duration_ms,
                n.deadline_misses,
                n.budget_overruns,
                n.shutdown
            )?;
        }
        Ok(())
    }
}
