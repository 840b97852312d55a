//! [`Session`]: the CLI's own hidden node on the graph, and the wait for discovery.

use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use horus_ros_rmw::{BackendError, Context, ContextError, Node};

use crate::{CliError, Global};

/// The shortest discovery wait: peers answer a new participant's announcement within a few
/// milliseconds, but not at once.
const MIN_DISCOVERY: Duration = Duration::from_millis(120);
/// Once what is known is consistent, the wait ends when nothing has changed for this long
/// (participants not seen yet get this long to show up).
const GRACE: Duration = Duration::from_millis(30);
/// Longest single wait while what is known is still inconsistent.
const STEP: Duration = Duration::from_millis(10);

/// A context, a hidden node (`_horus_ros_<pid>`, as ros2cli's `_ros2cli_<pid>`), and the live
/// graph seen from it.
pub struct Session {
    /// The context.
    pub context: Context,
    /// The CLI's node (hidden: its name starts with `_`).
    pub node: Node,
    /// The graph.
    pub graph: Arc<Graph>,
}

impl Session {
    /// Joins the domain and waits for discovery to settle (at most `--spin-time`).
    pub fn open(global: &Global) -> Result<Self, CliError> {
        let session = Self::join(global)?;
        session.settle(global);
        Ok(session)
    }

    /// Joins the domain without waiting.
    pub fn join(global: &Global) -> Result<Self, CliError> {
        let mut builder = Context::builder();
        // Unset: the context reads HORUS_ROS_BACKEND, then RMW_IMPLEMENTATION, as the library does.
        if let Some(b) = global.backend() {
            builder = builder.backend(b);
        }
        if let Some(d) = global.domain_id {
            builder = builder.domain_id(d);
        }
        let context = builder.build().map_err(|e| match e {
            // The one place the CLI adds to a library message: its own override.
            ContextError::Backend(e @ BackendError::UnsupportedRmw { .. }) => {
                CliError::new(format!("{e} (or pass --backend)"))
            }
            e => e.into(),
        })?;
        let node = context.create_node(&format!("_horus_ros_{}", std::process::id()), "/")?;
        let graph = Graph::shared(&context)?;
        Ok(Self {
            context,
            node,
            graph,
        })
    }

    /// Waits for discovery, never longer than `--spin-time` (ros2cli always waits the whole
    /// spin time): at least [`MIN_DISCOVERY`], then until what is known is consistent (every
    /// participant's `ros_discovery_info` in and every endpoint it lists discovered) and has not
    /// changed for [`GRACE`].
    pub fn settle(&self, global: &Global) {
        let start = Instant::now();
        let limit = Duration::from_secs_f64(global.spin_time.max(0.0));
        std::thread::sleep(MIN_DISCOVERY.min(limit));
        loop {
            let left = limit.saturating_sub(start.elapsed());
            if left.is_zero() {
                return;
            }
            if self.graph.read(|c| c.is_consistent()) {
                if !self.graph.wait_for_graph_change(GRACE.min(left)) {
                    return;
                }
            } else {
                self.graph.wait_for_graph_change(STEP.min(left));
            }
        }
    }
}
