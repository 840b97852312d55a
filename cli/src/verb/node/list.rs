//! `horus-ros node list` (ros2node `verb/list.py`).

use serde_json::{json, Value};

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// ros2node's warning when two nodes share a full name.
const DUPLICATE_WARNING: &str = "WARNING: Be aware that there are nodes in the graph that share \
                                 an exact name, which can have unintended side effects.";

/// Arguments of `node list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Display all nodes even hidden ones.
    #[arg(short = 'a', long)]
    pub all: bool,
    /// Only display the number of nodes discovered.
    #[arg(short = 'c', long)]
    pub count_nodes: bool,
}

/// Runs `node list`: full names sorted, one a line (a warning on stderr when two nodes share a
/// name); hidden nodes (name starting with `_`, ours included) only with `-a`.
pub fn run(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let mut nodes: Vec<(String, horus_ros_graph::NodeInfo)> = source
        .read(|c| c.node_names())
        .into_iter()
        .filter(|n| args.all || !names::is_hidden_node(&n.name))
        .map(|n| (names::node_full_name(&n.namespace, &n.name), n))
        .collect();
    if args.count_nodes {
        return if global.json {
            names::print_json(&names::count_json(nodes.len()))
        } else {
            println!("{}", nodes.len());
            Ok(())
        };
    }
    nodes.sort_by(|a, b| a.0.cmp(&b.0));
    if nodes.windows(2).any(|w| w[0].0 == w[1].0) {
        eprintln!("{DUPLICATE_WARNING}");
    }
    if global.json {
        let list: Vec<Value> = nodes
            .iter()
            .map(|(full_name, n)| {
                json!({
                    "full_name": full_name,
                    "name": n.name,
                    "namespace": n.namespace,
                    "enclave": n.enclave,
                })
            })
            .collect();
        return names::print_json(&Value::Array(list));
    }
    for (full_name, _) in &nodes {
        println!("{full_name}");
    }
    Ok(())
}
