//! [`Session`]: the CLI's own hidden node on the graph, and where the query verbs read the
//! graph from ([`GraphSource`]: the daemon's, or a session's own).

use std::sync::Arc;
use std::time::Instant;

use horus_ros_graph::{Graph, GraphCache};
use horus_ros_rmw::{BackendError, Context, ContextError, Node};

use crate::settle::{incomplete_warning, spin_time, Outstanding, Wait};
use crate::{CliError, Global};

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
    /// Which participants have been outstanding since when, until the session has settled.
    outstanding: Option<Arc<Outstanding>>,
}

impl Session {
    /// Joins the domain and waits for discovery to settle ([`settle`](Self::settle)).
    pub fn open(global: &Global) -> Result<Self, CliError> {
        let mut session = Self::join(global)?;
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
        let graph = Graph::of(&context)?;
        let outstanding = Some(Outstanding::watch(&graph));
        Ok(Self {
            context,
            node,
            graph,
            joined: Instant::now(),
            outstanding,
        })
    }

    /// Waits for discovery (see [`crate::settle`]): until the graph is complete and quiet, at
    /// most until its bounds. When a bound is hit first, one line on stderr says what is
    /// missing, so an incomplete answer is never silent. The tracking of outstanding
    /// participants ends here.
    pub fn settle(&mut self, global: &Global) {
        let outstanding = self
            .outstanding
            .take()
            .unwrap_or_else(|| Outstanding::watch(&self.graph));
        let wait = Wait {
            graph: &self.graph,
            outstanding: &outstanding,
            joined: self.joined,
            start: self.joined,
            spin: spin_time(global),
        };
        if let Some(incomplete) = wait.run() {
            eprintln!("{}", incomplete_warning(&incomplete));
        }
    }

    /// The tracker of outstanding participants, for a session that keeps waiting for its graph
    /// (the daemon's).
    pub fn outstanding(&self) -> Option<&Arc<Outstanding>> {
        self.outstanding.as_ref()
    }
}

/// Where the query verbs read the graph from: a snapshot from the daemon of this domain and
/// these discovery settings (started on first use), else discovery of their own.
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
    /// The daemon's graph unless `--no-daemon` is given: from the daemon that runs for these
    /// options, else from one started now (as ros2cli starts its daemon on first use; see
    /// [`crate::daemon::client::graph_or_spawn`]). Else (`--no-daemon`, or a daemon that could
    /// not be started or used, which costs one line on stderr) a [`Session`] of our own,
    /// settled as [`Session::open`] does. An incomplete answer of the daemon (its wait hit a
    /// bound) costs the same one line as an incomplete discovery of our own.
    pub fn open(global: &Global) -> Result<Self, CliError> {
        if !global.no_daemon {
            if let Some(answer) = crate::daemon::client::graph_or_spawn(global) {
                if let Some(incomplete) = &answer.incomplete {
                    eprintln!("{}", incomplete_warning(incomplete));
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
