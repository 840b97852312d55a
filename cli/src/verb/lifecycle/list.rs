//! `horus-ros lifecycle list` (ros2lifecycle `verb/list.py`).

use serde_json::{json, Value};

use super::{absolute, client, direct, exception, require_node, transition_json, CALL_TIMEOUT};
use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `lifecycle list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Name of the ROS node.
    pub node_name: String,
    /// Consider hidden nodes as well.
    #[arg(long)]
    pub include_hidden_nodes: bool,
    /// Display all existing transitions.
    #[arg(short, long)]
    pub all: bool,
}

/// Runs `lifecycle list`: the transitions from the node's current state (`--all`: every
/// transition), each as `- <label> [<id>]`, `\tStart: <label>`, `\tGoal: <label>`.
pub fn run(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let node = absolute(&args.node_name);
    require_node(&source, &node, args.include_hidden_nodes)?;
    let session = direct(global, source)?;
    let mut lifecycle = client(&session, &node)?;
    // With no state to filter by (`states={node_name: None}`), every description is listed.
    let transitions = if args.all {
        lifecycle.transition_graph(CALL_TIMEOUT)
    } else {
        lifecycle.available_transitions(CALL_TIMEOUT)
    }
    .map_err(|e| CliError::new(exception(&args.node_name, &e)))?;
    if global.json {
        let list: Vec<Value> = transitions.iter().map(transition_json).collect();
        return names::print_json(&json!({"node": node, "transitions": list}));
    }
    for t in &transitions {
        println!(
            "- {} [{}]\n\tStart: {}\n\tGoal: {}",
            t.transition.label, t.transition.id, t.start_state.label, t.goal_state.label
        );
    }
    Ok(())
}
