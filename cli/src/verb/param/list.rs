//! `horus-ros param list` (ros2param `verb/list.py`).

use std::time::{Duration, Instant};

use horus_ros_dynamic::repr::py_str;
use horus_ros_msgs::rcl_interfaces::srv::{
    DescribeParameters, DescribeParametersRequest, ListParameters, ListParametersRequest,
};
use regex::Regex;
use serde_json::{json, Value};

use super::{absolute_node_name, client, node_names, type_string, CALL_TIMEOUT, SERVICE_WAIT};
use crate::session::{GraphSource, Session};
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `param list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Name of the ROS node.
    pub node_name: Option<String>,
    /// Only parameters matching the regex expression will be showed. Supports `re` regex
    /// syntax.
    #[arg(long, value_name = "FILTER")]
    pub filter: Option<String>,
    /// Consider hidden nodes as well.
    #[arg(long)]
    pub include_hidden_nodes: bool,
    /// Only list parameters with the provided prefixes.
    #[arg(long, value_name = "PARAM_PREFIXES", num_args = 1..)]
    pub param_prefixes: Vec<String>,
    /// Print parameter types with parameter names.
    #[arg(long)]
    pub param_type: bool,
}

/// One node's answer.
struct Listed {
    full_name: String,
    /// The names (sorted, filtered), or the error line and whether it goes to stdout.
    names: Result<Vec<String>, (String, bool)>,
}

/// Runs `param list`: each node's parameter names, sorted (under a `/node:` header when no node
/// is named).
pub fn run(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    // `re.match`: anchored at the start only.
    let filter = args
        .filter
        .as_deref()
        .map(|f| Regex::new(&format!("^(?:{f})")))
        .transpose()
        .map_err(|e| CliError::new(format!("invalid --filter: {e}")))?;
    // ros2param's `NodeStrategy` (the daemon's graph, as the query verbs read it) for the
    // nodes, then its `DirectNode` for the calls (each waits for its service).
    let source = GraphSource::open(global)?;
    let mut nodes = node_names(&source, args.include_hidden_nodes);
    if let Some(name) = &args.node_name {
        let name = absolute_node_name(name);
        if !nodes.iter().any(|n| n.2 == name) {
            return Err(CliError::new("Node not found"));
        }
        nodes.retain(|n| n.2 == name);
    }
    // `sorted(responses.keys())`: ros2node's NodeName tuples, (name, namespace, full_name).
    nodes.sort();
    nodes.dedup();
    let session = crate::verb::lifecycle::direct(global, source)?;
    // All clients first: their discovery overlaps (ros2param waits 5 s for each in turn).
    let mut clients = nodes
        .iter()
        .map(|n| client::<ListParameters>(&session, &n.2, "list_parameters"))
        .collect::<Result<Vec<_>, _>>()?;
    let start = Instant::now();
    let mut listed = Vec::new();
    for ((name, namespace, full_name), c) in nodes.iter().zip(&mut clients) {
        let wait = (start + SERVICE_WAIT).saturating_duration_since(Instant::now());
        let names = if !c.wait_for_service(wait.max(Duration::from_millis(1))) {
            Err((
                format!(
                    "Wait for service timed out waiting for parameter services for node \
                     NodeName(name={}, namespace={}, full_name={})",
                    py_str(name),
                    py_str(namespace),
                    py_str(full_name)
                ),
                true,
            ))
        } else {
            let request = ListParametersRequest {
                prefixes: args.param_prefixes.clone(),
                depth: 0,
            };
            match c.call(request, CALL_TIMEOUT) {
                Ok(r) => {
                    let mut names = r.result.names;
                    names.sort();
                    if let Some(f) = &filter {
                        names.retain(|n| f.is_match(n));
                    }
                    Ok(names)
                }
                Err(e) => Err((
                    format!("Exception while calling service of node '{full_name}': {e}"),
                    false,
                )),
            }
        };
        listed.push(Listed {
            full_name: full_name.clone(),
            names,
        });
    }
    let mut out = String::new();
    let mut documents = Vec::new();
    for l in &listed {
        let names = match &l.names {
            Ok(names) => names,
            Err((line, to_stdout)) => {
                if global.json {
                    documents.push(json!({"node": l.full_name, "parameters": [], "error": line}));
                } else if *to_stdout {
                    out.push_str(line);
                    out.push('\n');
                } else {
                    print!("{out}");
                    out.clear();
                    eprintln!("{line}");
                }
                continue;
            }
        };
        if args.node_name.is_none() && !names.is_empty() && !global.json {
            out.push_str(&format!("{}:\n", l.full_name));
        }
        let types = if args.param_type {
            Some(describe_types(&session, &l.full_name, names)?)
        } else {
            None
        };
        if global.json {
            let parameters: Vec<Value> = names
                .iter()
                .enumerate()
                .map(|(i, n)| json!({"name": n, "type": types.as_ref().map(|t| &t[i])}))
                .collect();
            documents.push(json!({"node": l.full_name, "parameters": parameters, "error": null}));
            continue;
        }
        for (i, name) in names.iter().enumerate() {
            match &types {
                Some(t) => out.push_str(&format!("  {name} (type: {})\n", t[i])),
                None => out.push_str(&format!("  {name}\n")),
            }
        }
    }
    if global.json {
        return names::print_json(&Value::Array(documents));
    }
    print!("{out}");
    Ok(())
}

/// The type strings of `names` (`--param-type`), from `<node>/describe_parameters`.
fn describe_types(
    session: &Session,
    node: &str,
    names: &[String],
) -> Result<Vec<String>, CliError> {
    let mut describe = client::<DescribeParameters>(session, node, "describe_parameters")?;
    let response = super::call(
        &mut describe,
        node,
        DescribeParametersRequest {
            names: names.to_vec(),
        },
    )?;
    // ros2param maps names to types through the descriptors' names.
    names
        .iter()
        .map(|n| {
            let d = response
                .descriptors
                .iter()
                .find(|d| d.name == *n)
                .ok_or_else(|| CliError::new(format!("KeyError: {}", py_str(n))))?;
            type_string(d.r#type)
                .map(str::to_owned)
                .ok_or_else(|| CliError::new(format!("KeyError: {}", d.r#type)))
        })
        .collect()
}
