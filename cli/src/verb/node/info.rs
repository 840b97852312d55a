//! `horus-ros node info` (ros2node `verb/info.py`).

use horus_ros_graph::{GraphCache, NamesAndTypes};
use horus_ros_rmw::names::is_hidden_name;
use serde_json::json;

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `node info`.
#[derive(Debug, clap::Args)]
pub struct InfoArgs {
    /// Node name to request information.
    pub node_name: String,
    /// Display hidden topics, services, and actions as well.
    #[arg(long)]
    pub include_hidden: bool,
}

/// The six sections, in ros2cli's order.
struct NodeDetails {
    subscribers: NamesAndTypes,
    publishers: NamesAndTypes,
    service_servers: NamesAndTypes,
    service_clients: NamesAndTypes,
    action_servers: NamesAndTypes,
    action_clients: NamesAndTypes,
}

/// Runs `node info`: the node's full name then its sections. The name must be the node's exact
/// full name as `node list` prints it (ros2cli compares strings); hidden nodes, topics,
/// services and actions only with `--include-hidden`.
pub fn run(global: &Global, args: &InfoArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let (count, details) = source.read(|c| read(c, &args.node_name, args.include_hidden));
    if count > 1 {
        eprintln!(
            "There are {count} nodes in the graph with the exact name \"{}\". \
             You are seeing information about only one of them.",
            args.node_name
        );
    }
    let details = match details {
        Some(details) => details?,
        None => {
            return Err(CliError::new(format!(
                "Unable to find node '{}'",
                args.node_name
            )))
        }
    };
    if global.json {
        let (name, namespace) = names::parse_node_name(&args.node_name);
        return names::print_json(&json!({
            "full_name": args.node_name,
            "name": name,
            "namespace": namespace,
            "subscribers": names::names_and_types_json(&details.subscribers),
            "publishers": names::names_and_types_json(&details.publishers),
            "service_servers": names::names_and_types_json(&details.service_servers),
            "service_clients": names::names_and_types_json(&details.service_clients),
            "action_servers": names::names_and_types_json(&details.action_servers),
            "action_clients": names::names_and_types_json(&details.action_clients),
        }));
    }
    print!("{}", render(&args.node_name, &details));
    Ok(())
}

/// How many nodes have that full name, and the details of the first.
fn read(
    cache: &GraphCache,
    full_name: &str,
    include_hidden: bool,
) -> (usize, Option<Result<NodeDetails, CliError>>) {
    let count = cache
        .node_names()
        .iter()
        .filter(|n| include_hidden || !names::is_hidden_node(&n.name))
        .filter(|n| names::node_full_name(&n.namespace, &n.name) == full_name)
        .count();
    if count == 0 {
        return (0, None);
    }
    let (name, namespace) = names::parse_node_name(full_name);
    let visible = |mut nt: NamesAndTypes| {
        if !include_hidden {
            nt.retain(|n, _| !is_hidden_name(n));
        }
        nt
    };
    let details = (|| {
        let publishers = cache.publisher_names_and_types_by_node(&name, &namespace)?;
        let subscribers = cache.subscription_names_and_types_by_node(&name, &namespace)?;
        Ok(NodeDetails {
            action_servers: visible(horus_ros_graph::filter_action_names(&publishers)),
            action_clients: visible(horus_ros_graph::filter_action_names(&subscribers)),
            service_servers: visible(cache.service_names_and_types_by_node(&name, &namespace)?),
            service_clients: visible(cache.client_names_and_types_by_node(&name, &namespace)?),
            subscribers: visible(subscribers),
            publishers: visible(publishers),
        })
    })()
    .map_err(|e: horus_ros_graph::GraphError| CliError::new(e.to_string()));
    (count, Some(details))
}

/// ros2cli's `print_names_and_types` for one section: `    /name: type, type` lines; an empty
/// section still prints one empty line (`print(*[], sep='\n')`).
fn section(out: &mut String, title: &str, items: &NamesAndTypes) {
    out.push_str(title);
    out.push('\n');
    let lines: Vec<String> = items
        .iter()
        .map(|(name, types)| {
            let types: Vec<&str> = types.iter().map(String::as_str).collect();
            format!("    {name}: {}", types.join(", "))
        })
        .collect();
    out.push_str(&lines.join("\n"));
    out.push('\n');
}

fn render(full_name: &str, d: &NodeDetails) -> String {
    let mut out = format!("{full_name}\n");
    section(&mut out, "  Subscribers:", &d.subscribers);
    section(&mut out, "  Publishers:", &d.publishers);
    section(&mut out, "  Service Servers:", &d.service_servers);
    section(&mut out, "  Service Clients:", &d.service_clients);
    section(&mut out, "  Action Servers:", &d.action_servers);
    section(&mut out, "  Action Clients:", &d.action_clients);
    out
}
