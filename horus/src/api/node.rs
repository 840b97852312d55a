//! The [`Node`] trait and the types that describe a node's lifecycle and health.

use std::sync::atomic::{AtomicU8, Ordering};

use crate::api::error::Result;

/// A component of a robot program: a sensor driver, a controller, a planner, a logger.
///
/// The [`Scheduler`](crate::Scheduler) calls `init` once (lazily, on the first `run` or
/// `tick_once`), `tick` repeatedly and `shutdown` once at exit, each wrapped in `catch_unwind`.
/// Every scheduled node is also a ROS 2 node (see the crate documentation).
///
/// Nodes are `Send` (moved into the scheduler) but need not be `Sync`: the scheduler never
/// calls one from two threads at once.
pub trait Node: Send {
    /// A unique name within the scheduler. Default: the type's name without its module path
    /// (`my_crate::sensors::ImuReader` → `ImuReader`).
    fn name(&self) -> &str {
        short_type_name(std::any::type_name::<Self>())
    }

    /// One-time setup that may fail (open hardware, load calibration). Called lazily on the
    /// first `run()` / `tick_once()`. If it fails, `tick` and `shutdown` are never called.
    fn init(&mut self) -> Result<()> {
        Ok(())
    }

    /// One cycle of work. The only required method. Must not block.
    fn tick(&mut self);

    /// Cleanup at exit (zero the motors). Called once, in registration order.
    fn shutdown(&mut self) -> Result<()> {
        Ok(())
    }

    /// Whether an isolated node may resume (checked every cycle while it is isolated).
    fn is_safe_state(&self) -> bool {
        true
    }

    /// Go to a safe configuration (called when the watchdog isolates the node, or on a deadline
    /// miss with `Miss::SafeMode`).
    fn enter_safe_state(&mut self) {}

    /// Called with the panic message when `tick` panicked.
    fn on_error(&mut self, error: &str) {
        crate::hlog!(error, "Node error: {}", error);
    }

    /// The topics this node publishes (for monitoring; the `node!` macro generates it).
    #[doc(hidden)]
    fn publishers(&self) -> Vec<TopicMetadata> {
        Vec::new()
    }

    /// The topics this node subscribes to (for monitoring; the `node!` macro generates it).
    #[doc(hidden)]
    fn subscribers(&self) -> Vec<TopicMetadata> {
        Vec::new()
    }
}

/// `a::b::Name<c::D>` → `Name<c::D>`: the last path segment before any generic arguments.
pub(crate) fn short_type_name(full: &'static str) -> &'static str {
    let end = full.find('<').unwrap_or(full.len());
    let start = full[..end].rfind("::").map(|i| i + 2).unwrap_or(0);
    &full[start..]
}

/// A topic connection of a node, for monitoring.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct TopicMetadata {
    /// The topic name as the node names it (HORUS form, e.g. `motor.cmd`).
    pub topic_name: String,
    /// The message type name.
    pub type_name: String,
}

/// A node's lifecycle state, tracked by the scheduler.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NodeState {
    /// Registered, `init` not yet called.
    Uninitialized,
    /// `init` is running.
    Initializing,
    /// Normal operation: `tick` is being called.
    Running,
    /// `shutdown` is running.
    Stopping,
    /// Shutdown complete.
    Stopped,
    /// `init` (or a restart) returned an error.
    Error(String),
    /// `tick` panicked.
    Crashed(String),
}

/// Watchdog health of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum NodeHealthState {
    /// Normal operation: ticked every cycle.
    Healthy = 0,
    /// 1× the watchdog timeout without a feed: still ticked, a warning is logged.
    Warning = 1,
    /// 2× the timeout: skipped in the tick loop.
    Unhealthy = 2,
    /// 3× the timeout: `enter_safe_state()` was called; skipped until `is_safe_state()`.
    Isolated = 3,
}

impl NodeHealthState {
    fn from_u8(v: u8) -> Self {
        match v {
            0 => Self::Healthy,
            1 => Self::Warning,
            2 => Self::Unhealthy,
            _ => Self::Isolated,
        }
    }
}

/// A [`NodeHealthState`] stored as an `AtomicU8`, readable from any thread without a lock.
#[derive(Debug, Default)]
pub(crate) struct AtomicHealth(AtomicU8);

impl AtomicHealth {
    pub(crate) fn load(&self) -> NodeHealthState {
        NodeHealthState::from_u8(self.0.load(Ordering::Acquire))
    }

    pub(crate) fn store(&self, state: NodeHealthState) {
        self.0.store(state as u8, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_names() {
        assert_eq!(short_type_name("my_crate::sensors::ImuReader"), "ImuReader");
        assert_eq!(short_type_name("ImuReader"), "ImuReader");
        assert_eq!(short_type_name("a::Wrap<b::Inner>"), "Wrap<b::Inner>");
    }
}
