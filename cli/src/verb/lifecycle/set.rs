//! `horus-ros lifecycle set` (ros2lifecycle `verb/set.py`).

use serde_json::json;

use super::{absolute, client, direct, exception, require_node, CALL_TIMEOUT};
use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `lifecycle set`.
#[derive(Debug, clap::Args)]
pub struct SetArgs {
    /// Name of the ROS node.
    pub node_name: String,
    /// Consider hidden nodes as well.
    #[arg(long)]
    pub include_hidden_nodes: bool,
    /// The lifecycle transition.
    pub transition: String,
}

/// Runs `lifecycle set`: the transition named by label (or else by id) among the node's
/// available ones; "Transitioning successful" on stdout, or "Transitioning failed" on stderr
/// (exit status 0 both, as ros2lifecycle).
pub fn run(global: &Global, args: &SetArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let node = absolute(&args.node_name);
    require_node(&source, &node, args.include_hidden_nodes)?;
    let session = direct(global, source)?;
    let mut lifecycle = client(&session, &node)?;
    let transitions = lifecycle
        .available_transitions(CALL_TIMEOUT)
        .map_err(|e| CliError::new(exception(&args.node_name, &e)))?;
    // By label first, then by the id's decimal text (`str(transition.id)`).
    let chosen = transitions
        .iter()
        .map(|t| &t.transition)
        .find(|t| t.label == args.transition)
        .or_else(|| {
            transitions
                .iter()
                .map(|t| &t.transition)
                .find(|t| t.id.to_string() == args.transition)
        })
        .cloned();
    let Some(transition) = chosen else {
        let available: String = transitions
            .iter()
            .map(|t| format!("\n- {} [{}]", t.transition.label, t.transition.id))
            .collect();
        return Err(CliError::new(format!(
            "Unknown transition requested, available ones are:{available}"
        )));
    };
    let result = lifecycle.change_state_msg(transition.clone(), CALL_TIMEOUT);
    if global.json {
        return match result {
            Ok(success) => names::print_json(&json!({
                "node": node,
                "transition": {"id": transition.id, "label": transition.label},
                "success": success,
            })),
            Err(e) => Err(CliError::new(exception(&args.node_name, &e))),
        };
    }
    match result {
        Err(e) => eprintln!("{}", exception(&args.node_name, &e)),
        Ok(true) => println!("Transitioning successful"),
        Ok(false) => eprintln!("Transitioning failed"),
    }
    Ok(())
}
