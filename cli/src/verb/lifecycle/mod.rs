//! `horus-ros lifecycle …`: ros2cli's `ros2 lifecycle` verbs (ros2lifecycle 0.32, Jazzy:
//! `ros2lifecycle/verb/{nodes,list,get,set}.py`, `ros2lifecycle/api/__init__.py`), calling a
//! managed node's `~/get_state`, `~/get_available_transitions`, `~/get_transition_graph` and
//! `~/change_state` (lifecycle_msgs) through horus-ros-lifecycle's `LifecycleClient`.
//!
//! # `--json`
//!
//! - `lifecycle nodes`: `["/a", "/b"…]` (sorted); with `--count-nodes`: `{"count": N}`.
//! - `lifecycle list <node>`: `{"node", "transitions": [{"id", "label", "start": {"id",
//!   "label"}, "goal": {"id", "label"}}…]}`.
//! - `lifecycle get <node>`: `{"node", "state": {"id", "label"}}`; without a node:
//!   `[{"node", "state": {…} | null, "error": null | "…"}…]`, sorted by node.
//! - `lifecycle set <node> <transition>`: `{"node", "transition": {"id", "label"}, "success"}`.

pub mod get;
pub mod list;
pub mod nodes;
pub mod set;

use std::time::Duration;

use clap::Subcommand;
use horus_ros_lifecycle::lifecycle_msgs::msg::{State, TransitionDescription};
use horus_ros_lifecycle::LifecycleClient;
use serde_json::{json, Value};

use crate::session::{GraphSource, Session};
use crate::verb::names;
use crate::{CliError, Global};

/// How long one lifecycle service may take to be ready and answer (ros2lifecycle waits without
/// a bound).
pub const CALL_TIMEOUT: Duration = Duration::from_secs(30);

/// The `lifecycle` verbs.
#[derive(Debug, Subcommand)]
pub enum LifecycleCommand {
    /// Output a list of nodes with lifecycle.
    Nodes(nodes::NodesArgs),
    /// Output a list of available transitions.
    List(list::ListArgs),
    /// Get lifecycle state for one or more nodes.
    Get(get::GetArgs),
    /// Trigger lifecycle state transition.
    Set(set::SetArgs),
}

/// Runs a `lifecycle` verb.
pub fn run(global: &Global, command: LifecycleCommand) -> Result<(), CliError> {
    match command {
        LifecycleCommand::Nodes(a) => nodes::run(global, &a),
        LifecycleCommand::List(a) => list::run(global, &a),
        LifecycleCommand::Get(a) => get::run(global, &a),
        LifecycleCommand::Set(a) => set::run(global, &a),
    }
}

/// ros2lifecycle's `get_node_names`: the full names of the nodes (hidden ones only when asked)
/// that offer `<node>/get_state` of type `lifecycle_msgs/srv/GetState` (hidden services only
/// when hidden nodes are asked for), sorted and without duplicates.
pub fn lifecycle_nodes(source: &GraphSource, include_hidden: bool) -> Vec<String> {
    let mut found: Vec<String> = source.read(|c| {
        let services = c.service_names_and_types(include_hidden);
        c.node_names()
            .into_iter()
            .filter(|n| include_hidden || !names::is_hidden_node(&n.name))
            .map(|n| names::node_full_name(&n.namespace, &n.name))
            .filter(|full| {
                services
                    .get(&format!("{full}/get_state"))
                    .is_some_and(|types| types.contains("lifecycle_msgs/srv/GetState"))
            })
            .collect()
    });
    found.sort();
    found.dedup();
    found
}

/// Checks that `node` is a lifecycle node of the graph ("Node not found" otherwise, as
/// ros2lifecycle). A session of our own (`--no-daemon`, or no daemon) is younger than the
/// daemon ros2cli asks: when the node is not there yet it waits for it, woken by graph changes,
/// until [`ENDPOINTS_BOUND`](crate::settle::ENDPOINTS_BOUND) after joining (a participant not
/// heard of at all when the discovery wait ended, on a loaded machine, is usually heard by then).
pub fn require_node(
    source: &GraphSource,
    node: &str,
    include_hidden: bool,
) -> Result<(), CliError> {
    let found = |source: &GraphSource| {
        lifecycle_nodes(source, include_hidden)
            .iter()
            .any(|n| n == node)
    };
    let GraphSource::Direct(session) = source else {
        return if found(source) {
            Ok(())
        } else {
            Err(CliError::new("Node not found"))
        };
    };
    let deadline = session.joined + crate::settle::ENDPOINTS_BOUND;
    loop {
        let seen = session.graph.generation();
        if found(source) {
            return Ok(());
        }
        let now = std::time::Instant::now();
        if now >= deadline {
            return Err(CliError::new("Node not found"));
        }
        session
            .graph
            .wait_for_graph_change_since(seen, deadline - now);
    }
}

/// ros2node's `get_absolute_node_name`.
pub fn absolute(name: &str) -> String {
    crate::verb::param::absolute_node_name(name)
}

/// ros2cli's `DirectNode`: the session the graph came from when it is our own, else a new one
/// (the calls wait for their services themselves).
pub fn direct(global: &Global, source: GraphSource) -> Result<Session, CliError> {
    match source {
        GraphSource::Direct(session) => Ok(*session),
        GraphSource::Daemon { .. } => Session::join(global),
    }
}

/// A lifecycle client of `node` on the session's node.
pub fn client(session: &Session, node: &str) -> Result<LifecycleClient, CliError> {
    Ok(LifecycleClient::builder()
        .node(&session.node)
        .target(node)
        .build()?)
}

/// An error and its causes, as one line (`a: b: c`): what the exception would say.
pub fn error_text(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

/// ros2lifecycle's text for a failed call.
pub fn exception(node_name: &str, e: &dyn std::error::Error) -> String {
    format!(
        "Exception while calling service of node '{node_name}': {}",
        error_text(e)
    )
}

/// A state as JSON.
pub fn state_json(s: &State) -> Value {
    json!({"id": s.id, "label": s.label})
}

/// A transition description as JSON.
pub fn transition_json(t: &TransitionDescription) -> Value {
    json!({
        "id": t.transition.id,
        "label": t.transition.label,
        "start": state_json(&t.start_state),
        "goal": state_json(&t.goal_state),
    })
}
