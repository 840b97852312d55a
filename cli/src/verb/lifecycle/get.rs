//! `horus-ros lifecycle get` (ros2lifecycle `verb/get.py`).

use serde_json::{json, Value};

use super::{
    absolute, client, direct, exception, lifecycle_nodes, require_node, state_json, CALL_TIMEOUT,
};
use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `lifecycle get`.
#[derive(Debug, clap::Args)]
pub struct GetArgs {
    /// Name of the ROS node. If no name is provided, then get the state for all nodes.
    pub node_name: Option<String>,
    /// Consider hidden nodes as well.
    #[arg(long)]
    pub include_hidden_nodes: bool,
}

/// Runs `lifecycle get`: `<label> [<id>]` for one node; `<node>: <label> [<id>]` for every
/// lifecycle node (sorted) without one. A node whose service failed is reported on stderr
/// (and ends the command, exit status 1, when it was named).
pub fn run(global: &Global, args: &GetArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let to_query = match &args.node_name {
        Some(name) => {
            let node = absolute(name);
            require_node(&source, &node, args.include_hidden_nodes)?;
            vec![node]
        }
        None => lifecycle_nodes(&source, args.include_hidden_nodes),
    };
    let session = direct(global, source)?;
    let mut states = Vec::new();
    for node in &to_query {
        let state = client(&session, node)?.get_state(CALL_TIMEOUT);
        states.push((node.clone(), state));
    }
    // `states` is keyed by node and printed sorted (the names are sorted already).
    if global.json {
        if args.node_name.is_some() {
            return match states.pop() {
                Some((node, Ok(state))) => {
                    names::print_json(&json!({"node": node, "state": state_json(&state)}))
                }
                Some((node, Err(e))) => Err(CliError::new(exception(&node, &e))),
                None => Ok(()),
            };
        }
        let list: Vec<Value> = states
            .iter()
            .map(|(node, state)| match state {
                Ok(s) => json!({"node": node, "state": state_json(s), "error": null}),
                Err(e) => json!({"node": node, "state": null, "error": exception(node, e)}),
            })
            .collect();
        return names::print_json(&Value::Array(list));
    }
    let mut ok = Vec::new();
    for (node, state) in states {
        match state {
            Ok(s) => ok.push((node, s)),
            Err(e) => {
                eprintln!("{}", exception(&node, &e));
                if args.node_name.is_some() {
                    return Err(CliError {
                        message: String::new(),
                        code: 1,
                    });
                }
            }
        }
    }
    for (node, state) in ok {
        let prefix = if args.node_name.is_some() {
            String::new()
        } else {
            format!("{node}: ")
        };
        println!("{prefix}{} [{}]", state.label, state.id);
    }
    Ok(())
}
