//! `horus-ros lifecycle nodes` (ros2lifecycle `verb/nodes.py`).

use serde_json::Value;

use super::lifecycle_nodes;
use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `lifecycle nodes`.
#[derive(Debug, clap::Args)]
pub struct NodesArgs {
    /// Display all nodes even hidden ones.
    #[arg(short, long)]
    pub all: bool,
    /// Only display the number of nodes discovered.
    #[arg(short, long)]
    pub count_nodes: bool,
}

/// Runs `lifecycle nodes`: the lifecycle nodes' full names, sorted, one a line (or their
/// number); nothing when there are none.
pub fn run(global: &Global, args: &NodesArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let nodes = lifecycle_nodes(&source, args.all);
    if args.count_nodes {
        return if global.json {
            names::print_json(&names::count_json(nodes.len()))
        } else {
            println!("{}", nodes.len());
            Ok(())
        };
    }
    if global.json {
        return names::print_json(&Value::Array(
            nodes.into_iter().map(Value::String).collect(),
        ));
    }
    for node in nodes {
        println!("{node}");
    }
    Ok(())
}
