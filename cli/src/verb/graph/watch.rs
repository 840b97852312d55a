//! `graph --watch`: the graph's changes as timestamped `+`/`-` lines (or JSON objects), one per
//! node or endpoint appearing or vanishing.
//!
//! Everything shown comes from the graph's ROS-level events ([`GraphEvent`]) and, for the
//! initial snapshot, the same endpoints as the graph lists them ([`GraphCache::all_endpoints`]):
//! an endpoint's role, ROS name and ROS type are the graph's, never rebuilt here from DDS names.
//! Endpoints that are not ROS (no role) are not shown, and the lines do not name an endpoint's
//! node, so [`GraphEvent::EndpointNodeChanged`] prints nothing.

use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::time::SystemTime;

use horus_ros_graph::{
    EndpointRole as Role, Gid, GraphCache, GraphEndpoint, GraphEvent, RecvError, RosEndpoint,
};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::names::is_hidden_name;
use horus_ros_rmw::qos::EndpointKind;
use serde_json::{json, Value};

use super::GraphArgs;
use crate::session::Session;
use crate::verb::names;
use crate::{CliError, Global};

/// How the lines name an endpoint's role (the role itself comes with the graph's events).
pub(super) trait RoleText {
    /// The endpoint as ROS users name it, in text lines.
    fn text(self) -> &'static str;
    /// `kind` in JSON lines.
    fn json_kind(self) -> &'static str;
    /// Which of a server's or client's two DDS endpoints this is.
    fn part(self) -> Option<&'static str>;
}

impl RoleText for Role {
    fn text(self) -> &'static str {
        if self.is_server() {
            "service server"
        } else if self.is_client() {
            "service client"
        } else if self.kind() == EndpointKind::Writer {
            "publisher"
        } else {
            "subscription"
        }
    }

    fn json_kind(self) -> &'static str {
        match self.text() {
            "service server" => "service_server",
            "service client" => "service_client",
            other => other,
        }
    }

    fn part(self) -> Option<&'static str> {
        match self {
            Role::ServerRequestReader => Some("request reader"),
            Role::ServerResponseWriter => Some("response writer"),
            Role::ClientRequestWriter => Some("request writer"),
            Role::ClientResponseReader => Some("response reader"),
            _ => None,
        }
    }
}

/// One endpoint as the watcher last printed it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct EndpointView {
    gid: Gid,
    role: Role,
    /// The ROS topic or service name.
    name: String,
    /// The message type (`pkg/msg/Name`) or service type (`pkg/srv/Name`).
    ty: String,
    type_hash: TypeHash,
    dds_topic: String,
}

impl EndpointView {
    /// What the lines show of a ROS endpoint (`None`: not a ROS endpoint, not shown).
    fn of(endpoint: GraphEndpoint) -> Option<Self> {
        let RosEndpoint { role, name } = endpoint.ros?;
        Some(Self {
            gid: endpoint.gid,
            role,
            name,
            // The type comes with the event: by the time it is applied, the cache may have lost
            // the endpoint again.
            ty: endpoint.type_name,
            type_hash: endpoint.type_hash,
            dds_topic: endpoint.dds_topic,
        })
    }
}

/// One line of `--watch`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Change {
    Node {
        added: bool,
        name: String,
        namespace: String,
    },
    Endpoint {
        added: bool,
        view: EndpointView,
    },
}

impl Change {
    pub(super) fn text(&self, time: &str) -> String {
        match self {
            Self::Node {
                added,
                name,
                namespace,
            } => format!(
                "{time} {} node {}",
                sign(*added),
                names::node_full_name(namespace, name)
            ),
            Self::Endpoint { added, view } => {
                let mut line =
                    format!("{time} {} {} {}", sign(*added), view.role.text(), view.name);
                line.push_str(&format!(" [{}]", view.ty));
                if let Some(part) = view.role.part() {
                    line.push_str(&format!(" {part}"));
                }
                line.push_str(&format!(" gid {}", view.gid));
                line
            }
        }
    }

    pub(super) fn json(&self, time: &str) -> Value {
        let change = |added: bool| if added { "added" } else { "removed" };
        match self {
            Self::Node {
                added,
                name,
                namespace,
            } => json!({
                "time": time,
                "change": change(*added),
                "kind": "node",
                "full_name": names::node_full_name(namespace, name),
                "name": name,
                "namespace": namespace,
            }),
            Self::Endpoint { added, view } => {
                let mut v = json!({
                    "time": time,
                    "change": change(*added),
                    "kind": view.role.json_kind(),
                    "type": view.ty,
                    "type_hash": view.type_hash.is_set().then(|| view.type_hash.to_string()),
                    "gid": view.gid.to_string(),
                    "dds_topic": view.dds_topic,
                    "dds_endpoint": match view.role.kind() {
                        EndpointKind::Reader => "reader",
                        EndpointKind::Writer => "writer",
                    },
                });
                if let Some(map) = v.as_object_mut() {
                    let key = if view.role.is_service() {
                        "service"
                    } else {
                        "topic"
                    };
                    map.insert(key.to_owned(), json!(view.name));
                    if let Some(part) = view.role.part() {
                        map.insert("part".to_owned(), json!(part.replace(' ', "_")));
                    }
                }
                v
            }
        }
    }
}

pub(super) fn sign(added: bool) -> char {
    if added {
        '+'
    } else {
        '-'
    }
}

/// The watcher's view of the graph: what it has printed as present. Graph events are checked
/// against it and against the cache, so a change is printed once even when the initial snapshot
/// and the first events overlap.
#[derive(Debug, Default)]
pub(super) struct Watcher {
    all: bool,
    /// Visible nodes by (namespace, name), with how many of that name are present.
    nodes: BTreeMap<(String, String), usize>,
    /// Visible endpoints by GID.
    endpoints: HashMap<Gid, EndpointView>,
}

pub(super) fn node_count(cache: &GraphCache, namespace: &str, name: &str) -> usize {
    cache
        .node_names()
        .iter()
        .filter(|n| n.namespace == namespace && n.name == name)
        .count()
}

impl Watcher {
    pub(super) fn new(all: bool) -> Self {
        Self {
            all,
            ..Self::default()
        }
    }

    pub(super) fn visible_node(&self, name: &str) -> bool {
        self.all || !names::is_hidden_node(name)
    }

    pub(super) fn visible_name(&self, name: &str) -> bool {
        self.all || !is_hidden_name(name)
    }

    /// The current graph as `+` changes (nodes, then topic endpoints by topic, then service
    /// endpoints by service), and the view set to it.
    pub(super) fn snapshot(&mut self, cache: &GraphCache) -> Vec<Change> {
        let mut out = Vec::new();
        for n in cache.node_names() {
            if !self.visible_node(&n.name) {
                continue;
            }
            *self
                .nodes
                .entry((n.namespace.clone(), n.name.clone()))
                .or_default() += 1;
            out.push(Change::Node {
                added: true,
                name: n.name,
                namespace: n.namespace,
            });
        }
        // Topics then services, each by name; a topic's publishers then subscriptions, a
        // service's server (request reader, response writer) then client (request writer,
        // response reader) endpoints: the order of `EndpointRole`; then GID order.
        let mut views: Vec<EndpointView> = cache
            .all_endpoints()
            .into_iter()
            .filter_map(EndpointView::of)
            .filter(|view| self.visible_name(&view.name))
            .collect();
        views.sort_by(|a, b| {
            (a.role.is_service(), &a.name, a.role, a.gid).cmp(&(
                b.role.is_service(),
                &b.name,
                b.role,
                b.gid,
            ))
        });
        for view in views {
            self.endpoints.insert(view.gid, view.clone());
            out.push(Change::Endpoint { added: true, view });
        }
        out
    }

    /// The changes one graph event makes to the view (none if the view already shows it).
    pub(super) fn apply(&mut self, cache: &GraphCache, event: GraphEvent) -> Vec<Change> {
        match event {
            GraphEvent::NodeAdded { name, .. } | GraphEvent::NodeRemoved { name, .. }
                if !self.visible_node(&name) =>
            {
                Vec::new()
            }
            GraphEvent::NodeAdded { name, namespace } => {
                let present = node_count(cache, &namespace, &name);
                let shown = self
                    .nodes
                    .entry((namespace.clone(), name.clone()))
                    .or_default();
                if present > *shown {
                    *shown += 1;
                    vec![Change::Node {
                        added: true,
                        name,
                        namespace,
                    }]
                } else {
                    Vec::new()
                }
            }
            GraphEvent::NodeRemoved { name, namespace } => {
                let present = node_count(cache, &namespace, &name);
                let key = (namespace, name);
                let shown = self.nodes.get(&key).copied().unwrap_or(0);
                if shown > present {
                    if shown == 1 {
                        self.nodes.remove(&key);
                    } else {
                        self.nodes.insert(key.clone(), shown - 1);
                    }
                    vec![Change::Node {
                        added: false,
                        name: key.1,
                        namespace: key.0,
                    }]
                } else {
                    Vec::new()
                }
            }
            GraphEvent::EndpointAdded(endpoint) => {
                let Some(view) = EndpointView::of(endpoint) else {
                    return Vec::new();
                };
                if !self.visible_name(&view.name) {
                    return Vec::new();
                }
                let mut out = Vec::new();
                if let Some(old) = self.endpoints.get(&view.gid) {
                    if old.role == view.role && old.dds_topic == view.dds_topic {
                        return out;
                    }
                    if let Some(old) = self.endpoints.remove(&view.gid) {
                        out.push(Change::Endpoint {
                            added: false,
                            view: old,
                        });
                    }
                }
                self.endpoints.insert(view.gid, view.clone());
                out.push(Change::Endpoint { added: true, view });
                out
            }
            GraphEvent::EndpointRemoved(endpoint) => match self.endpoints.remove(&endpoint.gid) {
                Some(view) => vec![Change::Endpoint { added: false, view }],
                None => Vec::new(),
            },
            // The lines do not name an endpoint's node.
            GraphEvent::EndpointNodeChanged { .. } => Vec::new(),
        }
    }
}

/// RFC 3339 UTC with milliseconds: `2026-11-22T01:23:45.678Z`.
pub(super) fn rfc3339_millis(t: SystemTime) -> String {
    chrono::DateTime::<chrono::Utc>::from(t).to_rfc3339_opts(chrono::SecondsFormat::Millis, true)
}

/// Writes changes, one line each; `false` once stdout is gone (e.g. a closed pipe).
pub(super) fn emit(out: &mut impl Write, changes: &[Change], json: bool) -> bool {
    if changes.is_empty() {
        return true;
    }
    let time = rfc3339_millis(SystemTime::now());
    for change in changes {
        let line = if json {
            change.json(&time).to_string()
        } else {
            change.text(&time)
        };
        if writeln!(out, "{line}").is_err() {
            return false;
        }
    }
    out.flush().is_ok()
}

/// `graph --watch`: the snapshot, then every change, until SIGINT / SIGTERM / SIGHUP.
pub(super) fn watch(global: &Global, args: &GraphArgs) -> Result<(), CliError> {
    let session = Session::open(global)?;
    let mut watcher = Watcher::new(args.all);
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    // Subscribed before the snapshot, so nothing falls between them; what both hold is
    // printed once (see `Watcher`).
    let events = session.graph.subscribe();
    // A signal closes the subscription: the loop below ends once it is drained.
    let interrupter = events.interrupter();
    ctrlc::set_handler(move || interrupter.interrupt())
        .map_err(|e| CliError::new(format!("could not handle Ctrl+C: {e}")))?;
    let changes = session.graph.read(|c| watcher.snapshot(c));
    if !emit(&mut out, &changes, global.json) {
        return Ok(());
    }
    loop {
        let first = match events.recv(None) {
            Ok(event) => event,
            Err(RecvError::Lagged(missed)) => {
                tracing::warn!("graph --watch fell behind: {missed} graph changes were not shown");
                continue;
            }
            Err(_) => break,
        };
        let changes = session.graph.read(|c| {
            let mut changes = watcher.apply(c, first);
            while let Ok(event) = events.try_recv() {
                changes.extend(watcher.apply(c, event));
            }
            changes
        });
        if !emit(&mut out, &changes, global.json) {
            break;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, UNIX_EPOCH};

    #[test]
    fn timestamps_are_rfc3339_utc_millis() {
        assert_eq!(rfc3339_millis(UNIX_EPOCH), "1970-01-01T00:00:00.000Z");
        let t = UNIX_EPOCH + Duration::from_millis(1_795_310_625_678);
        assert_eq!(rfc3339_millis(t), "2026-11-22T01:23:45.678Z");
        // A leap day.
        let t = UNIX_EPOCH + Duration::from_secs(951_782_400);
        assert_eq!(rfc3339_millis(t), "2000-02-29T00:00:00.000Z");
        let t = UNIX_EPOCH + Duration::from_secs(4_102_444_799);
        assert_eq!(rfc3339_millis(t), "2099-12-31T23:59:59.000Z");
    }

    /// A GID of participant `p`'s endpoint `n`.
    fn gid(p: u8, n: u8) -> Gid {
        let mut data = [p; 16];
        data[12..].copy_from_slice(&[0, 0, 0, n]);
        Gid::from_bytes(data)
    }

    fn entry(n: u8, topic: &str, ty: &str, kind: EndpointKind) -> horus_ros_graph::EndpointEntry {
        horus_ros_graph::EndpointEntry {
            gid: gid(1, n),
            participant_gid: gid(1, 0xc1),
            dds_topic_name: topic.to_owned(),
            dds_type_name: ty.to_owned(),
            qos: horus_ros_rmw::qos::Qos::default(),
            type_hash: TypeHash::ZERO,
            kind,
        }
    }

    fn nodes(
        names: &[&str],
        writers: &[u8],
    ) -> horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo {
        use horus_ros_msgs::rmw_dds_common::{NodeEntitiesInfo, ParticipantEntitiesInfo};
        ParticipantEntitiesInfo {
            gid: gid(1, 0xc1),
            node_entities_info_seq: names
                .iter()
                .map(|name| NodeEntitiesInfo {
                    node_namespace: "/".to_owned(),
                    node_name: (*name).to_owned(),
                    reader_gid_seq: Vec::new(),
                    writer_gid_seq: writers.iter().map(|n| gid(1, *n)).collect(),
                })
                .collect(),
        }
    }

    /// The lines of `changes` after their timestamp.
    fn lines(changes: &[Change]) -> Vec<String> {
        changes
            .iter()
            .map(|c| c.text("t").trim_start_matches("t ").to_owned())
            .collect()
    }

    #[test]
    fn the_snapshot_and_the_events_show_ros_endpoints_by_topic_then_service() {
        use EndpointKind::{Reader, Writer};
        const STRING: &str = "std_msgs::msg::dds_::String_";
        const REQ: &str = "example_interfaces::srv::dds_::AddTwoInts_Request_";
        const REP: &str = "example_interfaces::srv::dds_::AddTwoInts_Response_";
        let mut cache = GraphCache::new();
        cache.update_participant_entities(nodes(&["talker"], &[5, 9]));
        for e in [
            entry(1, "rq/add_two_intsRequest", REQ, Writer),
            entry(2, "rq/add_two_intsRequest", REQ, Reader),
            entry(3, "rt/chatter", STRING, Reader),
            entry(4, "rr/add_two_intsReply", REP, Writer),
            entry(5, "rt/chatter", STRING, Writer),
            entry(6, "rr/add_two_intsReply", REP, Reader),
            entry(7, "rt/_hidden", STRING, Writer),
            entry(8, "ros_discovery_info", "x::dds_::Info_", Writer),
            entry(9, "rt/alpha", STRING, Writer),
        ] {
            cache.add_entity(e);
        }
        let mut watcher = Watcher::new(false);
        let g = |n| gid(1, n);
        let srv = "/add_two_ints [example_interfaces/srv/AddTwoInts]";
        assert_eq!(
            lines(&watcher.snapshot(&cache)),
            [
                "+ node /talker".to_owned(),
                format!("+ publisher /alpha [std_msgs/msg/String] gid {}", g(9)),
                format!("+ publisher /chatter [std_msgs/msg/String] gid {}", g(5)),
                format!("+ subscription /chatter [std_msgs/msg/String] gid {}", g(3)),
                format!("+ service server {srv} request reader gid {}", g(2)),
                format!("+ service server {srv} response writer gid {}", g(4)),
                format!("+ service client {srv} request writer gid {}", g(1)),
                format!("+ service client {srv} response reader gid {}", g(6)),
            ]
        );

        // An endpoint moving to another node prints nothing but the nodes; the participant's
        // loss its endpoints, then its node.
        cache.record_events(true);
        cache.update_participant_entities(nodes(&["renamed"], &[5, 9]));
        let mut changes = Vec::new();
        for event in cache.drain_events() {
            changes.extend(watcher.apply(&cache, event));
        }
        assert_eq!(lines(&changes), ["+ node /renamed", "- node /talker"]);
        cache.remove_participant(gid(1, 0xc1));
        let mut changes = Vec::new();
        for event in cache.drain_events() {
            changes.extend(watcher.apply(&cache, event));
        }
        let changes = lines(&changes);
        assert_eq!(changes.len(), 8, "{changes:?}");
        assert_eq!(
            changes[0],
            format!("- service client {srv} request writer gid {}", g(1))
        );
        assert_eq!(changes[7], "- node /renamed");
    }

    #[test]
    fn change_lines() {
        let view = EndpointView {
            gid: Gid::from_bytes([1; 16]),
            role: Role::ServerRequestReader,
            name: "/add_two_ints".to_owned(),
            ty: "example_interfaces/srv/AddTwoInts".to_owned(),
            type_hash: TypeHash::ZERO,
            dds_topic: "rq/add_two_intsRequest".to_owned(),
        };
        let t = "2026-11-22T01:23:45.678Z";
        let change = Change::Endpoint { added: false, view };
        assert_eq!(
            change.text(t),
            format!(
                "{t} - service server /add_two_ints [example_interfaces/srv/AddTwoInts] \
                 request reader gid {}",
                Gid::from_bytes([1; 16])
            )
        );
        let j = change.json(t);
        assert_eq!(j["kind"], "service_server");
        assert_eq!(j["change"], "removed");
        assert_eq!(j["service"], "/add_two_ints");
        assert_eq!(j["part"], "request_reader");
        assert_eq!(j["dds_endpoint"], "reader");
        assert_eq!(j["type_hash"], Value::Null);
        let node = Change::Node {
            added: true,
            name: "talker".to_owned(),
            namespace: "/ns".to_owned(),
        };
        assert_eq!(node.text(t), format!("{t} + node /ns/talker"));
        assert_eq!(node.json(t)["full_name"], "/ns/talker");
    }
}
