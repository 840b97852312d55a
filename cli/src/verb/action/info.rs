//! `horus-ros action info` (ros2action `verb/info.py`, `api/__init__.py`
//! `get_action_clients_and_servers`).

use horus_ros_graph::{ActionEndpoints, ActionUser};
use horus_ros_rmw::names::{Namespace, NodeName, TopicName};
use serde_json::{json, Value};

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `action info`.
#[derive(Debug, clap::Args)]
pub struct InfoArgs {
    /// Name of the ROS action to get info (e.g. '/fibonacci').
    pub action_name: String,
    /// Additionally show the action type.
    #[arg(short = 't', long)]
    pub show_types: bool,
    /// Only display the number of action clients and action servers.
    #[arg(short = 'c', long)]
    pub count: bool,
}

/// Runs `action info`: the name is expanded as a topic name of ros2cli's node (in `/`) and
/// must be valid; then its clients and servers.
pub fn run(global: &Global, args: &InfoArgs) -> Result<(), CliError> {
    let expanded = expand(&args.action_name)?;
    let source = GraphSource::open(global)?;
    let found = source.read(|c| c.action_clients_and_servers(&expanded));
    if global.json {
        return names::print_json(&json!({
            "name": args.action_name,
            "clients": users_json(&found.clients),
            "servers": users_json(&found.servers),
        }));
    }
    print!("{}", render(&args.action_name, &found, args));
    Ok(())
}

/// The action name as rclpy's `expand_topic_name` expands it for ros2cli's node (name
/// `_ros2cli`, namespace `/`), validated as a full topic name.
fn expand(given: &str) -> Result<String, CliError> {
    let invalid =
        |e: &dyn std::fmt::Display| CliError::new(format!("Invalid action name '{given}': {e}"));
    let node = NodeName::new("_ros2cli").map_err(|e| invalid(&e))?;
    let namespace = Namespace::new("/").map_err(|e| invalid(&e))?;
    TopicName::expand(given, &node, &namespace)
        .map(|t| t.as_str().to_owned())
        .map_err(|e| invalid(&e))
}

/// How ros2action 0.32 names a node in `info`: `'/'.join(node_ns) + node_name`, which joins
/// the namespace's characters with `/` (Jazzy's `api/__init__.py`): `/` + name for a node in
/// `/`, `//n/s` + name for one in `/ns`. Printed as Jazzy prints it; `--json` has the full name.
fn ros2action_node_name(user: &ActionUser) -> String {
    let ns: Vec<String> = user.node.namespace.chars().map(String::from).collect();
    format!("{}{}", ns.join("/"), user.node.name)
}

fn users_json(users: &[ActionUser]) -> Value {
    Value::Array(
        users
            .iter()
            .map(|u| {
                json!({
                    "node": names::node_full_name(&u.node.namespace, &u.node.name),
                    "types": u.types,
                })
            })
            .collect(),
    )
}

/// info.py's lines.
fn render(action: &str, found: &ActionEndpoints, args: &InfoArgs) -> String {
    let mut out = format!("Action: {action}\n");
    let section = |out: &mut String, title: &str, users: &[ActionUser]| {
        out.push_str(&format!("{title}: {}\n", users.len()));
        if args.count {
            return;
        }
        for u in users {
            let name = ros2action_node_name(u);
            if args.show_types {
                out.push_str(&format!("    {name} [{}]\n", u.types.join(", ")));
            } else {
                out.push_str(&format!("    {name}\n"));
            }
        }
    };
    section(&mut out, "Action clients", &found.clients);
    section(&mut out, "Action servers", &found.servers);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_graph::NodeInfo;

    fn user(namespace: &str, name: &str) -> ActionUser {
        ActionUser {
            node: NodeInfo {
                namespace: namespace.into(),
                name: name.into(),
                enclave: None,
            },
            types: vec!["test_msgs/action/Fibonacci".into()],
        }
    }

    fn args(show_types: bool, count: bool) -> InfoArgs {
        InfoArgs {
            action_name: "/fibonacci".into(),
            show_types,
            count,
        }
    }

    #[test]
    fn lines_as_ros2action_prints_them() {
        let found = ActionEndpoints {
            clients: vec![],
            servers: vec![user("/", "fibonacci_action_server")],
        };
        assert_eq!(
            render("/fibonacci", &found, &args(false, false)),
            "Action: /fibonacci\nAction clients: 0\nAction servers: 1\n    /fibonacci_action_server\n"
        );
        assert_eq!(
            render("/fibonacci", &found, &args(true, false)),
            "Action: /fibonacci\nAction clients: 0\nAction servers: 1\n    \
             /fibonacci_action_server [test_msgs/action/Fibonacci]\n"
        );
        assert_eq!(
            render("/fibonacci", &found, &args(false, true)),
            "Action: /fibonacci\nAction clients: 0\nAction servers: 1\n"
        );
    }

    #[test]
    fn node_names_as_jazzy_joins_them() {
        assert_eq!(ros2action_node_name(&user("/", "n")), "/n");
        assert_eq!(ros2action_node_name(&user("/ns", "n")), "//n/sn");
    }

    #[test]
    fn names_expand_relative_to_the_root() {
        assert_eq!(expand("fibonacci").ok(), Some("/fibonacci".to_owned()));
        assert!(expand("/bad name").is_err());
    }
}
