//! [`Session`]: the CLI's own hidden node on the graph, and the wait for discovery.

use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_graph::{Graph, Unsettled};
use horus_ros_rmw::{Context, Node};

use crate::{CliError, Global};

/// The shortest discovery wait: peers answer a new participant's announcement within a few
/// milliseconds, but not at once.
const MIN_DISCOVERY: Duration = Duration::from_millis(120);
/// Once what is known is consistent, the wait ends when nothing has changed for this long
/// (participants not seen yet get this long to show up).
const GRACE: Duration = Duration::from_millis(30);

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
        // The CLI is not a ROS executable: its own arguments are not `--ros-args`.
        let mut builder = Context::builder()
            .backend(global.backend.into())
            .arguments(horus_ros_rmw::args::Arguments::default());
        if let Some(d) = global.domain_id {
            builder = builder.domain_id(d);
        }
        let context = builder.build()?;
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
    /// participant, including one known only from its endpoints, has sent its
    /// `ros_discovery_info`, and every endpoint it lists is discovered) and has not changed for
    /// [`GRACE`]. Every wait is on the graph's change notification. When `--spin-time` runs out
    /// first, one line on stderr says what is missing, so an incomplete answer is never silent.
    pub fn settle(&self, global: &Global) {
        let start = Instant::now();
        let limit = Duration::from_secs_f64(global.spin_time.max(0.0));
        loop {
            let elapsed = start.elapsed();
            let left = limit.saturating_sub(elapsed);
            if left.is_zero() {
                break;
            }
            if elapsed < MIN_DISCOVERY {
                self.graph
                    .wait_for_graph_change((MIN_DISCOVERY - elapsed).min(left));
                continue;
            }
            if self.graph.read(|c| c.is_consistent()) {
                if !self.graph.wait_for_graph_change(GRACE.min(left)) {
                    return;
                }
            } else {
                // Woken by the change that may settle it, or by the end of the spin time.
                self.graph.wait_until(left, |c| c.is_consistent());
            }
        }
        let unsettled = self.graph.read(|c| c.unsettled());
        if !unsettled.is_empty() {
            eprintln!("{}", incomplete_warning(limit, &unsettled));
        }
    }
}

/// The one stderr line for a discovery wait that ran out before the graph was consistent.
pub fn incomplete_warning(limit: Duration, unsettled: &Unsettled) -> String {
    let mut missing = Vec::new();
    match unsettled.unannounced.as_slice() {
        [] => {}
        [one] => missing.push(format!(
            "participant {one} has not announced its nodes (ros_discovery_info)"
        )),
        many => missing.push(format!(
            "{} participants have not announced their nodes",
            many.len()
        )),
    }
    match unsettled.missing_endpoints {
        0 => {}
        1 => missing.push("1 endpoint listed by a node is not discovered yet".to_owned()),
        n => missing.push(format!(
            "{n} endpoints listed by nodes are not discovered yet"
        )),
    }
    format!(
        "WARNING: discovery incomplete after --spin-time {}: {}; the answer may be incomplete \
         (raise --spin-time, or run 'horus-ros daemon start')",
        seconds(limit),
        missing.join(", ")
    )
}

/// Seconds as `--spin-time` takes them (`0.5 s`).
fn seconds(d: Duration) -> String {
    format!("{} s", d.as_secs_f64())
}
