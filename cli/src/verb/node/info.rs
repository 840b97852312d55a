//! `horus-ros node info` (ros2node `verb/info.py`).

use horus_ros_graph::{GraphCache, GraphError, NamesAndTypes};
use horus_ros_rmw::names::is_hidden_name;
use serde_json::{json, Map, Value};

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

/// A node's six sections, in ros2cli's order (`node info`, and each node of `graph`).
#[derive(Default)]
pub(crate) struct NodeDetails {
    subscribers: NamesAndTypes,
    publishers: NamesAndTypes,
    service_servers: NamesAndTypes,
    service_clients: NamesAndTypes,
    action_servers: NamesAndTypes,
    action_clients: NamesAndTypes,
}

impl NodeDetails {
    /// The sections of node `name` in `namespace` (ros2node `get_node_info`: actions are the
    /// action topics among the publishers and subscribers); hidden names only with
    /// `include_hidden`.
    pub(crate) fn read(
        cache: &GraphCache,
        name: &str,
        namespace: &str,
        include_hidden: bool,
    ) -> Result<Self, GraphError> {
        let visible = |mut nt: NamesAndTypes| {
            if !include_hidden {
                nt.retain(|n, _| !is_hidden_name(n));
            }
            nt
        };
        let publishers = cache.publisher_names_and_types_by_node(name, namespace)?;
        let subscribers = cache.subscription_names_and_types_by_node(name, namespace)?;
        Ok(Self {
            action_servers: visible(horus_ros_graph::filter_action_names(&publishers)),
            action_clients: visible(horus_ros_graph::filter_action_names(&subscribers)),
            service_servers: visible(cache.service_names_and_types_by_node(name, namespace)?),
            service_clients: visible(cache.client_names_and_types_by_node(name, namespace)?),
            subscribers: visible(subscribers),
            publishers: visible(publishers),
        })
    }

    /// Each section's title, JSON key and names with their types, in ros2cli's order.
    pub(crate) fn sections(&self) -> [(&'static str, &'static str, &NamesAndTypes); 6] {
        [
            ("Subscribers", "subscribers", &self.subscribers),
            ("Publishers", "publishers", &self.publishers),
            ("Service Servers", "service_servers", &self.service_servers),
            ("Service Clients", "service_clients", &self.service_clients),
            ("Action Servers", "action_servers", &self.action_servers),
            ("Action Clients", "action_clients", &self.action_clients),
        ]
    }

    /// Adds each section to `object` under its JSON key (`docs/cli-json.md`).
    pub(crate) fn add_json(&self, object: &mut Map<String, Value>) {
        for (_, key, list) in self.sections() {
            object.insert(key.to_owned(), names::names_and_types_json(list));
        }
    }
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
        let mut j = json!({
            "full_name": args.node_name,
            "name": name,
            "namespace": namespace,
        });
        if let Value::Object(object) = &mut j {
            details.add_json(object);
        }
        return names::print_json(&j);
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
    let details = NodeDetails::read(cache, &name, &namespace, include_hidden)
        .map_err(|e| CliError::new(e.to_string()));
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
    for (title, _, list) in d.sections() {
        section(&mut out, &format!("  {title}:"), list);
    }
    out
}
