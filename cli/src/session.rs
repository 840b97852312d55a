//! [`Session`]: the CLI's own hidden node on the graph, and the wait for discovery.

use std::sync::Arc;
use std::time::{Duration, Instant};

use horus_ros_graph::{Graph, GraphCache, Unsettled};
use horus_ros_rmw::{BackendError, Context, ContextError, Node};

use crate::{CliError, Global};

/// The shortest discovery wait: peers answer a new participant's announcement within a few
/// milliseconds, but not at once.
const MIN_DISCOVERY: Duration = Duration::from_millis(120);
/// The part of `--spin-time` always waited (when more than [`MIN_DISCOVERY`]): a peer that
/// answers our announcement late (a loaded machine, a slow network) is not taken for absent
/// when the user gave discovery more time.
const MIN_DISCOVERY_SHARE: u32 = 10;
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
    /// When the graph started following discovery.
    pub joined: Instant,
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
        Self::join_as(global, &format!("_horus_ros_{}", std::process::id()))
    }

    /// Joins the domain with a node named `node_name` (in `/`), without waiting.
    pub fn join_as(global: &Global, node_name: &str) -> Result<Self, CliError> {
        // The CLI is not a ROS executable: its own arguments are not `--ros-args`.
        let mut builder = Context::builder().arguments(horus_ros_rmw::args::Arguments::default());
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
        let node = context.create_node(node_name, "/")?;
        let graph = Graph::shared(&context)?;
        Ok(Self {
            context,
            node,
            graph,
            joined: Instant::now(),
        })
    }

    /// Waits for discovery, never longer than `--spin-time` (ros2cli always waits the whole
    /// spin time; see [`wait_settled`]). When `--spin-time` runs out first, one line on stderr
    /// says what is missing, so an incomplete answer is never silent.
    pub fn settle(&self, global: &Global) {
        let limit = spin_time(global);
        let deadline = deadline_after(Instant::now(), limit);
        let unsettled = wait_settled(&self.graph, self.joined, deadline);
        if !unsettled.is_empty() {
            eprintln!(
                "{}",
                incomplete_warning(limit, &unsettled, Hint::StartDaemon)
            );
        }
    }
}

/// `--spin-time` as a duration (negative: none; too large for one: the longest there is).
pub fn spin_time(global: &Global) -> Duration {
    Duration::try_from_secs_f64(global.spin_time.max(0.0)).unwrap_or(Duration::MAX)
}

/// `start + limit`, or a moment far enough away when that cannot be represented.
pub fn deadline_after(start: Instant, limit: Duration) -> Instant {
    const FAR: Duration = Duration::from_secs(100 * 365 * 24 * 3600);
    start
        .checked_add(limit.min(FAR))
        .unwrap_or(start + Duration::from_secs(24 * 3600))
}

/// Waits until `graph` (following discovery since `joined`) has settled, never past
/// `deadline`, and returns what is still unsettled (nothing when it settled): at least
/// [`MIN_DISCOVERY`] after `joined` (or a tenth of the time to `deadline`, if more), then until what is known is consistent (every
/// participant, including one known only from its endpoints, has sent its
/// `ros_discovery_info`, and every endpoint it lists is discovered) and has not changed for
/// [`GRACE`]. Every wait is on the graph's change notification. A graph that has been
/// consistent and quiet for a while (the daemon's) answers at once.
pub fn wait_settled(graph: &Graph, joined: Instant, deadline: Instant) -> Unsettled {
    loop {
        let now = Instant::now();
        if now >= deadline {
            break;
        }
        let left = deadline - now;
        let discovering_until = joined
            + MIN_DISCOVERY.max(deadline.saturating_duration_since(joined) / MIN_DISCOVERY_SHARE);
        if now < discovering_until {
            graph.wait_for_graph_change((discovering_until - now).min(left));
            continue;
        }
        if graph.read(|c| c.is_consistent()) {
            let quiet_from = graph.last_change() + GRACE;
            if now >= quiet_from {
                return Unsettled::default();
            }
            graph.wait_for_graph_change((quiet_from - now).min(left));
        } else {
            // Woken by the change that may settle it, or at the deadline.
            graph.wait_until(left, |c| c.is_consistent());
        }
    }
    graph.read(|c| c.unsettled())
}

/// Where the query verbs read the graph from: a snapshot from the daemon when one runs for this
/// domain and these discovery settings (`horus-ros daemon start`), else discovery of their own.
pub enum GraphSource {
    /// This process's own participant and the graph it discovered.
    Direct(Box<Session>),
    /// The graph the daemon answered with.
    Daemon {
        /// The daemon's graph, rebuilt from its snapshot.
        cache: GraphCache,
        /// The daemon's domain.
        domain_id: u16,
    },
}

impl GraphSource {
    /// The daemon's graph when it runs (and `--no-daemon` is not given) and answers, else a
    /// [`Session`] of our own, settled as [`Session::open`] does. A daemon that does not answer
    /// properly costs one warning line on stderr, then discovery as without it; an incomplete
    /// answer of the daemon (its graph did not settle within `--spin-time`) costs the same one
    /// line as an incomplete discovery of our own.
    pub fn open(global: &Global) -> Result<Self, CliError> {
        if !global.no_daemon {
            if let Some(answer) = crate::daemon::client::graph(global) {
                let unsettled = answer.cache.unsettled();
                if !unsettled.is_empty() {
                    eprintln!(
                        "{}",
                        incomplete_warning(spin_time(global), &unsettled, Hint::RaiseSpinTime)
                    );
                }
                return Ok(Self::Daemon {
                    cache: answer.cache,
                    domain_id: answer.domain_id,
                });
            }
        }
        Ok(Self::Direct(Box::new(Session::open(global)?)))
    }

    /// Runs `f` on the graph.
    pub fn read<R>(&self, f: impl FnOnce(&GraphCache) -> R) -> R {
        match self {
            Self::Direct(session) => session.graph.read(f),
            Self::Daemon { cache, .. } => f(cache),
        }
    }

    /// The domain of the graph.
    pub fn domain_id(&self) -> u16 {
        match self {
            Self::Direct(session) => session.context.domain_id().get(),
            Self::Daemon { domain_id, .. } => *domain_id,
        }
    }
}

/// What an incomplete answer suggests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hint {
    /// A longer wait, or the daemon (whose graph is warm).
    StartDaemon,
    /// A longer wait (the daemon already answers).
    RaiseSpinTime,
}

/// The one stderr line for a discovery wait that ran out before the graph was consistent.
pub fn incomplete_warning(limit: Duration, unsettled: &Unsettled, hint: Hint) -> String {
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
         ({})",
        seconds(limit),
        missing.join(", "),
        match hint {
            Hint::StartDaemon => "raise --spin-time, or run 'horus-ros daemon start'",
            Hint::RaiseSpinTime => "raise --spin-time",
        }
    )
}

/// Seconds as `--spin-time` takes them (`0.5 s`).
fn seconds(d: Duration) -> String {
    format!("{} s", d.as_secs_f64())
}
