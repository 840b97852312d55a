//! Shared helpers of the query verbs (`service list|type|find|info`, `node list|info`,
//! `topic list|info`): ros2cli's name rules and text forms, and the `--json` documents.
//!
//! # `--json` schema (stable)
//!
//! Every query verb prints one JSON document (pretty-printed, then a newline) on stdout instead
//! of ros2cli's text. Failures are the same as without `--json`: a message on stderr, exit 1.
//! Names are ROS names as ros2cli prints them; lists of names are sorted as ros2cli sorts them.
//!
//! - A *names-and-types* entry: `{"name": "/add_two_ints", "types": ["example_interfaces/srv/AddTwoInts"]}`
//!   (`types` sorted, usually one).
//! - Any verb with `-c`: `{"count": N}`.
//! - `service list`: `[entry…]` (services, hidden ones with `--include-hidden-services`).
//! - `service type <svc>`: `entry`.
//! - `service find <type>`: `[entry…]`, the services having that type.
//! - `service info <svc>` (with or without `-v`):
//!   `{"name", "types", "clients_count", "services_count", "clients": [service endpoint…],
//!   "servers": [service endpoint…]}`; the counts are ros2cli's (DDS readers / writers of the
//!   service's reply topic), the lists rmw's `get_clients_info_by_service` /
//!   `get_servers_info_by_service` (Rolling), in reader-GID order.
//! - `node list`: `[{"full_name": "/ns/talker", "name": "talker", "namespace": "/ns",
//!   "enclave": "/" | null}…]`, sorted by full name, nodes sharing a name all listed.
//! - `node info <node>`: `{"full_name", "name", "namespace", "subscribers", "publishers",
//!   "service_servers", "service_clients", "action_servers", "action_clients"}`, each list
//!   `[entry…]` filtered as ros2cli filters them (hidden names only with `--include-hidden`).
//! - `topic list` (with or without `-t`/`-v`): `[{"name", "types", "publisher_count",
//!   "subscription_count"}…]`.
//! - `topic info <topic>` (with or without `-v`): `{"name", "types", "publisher_count",
//!   "subscription_count", "publishers": [topic endpoint…], "subscriptions": [topic endpoint…]}`.
//!
//! A *topic endpoint*: `{"node_name", "node_namespace", "type", "type_hash", "endpoint_type",
//! "gid", "qos"}` — `type_hash` is `"RIHS01_<64 hex>"` or `null` when unknown (ros2cli's
//! `INVALID`), `endpoint_type` `"PUBLISHER"` / `"SUBSCRIPTION"`, `gid` dotted hex as ros2cli
//! prints it (`01.0f.….0e.04`), `qos` one QoS object.
//!
//! A *service endpoint*: `{"node_name", "node_namespace", "type", "type_hash", "endpoint_type",
//! "gids": […], "qos": […]}` — `endpoint_type` `"SERVER"` / `"CLIENT"`; `gids` and `qos` list its
//! DDS endpoints in rmw's order, reader then writer: a server's request reader then response
//! writer, a client's response reader then request writer.
//!
//! A *QoS object*: `{"reliability", "history", "depth", "durability", "lifespan_ns",
//! "deadline_ns", "liveliness", "liveliness_lease_duration_ns"}` — policies by rmw's names
//! (`"RELIABLE"`, `"KEEP_LAST"`, `"VOLATILE"`, `"AUTOMATIC"`, `"UNKNOWN"`, …), `depth` a number,
//! durations in nanoseconds, `null` meaning infinite.

use horus_ros_graph::{NamesAndTypes, ServiceEndpointInfo, TopicEndpointInfo};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::{Qos, QosDuration};
use serde::Serialize;
use serde_json::Value;

use crate::CliError;

/// rclpy `HIDDEN_NODE_PREFIX`.
const HIDDEN_NODE_PREFIX: char = '_';

/// Whether a node name (the name alone, not its namespace) makes the node hidden, as ros2node's
/// `get_node_names` filters: empty or starting with `_`.
pub fn is_hidden_node(name: &str) -> bool {
    name.is_empty() || name.starts_with(HIDDEN_NODE_PREFIX)
}

/// ros2node's `full_name`: namespace, a `/` unless it already ends with one, then the name.
pub fn node_full_name(namespace: &str, name: &str) -> String {
    if namespace.ends_with('/') {
        format!("{namespace}{name}")
    } else {
        format!("{namespace}/{name}")
    }
}

/// ros2node's `parse_node_name`: (name, namespace) of a full node name (a `/` is prepended when
/// missing; the namespace is `/` at the root).
pub fn parse_node_name(full: &str) -> (String, String) {
    let full = if full.starts_with('/') {
        full.to_owned()
    } else {
        format!("/{full}")
    };
    let (namespace, name) = full.rsplit_once('/').unwrap_or(("", full.as_str()));
    let namespace = if namespace.is_empty() { "/" } else { namespace };
    (name.to_owned(), namespace.to_owned())
}

/// What ros2cli's `'Type: %s' % type_str` shows: the type alone when there is exactly one,
/// else Python's repr of the list (`['a/srv/A', 'b/srv/B']`, `[]`).
pub fn type_str<S: AsRef<str>>(types: &[S]) -> String {
    match types {
        [one] => one.as_ref().to_owned(),
        many => {
            let items: Vec<String> = many
                .iter()
                .map(|t| crate::dynamic::repr::py_str(t.as_ref()))
                .collect();
            format!("[{}]", items.join(", "))
        }
    }
}

/// Finds `name` among names and types (exact match, as ros2cli compares).
pub fn find_types(names_and_types: &NamesAndTypes, name: &str) -> Option<Vec<String>> {
    names_and_types
        .get(name)
        .map(|types| types.iter().cloned().collect())
}

/// Prints a JSON document on stdout.
pub fn print_json(value: &Value) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| CliError::new(format!("could not write JSON: {e}")))?;
    println!("{text}");
    Ok(())
}

/// A value as JSON (the documents below cannot fail to serialize: strings, numbers, lists).
fn to_json(value: impl Serialize) -> Value {
    serde_json::to_value(value).unwrap_or(Value::Null)
}

// The documents, as serde writes them: fields in the order the keys print (sorted, as
// `serde_json` sorts an object's keys), so the text is the same whichever way a document is
// built.

/// `{"count": N}`.
#[derive(Serialize)]
struct Count {
    count: usize,
}

/// A names-and-types entry.
#[derive(Serialize)]
struct Entry<'a> {
    name: &'a str,
    types: Vec<&'a str>,
}

/// A QoS object.
#[derive(Serialize)]
struct QosJson {
    deadline_ns: Option<i64>,
    depth: usize,
    durability: String,
    history: String,
    lifespan_ns: Option<i64>,
    liveliness: String,
    liveliness_lease_duration_ns: Option<i64>,
    reliability: String,
}

/// A topic endpoint.
#[derive(Serialize)]
struct TopicEndpoint<'a> {
    endpoint_type: String,
    gid: String,
    node_name: &'a str,
    node_namespace: &'a str,
    qos: QosJson,
    #[serde(rename = "type")]
    topic_type: &'a str,
    type_hash: Option<String>,
}

/// A service endpoint.
#[derive(Serialize)]
struct ServiceEndpoint<'a> {
    endpoint_type: String,
    gids: Vec<String>,
    node_name: &'a str,
    node_namespace: &'a str,
    qos: Vec<QosJson>,
    #[serde(rename = "type")]
    service_type: &'a str,
    type_hash: Option<String>,
}

/// `{"count": N}`.
pub fn count_json(count: usize) -> Value {
    to_json(Count { count })
}

/// A names-and-types entry.
pub fn entry_json<S: AsRef<str>>(name: &str, types: &[S]) -> Value {
    to_json(Entry {
        name,
        types: types.iter().map(AsRef::as_ref).collect(),
    })
}

/// A names-and-types map as a list of entries.
pub fn names_and_types_json(names_and_types: &NamesAndTypes) -> Value {
    to_json(
        names_and_types
            .iter()
            .map(|(name, types)| Entry {
                name,
                types: types.iter().map(String::as_str).collect(),
            })
            .collect::<Vec<_>>(),
    )
}

/// Nanoseconds, or nothing for an infinite duration.
fn nanos(d: QosDuration) -> Option<i64> {
    (!d.is_infinite()).then(|| d.total_nanos())
}

fn qos_document(qos: &Qos) -> QosJson {
    QosJson {
        deadline_ns: nanos(qos.deadline),
        depth: qos.depth,
        durability: qos.durability.to_string(),
        history: qos.history.to_string(),
        lifespan_ns: nanos(qos.lifespan),
        liveliness: qos.liveliness.to_string(),
        liveliness_lease_duration_ns: nanos(qos.liveliness_lease_duration),
        reliability: qos.reliability.to_string(),
    }
}

/// A QoS object, as the endpoint documents show it.
pub fn qos_json(qos: &Qos) -> Value {
    to_json(qos_document(qos))
}

fn type_hash_text(hash: &TypeHash) -> Option<String> {
    hash.is_set().then(|| hash.to_string())
}

/// A topic endpoint.
pub fn topic_endpoint_json(info: &TopicEndpointInfo) -> Value {
    to_json(TopicEndpoint {
        endpoint_type: info.endpoint_type.to_string(),
        gid: info.endpoint_gid.to_string(),
        node_name: &info.node_name,
        node_namespace: &info.node_namespace,
        qos: qos_document(&info.qos_profile),
        topic_type: &info.topic_type,
        type_hash: type_hash_text(&info.topic_type_hash),
    })
}

/// A service endpoint.
pub fn service_endpoint_json(info: &ServiceEndpointInfo) -> Value {
    to_json(ServiceEndpoint {
        endpoint_type: info.endpoint_type.to_string(),
        gids: info.endpoint_gids.iter().map(ToString::to_string).collect(),
        node_name: &info.node_name,
        node_namespace: &info.node_namespace,
        qos: info.qos_profiles.iter().map(qos_document).collect(),
        service_type: &info.service_type,
        type_hash: type_hash_text(&info.service_type_hash),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_names() {
        assert_eq!(node_full_name("/", "talker"), "/talker");
        assert_eq!(node_full_name("/ns", "talker"), "/ns/talker");
        assert_eq!(
            parse_node_name("/ns/a/talker"),
            ("talker".to_owned(), "/ns/a".to_owned())
        );
        assert_eq!(
            parse_node_name("talker"),
            ("talker".to_owned(), "/".to_owned())
        );
        assert!(is_hidden_node("_ros2cli_1") && is_hidden_node(""));
        assert!(!is_hidden_node("talker"));
    }

    #[test]
    fn type_strings_as_python_prints_them() {
        assert_eq!(type_str(&["a/srv/A"]), "a/srv/A");
        assert_eq!(type_str(&["a/srv/A", "b/srv/B"]), "['a/srv/A', 'b/srv/B']");
        assert_eq!(type_str::<&str>(&[]), "[]");
        assert_eq!(type_str(&["it's", "x"]), "[\"it's\", 'x']");
    }
}
