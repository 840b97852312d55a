//! Our graph next to rclpy's: our [`GraphCache`] in the shape of the peer's `{"graph": …}` lines
//! (rclpy's graph API: node names with enclaves, `get_topic_names_and_types`,
//! `get_service_names_and_types`, and `get_publishers_info_by_topic` /
//! `get_subscriptions_info_by_topic` of every DDS topic, each endpoint as rclpy prints it), and
//! the wait until the two are the same.
//!
//! Two things a Fast DDS node sees of our endpoints differ from what our context knows of them,
//! as the protocol has it, so the view of our own endpoints is the one they announce
//! ([`announced`]): discovery carries no history (rmw_fastrtps reports UNKNOWN, as for its own
//! endpoints) and a DDS QoS rather than the rmw profile (infinite durations for the defaults);
//! and on the rustdds backend our endpoints announce no USER_DATA, so their type hash is unset
//! (`INVALID`) there. Likewise for enclaves, which travel in participant USER_DATA: on rustdds
//! our nodes show none (`""`) to rclpy, and others' are unknown to us, so not compared.
//!
//! History is reported per observer: rmw_fastrtps reports none for remote endpoints (UNKNOWN),
//! rmw_cyclonedds what Cyclone DDS holds (the HISTORY a Cyclone DDS peer announces, else the
//! DDS default it fills in), rmw_zenoh what the tokens carry. So histories are compared where
//! our backend and the peers' RMW observe alike (rustdds beside rmw_fastrtps_cpp, Zenoh beside
//! rmw_zenoh_cpp), and left out of both views elsewhere.
//!
//! On Zenoh (our Zenoh backend beside rmw_zenoh_cpp peers) the graph comes from liveliness
//! tokens, and rclpy's graph API answers from rmw_zenoh's own graph cache (rmw_zenoh_cpp 0.2.10
//! `graph_cache.cpp`), which knows no DDS topics: `get_topic_names_and_types` and
//! `get_*_info_by_topic` ignore `no_demangle`/`no_mangle` and answer by ROS name with demangled
//! types, for publishers and subscriptions only (a service is one entity there, with no
//! endpoint per topic). So the view is then keyed by ROS topic names, our endpoints are as
//! their tokens announce them (the QoS of the token: a depth of 0 is rmw_zenoh's default, 42),
//! and every node's enclave is compared: each token carries its context's
//! (`@ros2_lv/<domain>/<zid>/<node>/<entity>/<kind>/<enclave>/…`).
//!
//! Services are compared node by node on every RMW (`node_services`: rclpy's
//! `get_service_names_and_types_by_node` and `get_client_names_and_types_by_node` of each node,
//! ours from the same queries of our cache), the one view of a server's or client's node that
//! rclpy gives on Zenoh.
//!
//! One difference is ours, not the protocol's: rmw lists its own participant's
//! `ros_discovery_info` writer and reader(s) under that DDS topic (they are discovered like any
//! endpoint), while our graph lists those of other participants only (the context reports its
//! nodes' endpoints, not its own built-ins; nor the late-joiner reader of `rmw/src/late_joiner.rs`,
//! which peers see too). Those entries of rclpy's view are left out of the comparison.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use horus_ros_graph::{
    Graph, GraphCache, RecvError, ServiceEndpointInfo, SubscriptionInterrupter, TopicEndpointInfo,
    TopicEndpointType,
};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::names::{
    ROS_SERVICE_REQUESTER_PREFIX, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX, SERVICE_REQUEST_SUFFIX,
};
use horus_ros_rmw::qos::{EndpointKind, HistoryPolicy, Qos};
use horus_ros_rmw::{Backend, Context, Gid};
use horus_ros_test_support::jazzy::Rmw;
use serde_json::{json, Map, Value};

use super::peer::{Line, RclpyPeer};

/// Who "we" are in a view: our participant, and whether our endpoints announce USER_DATA.
#[derive(Clone, Copy, Debug)]
pub struct Us {
    participant: Gid,
    announces_user_data: bool,
    /// Whether our backend and the peers' RMW report endpoints' history alike.
    histories_compared: bool,
    /// Whether the graph is Zenoh's (tokens; see the module documentation).
    zenoh: bool,
}

impl Us {
    /// The participant of `context`, beside peers on this run's RMW ([`Rmw::of_peers`]).
    pub fn of(context: &Context) -> Self {
        let histories_compared = matches!(
            (context.backend(), Rmw::of_peers()),
            (Some(Backend::RustDds), Rmw::FastRtps) | (Some(Backend::Zenoh), Rmw::Zenoh)
        );
        Self {
            participant: context.gid(),
            announces_user_data: context.capabilities().announces_user_data,
            histories_compared,
            zenoh: context.backend() == Some(Backend::Zenoh),
        }
    }

    /// Whether the graph is Zenoh's, keyed by ROS names (see the module documentation).
    pub fn on_zenoh(&self) -> bool {
        self.zenoh
    }

    /// Whether `gid` is an entity of our participant (same GUID prefix; on DDS only: see
    /// [`owned_in`](Self::owned_in)).
    pub fn owns(&self, gid: Gid) -> bool {
        gid.data[..12] == self.participant.data[..12]
    }

    /// Which GIDs of `cache` are our endpoints': on DDS those of our GUID prefix; on Zenoh,
    /// where an entity's GID is the hash of its token, those our participant reported.
    pub fn owned_in(&self, cache: &GraphCache) -> impl Fn(Gid) -> bool + '_ {
        let ours: Option<BTreeSet<Gid>> = self.zenoh.then(|| {
            cache
                .snapshot()
                .endpoints
                .into_iter()
                .filter(|e| self.owns(e.participant_gid))
                .map(|e| e.gid)
                .collect()
        });
        move |gid| match &ours {
            Some(ours) => ours.contains(&gid),
            None => self.owns(gid),
        }
    }
}

/// rmw_zenoh's depth where a token leaves it empty (rmw_zenoh_cpp 0.2.10 `qos.cpp`
/// `QoS::default_qos`, read back by `liveliness_utils.cpp` `keyexpr_to_qos`).
const ZENOH_DEFAULT_DEPTH: usize = 42;

/// An endpoint of ours as a Fast DDS node sees it: the QoS it announces (the DDS QoS of its
/// profile, read back without history), and no type hash where it announces no USER_DATA. On
/// Zenoh, as its token announces it: its QoS profile, a depth of 0 written as the default.
pub fn announced(us: &Us, mut info: TopicEndpointInfo) -> TopicEndpointInfo {
    if us.zenoh {
        if info.qos_profile.depth == 0 && info.qos_profile.history != HistoryPolicy::KeepAll {
            info.qos_profile.depth = ZENOH_DEFAULT_DEPTH;
        }
        return info;
    }
    let kind = match info.endpoint_type {
        TopicEndpointType::Publisher => EndpointKind::Writer,
        TopicEndpointType::Subscription => EndpointKind::Reader,
    };
    if let Ok(dds) = info.qos_profile.to_dds(kind) {
        info.qos_profile = Qos::from_dds(&dds);
    }
    info.qos_profile.history = HistoryPolicy::Unknown;
    info.qos_profile.depth = 0;
    if !us.announces_user_data {
        info.topic_type_hash = TypeHash::ZERO;
    }
    info
}

/// One endpoint of a server or client (`index` 0: its reader, 1: its writer) as rclpy's
/// `get_*_info_by_topic` prints it for the DDS topic, with `dds_type` (`pkg::srv::dds_::…_`).
pub fn service_endpoint_text(info: &ServiceEndpointInfo, index: usize, dds_type: &str) -> String {
    TopicEndpointInfo {
        node_name: info.node_name.clone(),
        node_namespace: info.node_namespace.clone(),
        topic_type: dds_type.to_owned(),
        topic_type_hash: info.endpoint_type_hashes[index],
        endpoint_type: if index == 0 {
            TopicEndpointType::Subscription
        } else {
            TopicEndpointType::Publisher
        },
        endpoint_gid: info.endpoint_gids[index],
        qos_profile: info.qos_profiles[index],
    }
    .to_string()
}

/// The DDS topics of a service: `(rq/<service>Request, rr/<service>Reply)`.
pub fn service_topics(service: &str) -> (String, String) {
    (
        format!("{ROS_SERVICE_REQUESTER_PREFIX}{service}{SERVICE_REQUEST_SUFFIX}"),
        format!("{ROS_SERVICE_RESPONSE_PREFIX}{service}{SERVICE_REPLY_SUFFIX}"),
    )
}

fn names_and_types(names: BTreeMap<String, BTreeSet<String>>) -> Value {
    Value::Object(
        names
            .into_iter()
            .map(|(name, types)| (name, json!(types)))
            .collect(),
    )
}

/// The topics of a view: those rclpy lists, and those of every name we list (DDS topics, or on
/// Zenoh the ROS names of topics).
fn view_topics(theirs: &Value, cache: &GraphCache, us: &Us) -> BTreeSet<String> {
    let mut topics: BTreeSet<String> = theirs["endpoints"]
        .as_object()
        .map(|o| o.keys().cloned().collect())
        .unwrap_or_default();
    if us.zenoh {
        topics.extend(cache.topic_names_and_types(true).into_keys());
        return topics;
    }
    topics.insert("ros_discovery_info".to_owned());
    for name in cache.topic_names_and_types(true).into_keys() {
        topics.insert(format!("{ROS_TOPIC_PREFIX}{name}"));
    }
    for name in cache.service_names_and_types(true).into_keys() {
        let (request, reply) = service_topics(&name);
        topics.insert(request);
        topics.insert(reply);
    }
    topics
}

/// The fully qualified name of a node, as the peer keys `node_services`.
fn qualified(namespace: &str, name: &str) -> String {
    format!("{}/{name}", namespace.trim_end_matches('/'))
}

/// Every node's services and clients with their types, as rclpy's
/// `get_service_names_and_types_by_node` / `get_client_names_and_types_by_node` give them.
fn node_services(cache: &GraphCache) -> Value {
    let mut out = Map::new();
    for n in cache.node_names() {
        let (Ok(services), Ok(clients)) = (
            cache.service_names_and_types_by_node(&n.name, &n.namespace),
            cache.client_names_and_types_by_node(&n.name, &n.namespace),
        ) else {
            continue;
        };
        out.insert(
            qualified(&n.namespace, &n.name),
            json!({"services": names_and_types(services), "clients": names_and_types(clients)}),
        );
    }
    Value::Object(out)
}

/// Our view of the graph in the shape of the peer's `{"graph": …}` (see the module
/// documentation), over the topics rclpy lists and ours.
pub fn our_view(cache: &GraphCache, us: &Us, theirs: &Value) -> Value {
    let their_enclave = |namespace: &str, name: &str| -> Option<Value> {
        theirs["nodes"]
            .as_array()?
            .iter()
            .find(|n| n[0] == namespace && n[1] == name)
            .map(|n| n[2].clone())
    };
    let nodes: Vec<Value> = cache
        .node_names()
        .into_iter()
        .map(|n| {
            let enclave = match (n.enclave, us.announces_user_data || us.zenoh) {
                // On Zenoh every token names its context's enclave: none is a finding.
                (enclave, true) if us.zenoh => json!(enclave),
                (Some(enclave), true) => json!(enclave),
                (None, true) => json!(""),
                // Without participant USER_DATA only our own nodes have one (the context
                // knows it), and they announce none; others' are unknown: not compared.
                (Some(_), false) => json!(""),
                (None, false) => their_enclave(&n.namespace, &n.name).unwrap_or(Value::Null),
            };
            json!([n.namespace, n.name, enclave])
        })
        .collect();
    let mut endpoints = Map::new();
    // rmw_zenoh answers by ROS name with demangled types; rmw_fastrtps and rmw_cyclonedds
    // by DDS topic with DDS types (`no_mangle`).
    let no_mangle = !us.zenoh;
    let ours = us.owned_in(cache);
    for topic in view_topics(theirs, cache, us) {
        let text = |infos: Vec<TopicEndpointInfo>| -> Vec<String> {
            let mut texts: Vec<String> = infos
                .into_iter()
                .map(|i| {
                    if ours(i.endpoint_gid) {
                        announced(us, i)
                    } else {
                        i
                    }
                    .to_string()
                })
                .collect();
            texts.sort();
            texts
        };
        let publishers = text(cache.publishers_info_by_topic(&topic, no_mangle));
        let subscriptions = text(cache.subscriptions_info_by_topic(&topic, no_mangle));
        if !publishers.is_empty() || !subscriptions.is_empty() {
            endpoints.insert(
                topic,
                json!({"publishers": publishers, "subscriptions": subscriptions}),
            );
        }
    }
    let mut nodes = nodes;
    nodes.sort_by_key(Value::to_string);
    json!({
        "nodes": nodes,
        "topics": names_and_types(cache.topic_names_and_types(true)),
        "services": names_and_types(cache.service_names_and_types(true)),
        "endpoints": endpoints,
        "node_services": node_services(cache),
    })
}

/// The GID in an endpoint's text as rclpy prints it (its `GID: …` line).
pub fn gid_in(text: &str) -> Option<Gid> {
    let hex = text.lines().find_map(|l| l.strip_prefix("GID: "))?;
    let bytes: Vec<u8> = hex
        .split('.')
        .map(|b| u8::from_str_radix(b, 16))
        .collect::<Result<_, _>>()
        .ok()?;
    Some(Gid::from_bytes(bytes.try_into().ok()?))
}

/// rclpy's view less our participant's own `ros_discovery_info` endpoints (see the module
/// documentation).
fn without_our_builtins(theirs: &Value, us: &Us) -> Value {
    let mut theirs = theirs.clone();
    // Only where rclpy lists it (indexing would add it: none on Zenoh).
    let Some(topic) = theirs
        .get_mut("endpoints")
        .and_then(|e| e.get_mut("ros_discovery_info"))
    else {
        return theirs;
    };
    for side in ["publishers", "subscriptions"] {
        if let Some(list) = topic.get_mut(side).and_then(Value::as_array_mut) {
            list.retain(|t| !t.as_str().and_then(gid_in).is_some_and(|g| us.owns(g)));
        }
    }
    theirs
}

/// An endpoint's text as views are compared (see [`wait_for_same_view`]): its `History
/// (Depth)` line left out unless `us` compares histories.
pub fn as_compared(us: &Us, text: &str) -> String {
    if us.histories_compared {
        return text.to_owned();
    }
    text.lines()
        .filter(|l| !l.trim_start().starts_with("History (Depth):"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `view` with every endpoint's `History (Depth)` line left out, unless `us` compares them.
fn histories_as_compared(mut view: Value, us: &Us) -> Value {
    if us.histories_compared {
        return view;
    }
    if let Some(topics) = view["endpoints"].as_object_mut() {
        for topic in topics.values_mut() {
            for side in ["publishers", "subscriptions"] {
                if let Some(list) = topic.get_mut(side).and_then(Value::as_array_mut) {
                    for text in list.iter_mut() {
                        *text = Value::from(as_compared(us, text.as_str().unwrap_or_default()));
                    }
                    list.sort_by_key(Value::to_string);
                }
            }
        }
    }
    view
}

/// What differs between two views, key by key (for failure messages).
pub fn difference(ours: &Value, theirs: &Value) -> String {
    let mut out = String::new();
    for key in ["nodes", "topics", "services", "node_services"] {
        if ours[key] != theirs[key] {
            out += &format!(
                "{key}:\n  ours:   {}\n  rclpy's: {}\n",
                ours[key], theirs[key]
            );
        }
    }
    let empty = Map::new();
    let ours_e = ours["endpoints"].as_object().unwrap_or(&empty);
    let theirs_e = theirs["endpoints"].as_object().unwrap_or(&empty);
    let topics: BTreeSet<&String> = ours_e.keys().chain(theirs_e.keys()).collect();
    for topic in topics {
        for side in ["publishers", "subscriptions"] {
            let list = |e: &Map<String, Value>| -> BTreeSet<String> {
                e.get(topic.as_str())
                    .and_then(|t| t[side].as_array())
                    .map(|a| {
                        a.iter()
                            .map(|v| v.as_str().unwrap_or_default().to_owned())
                            .collect()
                    })
                    .unwrap_or_default()
            };
            let (o, t) = (list(ours_e), list(theirs_e));
            for only in o.difference(&t) {
                out += &format!("{topic} {side}, only ours:\n{only}\n");
            }
            for only in t.difference(&o) {
                out += &format!("{topic} {side}, only rclpy's:\n{only}\n");
            }
        }
    }
    if out.is_empty() && ours != theirs {
        out = format!("ours:\n{ours:#}\nrclpy's:\n{theirs:#}\n");
    }
    out
}

/// Stops the thread that turns graph changes into wake-ups when dropped.
struct WakeOnChanges(SubscriptionInterrupter);

impl Drop for WakeOnChanges {
    fn drop(&mut self) {
        self.0.interrupt();
    }
}

/// Whether `view` lists, on `dds_topic`, a `side` (`publishers`/`subscriptions`) endpoint of the
/// node `name`.
pub fn lists(view: &Value, dds_topic: &str, side: &str, name: &str) -> bool {
    let line = format!("Node name: {name}\n");
    view["endpoints"][dds_topic][side]
        .as_array()
        .is_some_and(|a| {
            a.iter()
                .any(|t| t.as_str().is_some_and(|t| t.starts_with(&line)))
        })
}

/// Waits at most `limit` until our view of `graph` equals the peer's latest `{"graph": …}`
/// line ("graph": true in its spec) and is `complete` (both views may lack the same things for a
/// while: what a side has not discovered yet), looking again at every change of either;
/// returns the view. The error shows what still differs.
pub fn wait_for_same_view(
    peer: &mut RclpyPeer,
    graph: &Graph,
    us: &Us,
    limit: Duration,
    complete: impl Fn(&Value) -> bool,
) -> Result<Value, String> {
    let changes = graph.subscribe();
    let _stop = WakeOnChanges(changes.interrupter());
    let waker = peer.waker();
    std::thread::spawn(move || loop {
        match changes.recv(None) {
            Ok(_) | Err(RecvError::Lagged(_)) => {
                if waker.send(Line::Wake).is_err() {
                    return;
                }
            }
            Err(_) => return,
        }
    });
    let mut last = (Value::Null, Value::Null);
    let same = peer.wait_for(limit, "our view equal to rclpy's", |lines| {
        let theirs = without_our_builtins(lines.iter().rev().find_map(|l| l.get("graph"))?, us);
        let ours = histories_as_compared(graph.read(|c| our_view(c, us, &theirs)), us);
        let theirs = histories_as_compared(theirs, us);
        if ours == theirs && complete(&ours) {
            Some(ours)
        } else {
            last = (ours, theirs);
            None
        }
    });
    same.map_err(|e| format!("{e}\n--- what differs:\n{}", difference(&last.0, &last.1)))
}

/// The GID of node `name`'s one `side` (`publishers`/`subscriptions`) endpoint on `dds_topic` in
/// `view`, as rclpy lists it.
pub fn gid_of(view: &Value, dds_topic: &str, side: &str, name: &str) -> Option<Gid> {
    let line = format!("Node name: {name}\n");
    view["endpoints"][dds_topic][side]
        .as_array()?
        .iter()
        .filter_map(Value::as_str)
        .find(|t| t.starts_with(&line))
        .and_then(gid_in)
}

impl RclpyPeer {
    /// The GIDs of the peer node `name`'s endpoints, each given as (DDS topic, side:
    /// `publishers`/`subscriptions`), from rclpy's own view of the graph ("graph": true in its
    /// spec), waited for at most `limit`: the GIDs rmw gave them.
    pub fn own_gids(
        &mut self,
        name: &str,
        endpoints: &[(&str, &str)],
        limit: Duration,
    ) -> Result<Vec<Gid>, String> {
        self.wait_for(
            limit,
            "the peer's endpoints in its own graph view",
            |lines| {
                let view = lines.iter().rev().find_map(|l| l.get("graph"))?;
                endpoints
                    .iter()
                    .map(|(topic, side)| gid_of(view, topic, side, name))
                    .collect()
            },
        )
    }
}
