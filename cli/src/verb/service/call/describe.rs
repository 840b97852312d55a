//! Where a service type's description comes from: the types compiled into horus-ros-msgs, or the
//! serving node's `~/get_type_description` service.
//!
//! rcl (jazzy 9.2) `rcl_node_type_description_service_handle_request` looks a type up by its
//! hash alone (the `type_name` of the request is ignored), in the node's type cache, which holds
//! the hashes of the types its publishers, subscriptions, services and clients use — for a
//! service, the *service* type hash. Jazzy does not put that hash on the wire (service endpoints
//! announce their `_Request` / `_Response` hashes), so we ask, in order, for the hashes a peer
//! does show: the service hash if the graph has it, the `<service>/_service_event` publisher's
//! `_Event` type (present when the server enabled service introspection; its description holds
//! the request and response), and the request / response hashes themselves (known to nodes that
//! also publish or subscribe those types).
//!
//! A message type ([`fetch_message`], `interface show --from-graph`) is asked of the nodes whose
//! publishers or subscriptions announce it with its hash.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use horus_ros_graph::Graph;
use horus_ros_msgs::description::{EVENT_SUFFIX, REQUEST_SUFFIX, RESPONSE_SUFFIX};
use horus_ros_msgs::type_description_interfaces::srv::{
    GetTypeDescription, GetTypeDescriptionRequest, GetTypeDescriptionResponse,
};
use horus_ros_msgs::{Service, TypeDescription, TypeHash};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::Node;

use crate::dynamic::ServiceType;
use horus_ros_services::{EndpointBuilder, ServiceClient};

/// One type hash to ask a node about.
struct Candidate {
    type_name: String,
    hash: TypeHash,
}

/// Fetches the description of `service_type` from the node serving `service`.
pub fn fetch(
    node: &Node,
    graph: &Arc<Graph>,
    service: &str,
    service_type: &str,
    timeout: Duration,
) -> Result<ServiceType, String> {
    let servers: Vec<_> = graph
        .read(|c| c.servers_info_by_service(service, false))
        .unwrap_or_default()
        .into_iter()
        .filter(|s| s.service_type == service_type)
        .collect();
    let server = servers
        .first()
        .ok_or_else(|| format!("no server of '{service}' to describe '{service_type}'"))?;
    let node_name = if server.node_namespace.ends_with('/') {
        format!("{}{}", server.node_namespace, server.node_name)
    } else {
        format!("{}/{}", server.node_namespace, server.node_name)
    };
    let unknown = || {
        format!(
            "type '{service_type}' is not compiled in and its server {node_name} does not \
             describe it"
        )
    };
    let mut candidates = Vec::new();
    if server.service_type_hash.is_set() {
        candidates.push(Candidate {
            type_name: service_type.to_owned(),
            hash: server.service_type_hash,
        });
    }
    let event_type = format!("{service_type}{EVENT_SUFFIX}");
    for p in graph.read(|c| c.publishers_info_by_topic(&format!("{service}/_service_event"), false))
    {
        if p.topic_type == event_type
            && p.node_name == server.node_name
            && p.node_namespace == server.node_namespace
            && p.topic_type_hash.is_set()
        {
            candidates.push(Candidate {
                type_name: event_type.clone(),
                hash: p.topic_type_hash,
            });
        }
    }
    for (suffix, hash) in [REQUEST_SUFFIX, RESPONSE_SUFFIX]
        .iter()
        .zip(&server.endpoint_type_hashes)
    {
        if hash.is_set() {
            candidates.push(Candidate {
                type_name: format!("{service_type}{suffix}"),
                hash: *hash,
            });
        }
    }
    let mut got: Vec<TypeDescription> = Vec::new();
    ask(node, graph, &node_name, candidates, timeout, |d| {
        got.push(d);
        ServiceType::from_descriptions(service_type, &got).ok()
    })
    .map_err(|reasons| format!("{} ({})", unknown(), reasons.join("; ")))
}

/// Fetches the description of message type `type_name` from a node that publishes or
/// subscribes to it (its endpoints announce the type's hash): each such node in turn.
pub fn fetch_message(
    node: &Node,
    graph: &Arc<Graph>,
    type_name: &str,
    timeout: Duration,
) -> Result<TypeDescription, String> {
    let mut by_node: BTreeMap<String, Vec<Candidate>> = BTreeMap::new();
    graph.read(|c| {
        for (topic, types) in c.topic_names_and_types(true) {
            if !types.iter().any(|t| t == type_name) {
                continue;
            }
            let endpoints = c
                .publishers_info_by_topic(&topic, false)
                .into_iter()
                .chain(c.subscriptions_info_by_topic(&topic, false));
            for e in endpoints {
                if e.topic_type != type_name || !e.topic_type_hash.is_set() {
                    continue;
                }
                let name = crate::verb::names::node_full_name(&e.node_namespace, &e.node_name);
                let candidates = by_node.entry(name).or_default();
                if !candidates.iter().any(|c| c.hash == e.topic_type_hash) {
                    candidates.push(Candidate {
                        type_name: type_name.to_owned(),
                        hash: e.topic_type_hash,
                    });
                }
            }
        }
    });
    if by_node.is_empty() {
        return Err(format!(
            "no node in the graph publishes or subscribes to '{type_name}' with its type hash"
        ));
    }
    let mut reasons = Vec::new();
    for (node_name, candidates) in by_node {
        match ask(node, graph, &node_name, candidates, timeout, Some) {
            Ok(d) => return Ok(d),
            Err(r) => reasons.extend(r.into_iter().map(|r| format!("{node_name}: {r}"))),
        }
    }
    Err(format!(
        "no node in the graph describes '{type_name}' ({})",
        reasons.join("; ")
    ))
}

/// Asks node `node_name`'s `~/get_type_description` about each candidate in turn, until
/// `accept` takes the descriptions got so far (each checked against the hash asked for). The
/// reasons it failed otherwise.
fn ask<T>(
    node: &Node,
    graph: &Arc<Graph>,
    node_name: &str,
    candidates: Vec<Candidate>,
    timeout: Duration,
    mut accept: impl FnMut(TypeDescription) -> Option<T>,
) -> Result<T, Vec<String>> {
    let describe_service = format!("{node_name}/get_type_description");
    let has_describer = graph.read(|c| {
        c.servers_info_by_service(&describe_service, false)
            .is_ok_and(|s| {
                s.iter()
                    .any(|s| s.service_type == GetTypeDescription::TYPE_NAME)
            })
    });
    if !has_describer {
        return Err(vec![format!("it serves no {describe_service}")]);
    }
    let describe_name = ServiceName::expand(&describe_service, node.name(), node.namespace())
        .map_err(|e| vec![format!("{describe_service}: {e}")])?;
    let mut client = ServiceClient::<GetTypeDescription>::builder()
        .node(node)
        .name(describe_name.as_str())
        .build()
        .map_err(|e| vec![e.to_string()])?;
    let mut reasons: Vec<String> = Vec::new();
    for c in candidates {
        let reply = call_describe(
            &mut client,
            &GetTypeDescriptionRequest {
                type_name: c.type_name.clone(),
                type_hash: c.hash.to_string(),
                include_type_sources: false,
            },
            timeout,
        );
        match reply {
            Ok(r) if r.successful => {
                let hash = r.type_description.compute_type_hash();
                if hash != c.hash {
                    reasons.push(format!(
                        "the description of {} hashes to {hash}, not {}",
                        c.type_name, c.hash
                    ));
                    continue;
                }
                if let Some(done) = accept(r.type_description) {
                    return Ok(done);
                }
            }
            Ok(r) => reasons.push(format!("{}: {}", c.type_name, r.failure_reason)),
            Err(e) => reasons.push(format!("{describe_service}: {e}")),
        }
    }
    if reasons.is_empty() {
        reasons.push("no type hash of it is on the graph".to_owned());
    }
    reasons.dedup();
    Err(reasons)
}

/// One `GetTypeDescription` call.
fn call_describe(
    client: &mut ServiceClient<GetTypeDescription>,
    request: &GetTypeDescriptionRequest,
    timeout: Duration,
) -> Result<GetTypeDescriptionResponse, String> {
    client.call(request.clone(), timeout).map_err(|e| match e {
        horus_ros_services::ServiceError::NoServer => {
            "its server did not become reachable".to_owned()
        }
        horus_ros_services::ServiceError::Timeout => {
            format!("no response within {} s", timeout.as_secs_f64())
        }
        horus_ros_services::ServiceError::Transport(
            horus_ros_services::TransportError::ServerGone,
        ) => "its server left before answering".to_owned(),
        horus_ros_services::ServiceError::ServiceFailed(m) => m,
        horus_ros_services::ServiceError::Transport(cause) => cause.to_string(),
    })
}
