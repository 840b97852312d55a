//! The whole graph as one document: nodes with their endpoints, topics and services, as text
//! or JSON (`docs/cli-json.md`).

use horus_ros_graph::{Gid, GraphCache, ServiceEndpointInfo, TopicEndpointInfo};
use horus_ros_rmw::qos::Qos;
use serde_json::{json, Value};

use crate::verb::names;
use crate::verb::node::info::NodeDetails;

/// One node and what it publishes, subscribes to, serves and calls (as `node info` reads it).
pub(super) struct NodeDoc {
    name: String,
    namespace: String,
    enclave: Option<String>,
    sections: NodeDetails,
}

/// One topic with its endpoints (as `topic info -v` reads it).
pub(super) struct TopicDoc {
    name: String,
    types: Vec<String>,
    publishers: Vec<TopicEndpointInfo>,
    subscriptions: Vec<TopicEndpointInfo>,
}

/// One service with its servers and clients (as `service info -v` reads it).
pub(super) struct ServiceDoc {
    name: String,
    types: Vec<String>,
    clients_count: usize,
    services_count: usize,
    clients: Vec<ServiceEndpointInfo>,
    servers: Vec<ServiceEndpointInfo>,
}

/// The whole graph, read under one lock so that its parts agree.
pub(super) struct GraphDoc {
    nodes: Vec<NodeDoc>,
    topics: Vec<TopicDoc>,
    services: Vec<ServiceDoc>,
}

impl GraphDoc {
    pub(super) fn read(cache: &GraphCache, all: bool) -> Self {
        let nodes = cache
            .node_names()
            .into_iter()
            .filter(|n| all || !names::is_hidden_node(&n.name))
            .map(|n| NodeDoc {
                sections: NodeDetails::read(cache, &n.name, &n.namespace, all).unwrap_or_default(),
                name: n.name,
                namespace: n.namespace,
                enclave: n.enclave,
            })
            .collect();
        let topics = cache
            .topic_names_and_types(all)
            .into_iter()
            .map(|(name, types)| TopicDoc {
                publishers: cache.publishers_info_by_topic(&name, false),
                subscriptions: cache.subscriptions_info_by_topic(&name, false),
                types: types.into_iter().collect(),
                name,
            })
            .collect();
        let services = cache
            .service_names_and_types(all)
            .into_iter()
            .map(|(name, types)| ServiceDoc {
                clients_count: cache.count_clients(&name),
                services_count: cache.count_services(&name),
                // Only an error with no_mangle, which is not used.
                clients: cache
                    .clients_info_by_service(&name, false)
                    .unwrap_or_default(),
                servers: cache
                    .servers_info_by_service(&name, false)
                    .unwrap_or_default(),
                types: types.into_iter().collect(),
                name,
            })
            .collect();
        Self {
            nodes,
            topics,
            services,
        }
    }

    /// The JSON document (`docs/cli-json.md`, "graph").
    pub(super) fn to_json(&self, domain_id: u16) -> Value {
        let nodes: Vec<Value> = self
            .nodes
            .iter()
            .map(|n| {
                let mut j = json!({
                    "full_name": names::node_full_name(&n.namespace, &n.name),
                    "name": n.name,
                    "namespace": n.namespace,
                    "enclave": n.enclave,
                });
                if let Value::Object(object) = &mut j {
                    n.sections.add_json(object);
                }
                j
            })
            .collect();
        let topics: Vec<Value> = self
            .topics
            .iter()
            .map(|t| {
                json!({
                    "name": t.name,
                    "types": t.types,
                    "publisher_count": t.publishers.len(),
                    "subscription_count": t.subscriptions.len(),
                    "publishers": t.publishers.iter().map(names::topic_endpoint_json).collect::<Vec<_>>(),
                    "subscriptions": t.subscriptions.iter().map(names::topic_endpoint_json).collect::<Vec<_>>(),
                })
            })
            .collect();
        let services: Vec<Value> = self
            .services
            .iter()
            .map(|s| {
                json!({
                    "name": s.name,
                    "types": s.types,
                    "clients_count": s.clients_count,
                    "services_count": s.services_count,
                    "clients": s.clients.iter().map(names::service_endpoint_json).collect::<Vec<_>>(),
                    "servers": s.servers.iter().map(names::service_endpoint_json).collect::<Vec<_>>(),
                })
            })
            .collect();
        json!({
            "domain_id": domain_id,
            "nodes": nodes,
            "topics": topics,
            "services": services,
        })
    }

    /// The text document (`docs/cli-json.md`, "graph: text layout").
    pub(super) fn render(&self, domain_id: u16) -> String {
        let mut out = format!(
            "Domain {domain_id}: {}, {}, {}\n",
            plural(self.nodes.len(), "node"),
            plural(self.topics.len(), "topic"),
            plural(self.services.len(), "service"),
        );
        out.push_str("\nNodes:\n");
        for n in &self.nodes {
            out.push_str(&format!(
                "  {}\n",
                names::node_full_name(&n.namespace, &n.name)
            ));
            for (title, _, list) in n.sections.sections() {
                if list.is_empty() {
                    continue;
                }
                out.push_str(&format!("    {title}:\n"));
                for (name, types) in list {
                    out.push_str(&format!("      {name}: {}\n", join_types(types)));
                }
            }
        }
        out.push_str("\nTopics:\n");
        for t in &self.topics {
            out.push_str(&format!("  {}: {}\n", t.name, join_types(&t.types)));
            for (title, list) in [
                ("Publishers", &t.publishers),
                ("Subscriptions", &t.subscriptions),
            ] {
                out.push_str(&format!("    {title} ({}):\n", list.len()));
                for e in list {
                    out.push_str(&format!(
                        "      {}  gid {}  {}\n",
                        endpoint_node(&e.node_namespace, &e.node_name),
                        e.endpoint_gid,
                        qos_summary(&e.qos_profile),
                    ));
                }
            }
        }
        out.push_str("\nServices:\n");
        for s in &self.services {
            out.push_str(&format!("  {}: {}\n", s.name, join_types(&s.types)));
            for (title, list) in [("Servers", &s.servers), ("Clients", &s.clients)] {
                out.push_str(&format!("    {title} ({}):\n", list.len()));
                for e in list {
                    let gids: Vec<String> = e.endpoint_gids.iter().map(Gid::to_string).collect();
                    out.push_str(&format!(
                        "      {}  gids {}\n",
                        endpoint_node(&e.node_namespace, &e.node_name),
                        gids.join(", "),
                    ));
                }
            }
        }
        out
    }
}

pub(super) fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

pub(super) fn join_types<S: AsRef<str>>(types: impl IntoIterator<Item = S>) -> String {
    let types: Vec<String> = types.into_iter().map(|t| t.as_ref().to_owned()).collect();
    types.join(", ")
}

/// The full name of an endpoint's node; the placeholders (`_CREATED_BY_BARE_DDS_APP_`,
/// `_NODE_NAME_UNKNOWN_`) alone.
pub(super) fn endpoint_node(namespace: &str, name: &str) -> String {
    if name == horus_ros_graph::CREATED_BY_BARE_DDS_APP
        || name == horus_ros_graph::NODE_NAME_UNKNOWN
    {
        name.to_owned()
    } else {
        names::node_full_name(namespace, name)
    }
}

/// `RELIABLE, VOLATILE, KEEP_LAST (10)`: the policies that decide matching, in one line.
pub(super) fn qos_summary(qos: &Qos) -> String {
    format!(
        "{}, {}, {}",
        qos.reliability,
        qos.durability,
        qos.history_depth_string()
    )
}
