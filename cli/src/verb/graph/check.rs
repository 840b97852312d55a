//! `horus-ros graph check`: what makes a ROS graph fail silently, each finding with the
//! endpoints involved and what to change. Formats: `docs/cli-json.md` ("graph check").
//!
//! What is looked for, on the graph as discovery settled it ([`crate::settle`]):
//!
//! - `qos_incompatible`: a writer and a reader of one DDS topic and type whose QoS cannot match,
//!   as rmw_dds_common `qos_profile_check_compatible` tells ([`check_compatible`]: reliability,
//!   durability, deadline, liveliness and its lease);
//! - `type_hash_mismatch`: endpoints of one DDS topic that announce different RIHS01 type hashes
//!   (an endpoint that announces none, [`TypeHash::ZERO`], is not compared);
//! - `type_name_mismatch`: endpoints of one DDS topic with different DDS types (they never match);
//! - `service_wire_convention`: a client and a server of one service whose participants follow
//!   the two request/reply conventions that cannot talk to each other
//!   ([`WireFlavour::for_vendor`]: an rmw_cyclonedds participant and an rmw_fastrtps one,
//!   ros2/rmw_cyclonedds#184);
//! - `duplicate_node_name`: one fully qualified node name announced more than once (`ros2 node
//!   list` warns of it: ros2node `verb/list.py`);
//! - `participant_without_nodes`: a participant with endpoints whose `ros_discovery_info`
//!   announces no node (a bare DDS application, or a ROS participant whose announcement never
//!   reached us), and a ROS participant that never announced its nodes;
//! - `endpoint_without_node`: an endpoint of a participant that announces nodes, none of which
//!   lists it;
//! - `client_without_server`: a service client with no server of its service on the graph.
//!
//! The participants' vendors (which tell the service conventions) are known only to a live
//! graph, not to the daemon's snapshot: `graph check` always discovers the graph itself.

use std::collections::{BTreeMap, BTreeSet};
use std::io::Write;

use horus_ros_graph::{
    participant_gid_from_prefix, EndpointRole as Role, Gid, GraphCache, NodeName, ParticipantKind,
};
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::{check_compatible, EndpointKind, Qos, QosCompatibility, QosDuration};
use horus_ros_rmw::service::{Peers, WireFlavour};
use horus_ros_rmw::VendorId;
use serde_json::{json, Value};

use super::document::plural;
use super::watch::RoleText;
use crate::session::Session;
use crate::verb::names;
use crate::{CliError, Global};

/// The DDS topic every ROS participant announces its nodes on: rmw's own, never a finding.
const DISCOVERY_INFO_TOPIC: &str = "ros_discovery_info";

/// Arguments of `graph check`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Finds what makes a ROS graph fail silently: QoS incompatibilities between a topic's writers and
readers (reliability, durability, deadline, liveliness), endpoints of one topic with different
type hashes or types, service clients and servers whose DDS request/reply conventions cannot
talk (an rmw_cyclonedds client and an rmw_fastrtps server, or the reverse), duplicate node names,
participants whose endpoints no node announces, and service clients with no server.

Each finding is one block: what was found, the endpoints involved (node, topic or service, GID,
DDS vendor), why it fails and what to change; then a summary line. Exit status 1 when anything is
found, 0 when the graph is clean. With --json: one document (docs/cli-json.md, \"graph check\").
The graph is discovered directly (the DDS vendors of the participants are not in the daemon's
graph); --spin-time as for every command.")]
pub struct CheckArgs {
    /// Also check the endpoints of hidden nodes (a name starting with `_`, as ros2cli's own).
    #[arg(short = 'a', long)]
    pub all: bool,
}

/// Runs `graph check`.
pub fn run(global: &Global, args: &CheckArgs) -> Result<(), CliError> {
    let session = Session::open(global)?;
    let own = session.context.gid();
    let graph = &session.graph;
    let mut input = graph.read(|cache| Input::read(cache, own));
    input.set_vendors(|gid| graph.vendor_of(gid));
    let findings = find(&input, args.all);
    let domain_id = session.context.domain_id().get();
    if global.json {
        names::print_json(&to_json(&input, &findings, domain_id))?;
    } else {
        let mut out = std::io::stdout().lock();
        match out
            .write_all(render(&input, &findings, args.all).as_bytes())
            .and_then(|()| out.flush())
        {
            // A reader that stopped early (`| head`) is not an error.
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                return Err(CliError::new(format!("could not write the findings: {e}")));
            }
            _ => {}
        }
    }
    if findings.is_empty() {
        Ok(())
    } else {
        // The findings are the message: nothing more on stderr.
        Err(CliError {
            message: String::new(),
            code: 1,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// What is checked: the graph's endpoints and participants, with their vendors.

/// One reader or writer, as the graph lists it, with its participant's vendor.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Endpoint {
    pub(super) gid: Gid,
    pub(super) participant: Gid,
    pub(super) vendor: Option<VendorId>,
    pub(super) node: Option<NodeName>,
    /// Its role and ROS name; `None` on a DDS topic that is not ROS.
    pub(super) role: Option<Role>,
    pub(super) ros_name: Option<String>,
    pub(super) kind: EndpointKind,
    pub(super) dds_topic: String,
    pub(super) dds_type: String,
    /// `pkg/msg/Name` or `pkg/srv/Name` (the DDS type when it is not a ROS type).
    pub(super) type_name: String,
    pub(super) type_hash: TypeHash,
    pub(super) qos: Qos,
}

impl Endpoint {
    /// Whether its node is hidden (only checked with `--all`).
    fn hidden(&self) -> bool {
        self.node
            .as_ref()
            .is_some_and(|n| names::is_hidden_node(&n.name))
    }

    /// The fully qualified name of its node, if a node lists it.
    fn node_name(&self) -> Option<String> {
        self.node
            .as_ref()
            .map(|n| names::node_full_name(&n.namespace, &n.name))
    }

    /// The ROS topic or service name, else the DDS topic.
    fn name(&self) -> &str {
        self.ros_name.as_deref().unwrap_or(&self.dds_topic)
    }

    /// `publisher`, `service client (request writer)`, or `writer`/`reader` for a DDS topic that
    /// is not ROS.
    fn role_text(&self) -> String {
        match self.role {
            Some(role) => match role.part() {
                Some(part) => format!("{} ({part})", role.text()),
                None => role.text().to_owned(),
            },
            None if self.kind == EndpointKind::Writer => "writer".to_owned(),
            None => "reader".to_owned(),
        }
    }
}

/// One participant, as its `ros_discovery_info` announced it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Participant {
    pub(super) gid: Gid,
    pub(super) vendor: Option<VendorId>,
    /// Its nodes as last announced; `None` while it has announced nothing.
    pub(super) nodes: Option<Vec<NodeName>>,
    /// Whether it is known to be a ROS participant (USER_DATA, a `ros_discovery_info` writer).
    pub(super) ros: bool,
}

/// Everything the checks look at, read under one lock of the graph.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Input {
    pub(super) endpoints: Vec<Endpoint>,
    pub(super) participants: Vec<Participant>,
}

impl Input {
    /// Reads the graph, leaving out the participant `own` (this command's).
    fn read(cache: &GraphCache, own: Gid) -> Self {
        let own = own.prefix();
        let endpoints = cache
            .all_endpoints()
            .into_iter()
            .filter(|e| e.gid.prefix() != own)
            .map(|e| {
                let (role, ros_name) = e.ros.map_or((None, None), |r| (Some(r.role), Some(r.name)));
                Endpoint {
                    participant: participant_gid_from_prefix(e.gid.prefix()),
                    vendor: None,
                    gid: e.gid,
                    node: e.node,
                    role,
                    ros_name,
                    kind: e.kind,
                    dds_topic: e.dds_topic,
                    dds_type: e.dds_type,
                    type_name: e.type_name,
                    type_hash: e.type_hash,
                    qos: e.qos,
                }
            })
            .collect();
        let participants = cache
            .snapshot()
            .participants
            .into_iter()
            .filter(|p| p.gid.prefix() != own)
            .map(|p| Participant {
                ros: cache.participant_kind(p.gid.prefix()) == ParticipantKind::Ros,
                vendor: None,
                gid: p.gid,
                nodes: p.nodes.map(|nodes| {
                    nodes
                        .into_iter()
                        .map(|n| NodeName {
                            name: n.node_name,
                            namespace: n.node_namespace,
                        })
                        .collect()
                }),
            })
            .collect();
        Self {
            endpoints,
            participants,
        }
    }

    /// Fills in every participant's vendor, as `vendor_of` tells it.
    fn set_vendors(&mut self, vendor_of: impl Fn(Gid) -> Option<VendorId>) {
        let mut vendors = BTreeMap::new();
        for p in &mut self.participants {
            p.vendor = vendor_of(p.gid);
            vendors.insert(p.gid, p.vendor);
        }
        for e in &mut self.endpoints {
            e.vendor = *vendors
                .entry(e.participant)
                .or_insert_with(|| vendor_of(e.participant));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Findings.

/// What a finding is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Kind {
    QosIncompatible,
    TypeHashMismatch,
    TypeNameMismatch,
    ServiceWireConvention,
    DuplicateNodeName,
    ParticipantWithoutNodes,
    EndpointWithoutNode,
    ClientWithoutServer,
}

impl Kind {
    /// `kind` in JSON.
    pub(super) fn json(self) -> &'static str {
        match self {
            Self::QosIncompatible => "qos_incompatible",
            Self::TypeHashMismatch => "type_hash_mismatch",
            Self::TypeNameMismatch => "type_name_mismatch",
            Self::ServiceWireConvention => "service_wire_convention",
            Self::DuplicateNodeName => "duplicate_node_name",
            Self::ParticipantWithoutNodes => "participant_without_nodes",
            Self::EndpointWithoutNode => "endpoint_without_node",
            Self::ClientWithoutServer => "client_without_server",
        }
    }

    /// The summary line's name of `n` findings of this kind.
    fn counted(self, n: usize) -> String {
        let (one, many) = match self {
            Self::QosIncompatible => ("QoS incompatibility", "QoS incompatibilities"),
            Self::TypeHashMismatch => ("type hash mismatch", "type hash mismatches"),
            Self::TypeNameMismatch => ("type mismatch", "type mismatches"),
            Self::ServiceWireConvention => (
                "service wire convention mismatch",
                "service wire convention mismatches",
            ),
            Self::DuplicateNodeName => ("duplicate node name", "duplicate node names"),
            Self::ParticipantWithoutNodes => {
                ("participant without nodes", "participants without nodes")
            }
            Self::EndpointWithoutNode => ("endpoint without node", "endpoints without node"),
            Self::ClientWithoutServer => ("client without server", "clients without server"),
        };
        format!("{n} {}", if n == 1 { one } else { many })
    }
}

/// What a finding shows of each of its endpoints beside its identity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Detail {
    /// The QoS policies that decide matching.
    Qos,
    /// The type and its hash.
    Type,
    /// Nothing more.
    None,
    /// In text, one line a participant (its count of endpoints) instead of one an endpoint.
    PerParticipant,
}

/// One finding: what, where, why, and what to change.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Finding {
    pub(super) kind: Kind,
    /// The topic, service, node or participant it is about.
    pub(super) subject: String,
    /// One line: what was found.
    pub(super) summary: String,
    /// Why it fails, one reason a line.
    pub(super) why: Vec<String>,
    /// Indexes into [`Input::endpoints`].
    pub(super) endpoints: Vec<usize>,
    /// Participants involved that have no endpoint to show (a silent ROS participant).
    pub(super) participants: Vec<Gid>,
    /// What to change.
    pub(super) fix: String,
    detail: Detail,
}

/// Every finding on `input`, in a stable order (by kind, then subject); endpoints of hidden
/// nodes only with `all`.
pub(super) fn find(input: &Input, all: bool) -> Vec<Finding> {
    let checked: Vec<usize> = (0..input.endpoints.len())
        .filter(|&i| all || !input.endpoints[i].hidden())
        .collect();
    let mut by_topic: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for &i in &checked {
        let e = &input.endpoints[i];
        if e.dds_topic != DISCOVERY_INFO_TOPIC {
            by_topic.entry(&e.dds_topic).or_default().push(i);
        }
    }
    let mut findings = Vec::new();
    for (topic, endpoints) in &by_topic {
        qos_incompatible(input, endpoints, &mut findings);
        type_mismatches(input, topic, endpoints, &mut findings);
    }
    services(input, &checked, &mut findings);
    duplicate_node_names(input, all, &mut findings);
    without_nodes(input, &mut findings);
    findings.sort_by(|a, b| (a.kind, &a.subject).cmp(&(b.kind, &b.subject)));
    findings
}

/// The display name of a topic's endpoints: the ROS name of the first that has one.
fn subject_of(input: &Input, endpoints: &[usize]) -> String {
    endpoints
        .first()
        .map(|&i| input.endpoints[i].name().to_owned())
        .unwrap_or_default()
}

/// What to change for one of rmw_dds_common's QoS errors (the reason text of
/// [`check_compatible`], rmw_dds_common `src/qos.cpp`).
fn qos_fix(error: &str, writer: &Endpoint, reader: &Endpoint) -> String {
    let (w, r) = (writer.role_text(), reader.role_text());
    let (wq, rq) = (&writer.qos, &reader.qos);
    match error {
        "Best effort publisher and reliable subscription" => {
            format!("make the {r} BEST_EFFORT or the {w} RELIABLE")
        }
        "Volatile publisher and transient local subscription" => {
            format!("make the {r} VOLATILE or the {w} TRANSIENT_LOCAL")
        }
        // A discovered endpoint without a deadline announces an infinite one (DDS), which
        // rmw_dds_common reports as the second error.
        "Subscription has a deadline, but publisher does not"
        | "Subscription deadline is less than publisher deadline"
            if unlimited(wq.deadline) =>
        {
            format!(
                "give the {w} a deadline of at most {} or remove the {r}'s deadline",
                duration(rq.deadline)
            )
        }
        "Subscription deadline is less than publisher deadline" => format!(
            "make the {r}'s deadline at least {} or the {w}'s at most {}",
            duration(wq.deadline),
            duration(rq.deadline)
        ),
        "Publisher's liveliness is automatic and subscription's is manual by topic" => {
            format!("make the {r}'s liveliness AUTOMATIC or the {w}'s MANUAL_BY_TOPIC")
        }
        "Subscription has a liveliness lease duration, but publisher does not"
        | "Subscription liveliness lease duration is less than publisher"
            if unlimited(wq.liveliness_lease_duration) =>
        {
            format!(
                "give the {w} a liveliness lease duration of at most {} or remove the {r}'s",
                duration(rq.liveliness_lease_duration)
            )
        }
        "Subscription liveliness lease duration is less than publisher" => format!(
            "make the {r}'s liveliness lease duration at least {} or the {w}'s at most {}",
            duration(wq.liveliness_lease_duration),
            duration(rq.liveliness_lease_duration)
        ),
        _ => format!("give the {w} and the {r} compatible QoS"),
    }
}

/// Whether a QoS duration sets no limit (unset, or infinite as discovery reports it).
fn unlimited(d: QosDuration) -> bool {
    d.is_default() || d.is_infinite()
}

/// Every writer/reader pair of one DDS topic and type whose QoS cannot match.
fn qos_incompatible(input: &Input, endpoints: &[usize], findings: &mut Vec<Finding>) {
    let of = |kind| {
        endpoints
            .iter()
            .copied()
            .filter(move |&i| input.endpoints[i].kind == kind)
    };
    for w in of(EndpointKind::Writer) {
        for r in of(EndpointKind::Reader) {
            let (writer, reader) = (&input.endpoints[w], &input.endpoints[r]);
            // Endpoints of different types never match anyway (see type_name_mismatch).
            if writer.dds_type != reader.dds_type {
                continue;
            }
            let QosCompatibility::Error(reason) = check_compatible(&writer.qos, &reader.qos) else {
                continue;
            };
            let errors: Vec<&str> = reason
                .split(';')
                .map(|s| s.trim().trim_start_matches("ERROR: "))
                .filter(|s| !s.is_empty())
                .collect();
            let fixes: Vec<String> = errors
                .iter()
                .map(|error| qos_fix(error, writer, reader))
                .collect();
            findings.push(Finding {
                kind: Kind::QosIncompatible,
                subject: writer.name().to_owned(),
                summary: format!(
                    "QoS incompatible on {} ({}): the {} and the {} never match, no data flows",
                    writer.name(),
                    writer.type_name,
                    writer.role_text(),
                    reader.role_text()
                ),
                why: errors.iter().map(|e| (*e).to_owned()).collect(),
                endpoints: vec![w, r],
                participants: Vec::new(),
                fix: fixes.join("; "),
                detail: Detail::Qos,
            });
        }
    }
}

/// Endpoints of one DDS topic with different DDS types, or different non-zero type hashes.
fn type_mismatches(input: &Input, topic: &str, endpoints: &[usize], out: &mut Vec<Finding>) {
    let name = subject_of(input, endpoints);
    let mut by_type: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for &i in endpoints {
        by_type
            .entry(&input.endpoints[i].dds_type)
            .or_default()
            .push(i);
    }
    if by_type.len() > 1 {
        let types: Vec<String> = by_type
            .values()
            .map(|ids| {
                let e = &input.endpoints[ids[0]];
                format!("{} ({})", e.type_name, plural(ids.len(), "endpoint"))
            })
            .collect();
        out.push(Finding {
            kind: Kind::TypeNameMismatch,
            subject: name.clone(),
            summary: format!(
                "{} types on {name} (DDS topic {topic}): endpoints of different types never match",
                by_type.len()
            ),
            why: vec![format!("types: {}", types.join(", "))],
            endpoints: by_type.values().flatten().copied().collect(),
            participants: Vec::new(),
            fix: format!("use one type on {name} everywhere (or rename the topic of one side)"),
            detail: Detail::Type,
        });
    }
    for ids in by_type.values() {
        let mut by_hash: BTreeMap<String, Vec<usize>> = BTreeMap::new();
        for &i in ids {
            let hash = input.endpoints[i].type_hash;
            if hash.is_set() {
                by_hash.entry(hash.to_string()).or_default().push(i);
            }
        }
        if by_hash.len() < 2 {
            continue;
        }
        let type_name = &input.endpoints[ids[0]].type_name;
        let hashes: Vec<String> = by_hash
            .iter()
            .map(|(hash, ids)| format!("{hash} ({})", plural(ids.len(), "endpoint")))
            .collect();
        out.push(Finding {
            kind: Kind::TypeHashMismatch,
            subject: name.clone(),
            summary: format!(
                "{} definitions of {type_name} on {name}: the endpoints announce different type \
                 hashes, so they disagree on the message layout and data is misread or dropped",
                by_hash.len()
            ),
            why: vec![format!("type hashes: {}", hashes.join(", "))],
            endpoints: by_hash.values().flatten().copied().collect(),
            participants: Vec::new(),
            fix: format!(
                "build every node that uses {type_name} on {name} from the same definition of \
                 {type_name} (the same version of its package)"
            ),
            detail: Detail::Type,
        });
    }
}

/// The DDS product of a vendor, as findings name it.
fn vendor_text(vendor: Option<VendorId>) -> String {
    match vendor {
        Some(VendorId::FAST_DDS) => "Fast DDS".to_owned(),
        Some(VendorId::CYCLONE_DDS) => "Cyclone DDS".to_owned(),
        Some(VendorId::RUSTDDS) => "RustDDS".to_owned(),
        Some(VendorId([a, b])) => format!("vendor {a:02x}.{b:02x}"),
        None => "unknown vendor".to_owned(),
    }
}

/// Why a client of `client` vendor and a server of `server` vendor cannot talk, if they cannot.
///
/// rmw_fastrtps (Fast DDS) correlates requests and replies through the inline QoS
/// `related_sample_identity`; rmw_cyclonedds (Cyclone DDS) through a 16-byte header
/// (`cdds_request_header_t`) at the start of every request and reply body (see
/// rmw/src/service/convention.rs). Participants of other vendors (RustDDS: horus-ros, which
/// speaks both on its rustdds backend) are not judged.
fn convention_clash(client: Option<VendorId>, server: Option<VendorId>) -> Option<String> {
    let known =
        |v: Option<VendorId>| matches!(v, Some(VendorId::FAST_DDS) | Some(VendorId::CYCLONE_DDS));
    if !known(client) || !known(server) {
        return None;
    }
    match (
        WireFlavour::for_vendor(client),
        WireFlavour::for_vendor(server),
    ) {
        (WireFlavour::CycloneDds, WireFlavour::FastRtps) => Some(
            "the Cyclone DDS (rmw_cyclonedds) client puts a 16-byte request header in front of \
             each request, which the Fast DDS (rmw_fastrtps) server reads as the request's first \
             fields; its reply carries the request's identity in related_sample_identity only, \
             and the client, which looks for its header in the reply, drops it: calls are never \
             answered (ros2/rmw_cyclonedds#184)"
                .to_owned(),
        ),
        (WireFlavour::FastRtps, WireFlavour::CycloneDds) => Some(
            "the Fast DDS (rmw_fastrtps) client sends requests without the 16-byte request \
             header the Cyclone DDS (rmw_cyclonedds) server expects: the server reads the \
             request's first 16 bytes as the header (and drops a shorter request), and its \
             reply has no related_sample_identity, which is how the client matches replies to \
             requests: calls are never answered (ros2/rmw_cyclonedds#184)"
                .to_owned(),
        ),
        _ => None,
    }
}

/// Clients whose servers follow the other wire convention, and clients with no server.
fn services(input: &Input, checked: &[usize], findings: &mut Vec<Finding>) {
    let mut clients: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    let mut servers: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    // Servers are looked for among every endpoint: a hidden node's server still answers.
    for (i, e) in input.endpoints.iter().enumerate() {
        if let (Some(Role::ServerRequestReader), Some(name)) = (e.role, &e.ros_name) {
            servers.entry(name).or_default().push(i);
        }
    }
    for &i in checked {
        let e = &input.endpoints[i];
        if let (Some(Role::ClientRequestWriter), Some(name)) = (e.role, &e.ros_name) {
            clients.entry(name).or_default().push(i);
        }
    }
    for (service, client_ids) in &clients {
        let Some(server_ids) = servers.get(service) else {
            let ty = &input.endpoints[client_ids[0]].type_name;
            let mut elsewhere: Vec<&str> = servers
                .iter()
                .filter(|(_, ids)| ids.iter().any(|&s| input.endpoints[s].type_name == *ty))
                .map(|(name, _)| *name)
                .collect();
            elsewhere.dedup();
            let mut fix = format!(
                "start a server of {service} ({ty}), or point the client at the right name \
                 (namespace, remapping)"
            );
            if !elsewhere.is_empty() {
                fix.push_str(&format!(
                    "; servers of {ty} run as {}",
                    elsewhere.join(", ")
                ));
            }
            findings.push(Finding {
                kind: Kind::ClientWithoutServer,
                subject: (*service).to_owned(),
                summary: format!(
                    "{} of {service} ({ty}) but no server: its calls wait forever",
                    plural(client_ids.len(), "client")
                ),
                why: Vec::new(),
                endpoints: client_ids.clone(),
                participants: Vec::new(),
                fix,
                detail: Detail::None,
            });
            continue;
        };
        for &c in client_ids {
            for &s in server_ids {
                let (client, server) = (&input.endpoints[c], &input.endpoints[s]);
                let Some(why) = convention_clash(client.vendor, server.vendor) else {
                    continue;
                };
                findings.push(Finding {
                    kind: Kind::ServiceWireConvention,
                    subject: (*service).to_owned(),
                    summary: format!(
                        "the {} client and the {} server of {service} follow request/reply \
                         conventions that cannot talk",
                        vendor_text(client.vendor),
                        vendor_text(server.vendor)
                    ),
                    why: vec![why],
                    endpoints: vec![c, s],
                    participants: Vec::new(),
                    fix: "run the client and the server on the same rmw (RMW_IMPLEMENTATION=\
                          rmw_fastrtps_cpp for both, or rmw_cyclonedds_cpp for both); a horus-ros \
                          node on the rustdds backend calls and serves both"
                        .to_owned(),
                    detail: Detail::None,
                });
            }
        }
    }
}

/// Fully qualified node names that more than one node announces.
fn duplicate_node_names(input: &Input, all: bool, findings: &mut Vec<Finding>) {
    let mut seen: BTreeMap<String, Vec<Gid>> = BTreeMap::new();
    for p in &input.participants {
        for n in p.nodes.iter().flatten() {
            if all || !names::is_hidden_node(&n.name) {
                seen.entry(names::node_full_name(&n.namespace, &n.name))
                    .or_default()
                    .push(p.gid);
            }
        }
    }
    for (name, participants) in seen {
        if participants.len() < 2 {
            continue;
        }
        let endpoints: Vec<usize> = input
            .endpoints
            .iter()
            .enumerate()
            .filter(|(_, e)| e.node_name().as_deref() == Some(name.as_str()))
            .map(|(i, _)| i)
            .collect();
        let distinct: BTreeSet<Gid> = participants.iter().copied().collect();
        findings.push(Finding {
            kind: Kind::DuplicateNodeName,
            subject: name.clone(),
            summary: format!(
                "{} nodes are named {name} (in {}): tools, parameters and /rosout cannot tell \
                 them apart",
                participants.len(),
                plural(distinct.len(), "participant")
            ),
            why: vec![
                "nodes are addressed by name: their parameter and type description services \
                 share one name (a call reaches both servers), `ros2 node info` and `ros2 param` \
                 cannot tell which is meant, and their /rosout logs carry the same name"
                    .to_owned(),
            ],
            endpoints,
            participants: distinct.into_iter().collect(),
            fix: format!(
                "give each node its own name, e.g. `--ros-args -r __node:=<new name>` or another \
                 namespace (`-r __ns:=/<namespace>`) for all but one {name}"
            ),
            detail: Detail::PerParticipant,
        });
    }
}

/// Participants whose endpoints no node lists.
fn without_nodes(input: &Input, findings: &mut Vec<Finding>) {
    let mut unlisted: BTreeMap<Gid, Vec<usize>> = BTreeMap::new();
    for (i, e) in input.endpoints.iter().enumerate() {
        if e.node.is_none() && e.dds_topic != DISCOVERY_INFO_TOPIC {
            unlisted.entry(e.participant).or_default().push(i);
        }
    }
    let participant = |gid: Gid| input.participants.iter().find(|p| p.gid == gid);
    for (gid, endpoints) in &unlisted {
        let p = participant(*gid);
        let vendor = vendor_text(endpoints.first().and_then(|&i| input.endpoints[i].vendor));
        let announced = p.and_then(|p| p.nodes.as_ref());
        let count = plural(endpoints.len(), "endpoint");
        match announced {
            Some(nodes) if !nodes.is_empty() => findings.push(Finding {
                kind: Kind::EndpointWithoutNode,
                subject: gid.to_string(),
                summary: format!(
                    "participant {gid} ({vendor}) announces {} but none of them lists {count} \
                     of it: ROS tools show no node for them",
                    plural(nodes.len(), "node")
                ),
                why: Vec::new(),
                endpoints: endpoints.clone(),
                participants: Vec::new(),
                fix: "create these endpoints through a node (rcl), or update the participant's \
                      ros_discovery_info when they are created"
                    .to_owned(),
                detail: Detail::None,
            }),
            _ => {
                let how = if announced.is_some() {
                    "announces no node on ros_discovery_info"
                } else if p.is_some_and(|p| p.ros) {
                    "is a ROS participant whose ros_discovery_info never reached us"
                } else {
                    "announces no node (a bare DDS application, not a ROS node)"
                };
                findings.push(Finding {
                    kind: Kind::ParticipantWithoutNodes,
                    subject: gid.to_string(),
                    summary: format!(
                        "participant {gid} ({vendor}) {how}: no node owns its {count}"
                    ),
                    why: Vec::new(),
                    endpoints: endpoints.clone(),
                    participants: Vec::new(),
                    fix: without_nodes_fix(announced.is_some(), p.is_some_and(|p| p.ros)),
                    detail: Detail::None,
                });
            }
        }
    }
    // A ROS participant that never announced its nodes and has no endpoint of its own.
    for p in &input.participants {
        if p.ros && p.nodes.is_none() && !unlisted.contains_key(&p.gid) {
            findings.push(Finding {
                kind: Kind::ParticipantWithoutNodes,
                subject: p.gid.to_string(),
                summary: format!(
                    "participant {} ({}) is a ROS participant whose ros_discovery_info never \
                     reached us: its nodes, if any, are invisible",
                    p.gid,
                    vendor_text(p.vendor)
                ),
                why: Vec::new(),
                endpoints: Vec::new(),
                participants: vec![p.gid],
                fix: without_nodes_fix(false, true),
                detail: Detail::None,
            });
        }
    }
}

/// What to change for a participant without nodes.
fn without_nodes_fix(announced: bool, ros: bool) -> String {
    if announced || ros {
        "check that the participant publishes its nodes on ros_discovery_info and that its \
         samples reach this host (reliable, transient-local; a DDS partition, security or \
         interface setting that blocks it)"
            .to_owned()
    } else {
        "if it should be a ROS node, create its endpoints through rcl (a ROS 2 client library); \
         a bare DDS application's endpoints are shown by ROS tools as _CREATED_BY_BARE_DDS_APP_"
            .to_owned()
    }
}

// ---------------------------------------------------------------------------------------------
// Output.

/// A QoS duration in seconds (`Infinite`, `1.5 s`).
fn duration(d: QosDuration) -> String {
    if unlimited(d) {
        "Infinite".to_owned()
    } else {
        // Nanoseconds as f64: exact up to about 104 days, enough to read.
        #[allow(clippy::cast_precision_loss)]
        let secs = d.total_nanos() as f64 / 1e9;
        format!("{secs} s")
    }
}

/// The QoS policies that decide matching, in one line.
fn qos_line(qos: &Qos) -> String {
    format!(
        "{}, {}, deadline {}, liveliness {} (lease {})",
        qos.reliability,
        qos.durability,
        duration(qos.deadline),
        qos.liveliness,
        duration(qos.liveliness_lease_duration)
    )
}

/// One endpoint's line in a finding's block.
fn endpoint_line(e: &Endpoint, detail: Detail) -> String {
    let node = e.node_name().unwrap_or_else(|| "(none)".to_owned());
    let mut line = format!(
        "    - {} {}  node {node}  gid {}  {}",
        e.role_text(),
        e.name(),
        e.gid,
        vendor_text(e.vendor)
    );
    match detail {
        Detail::Qos => line.push_str(&format!("\n        QoS: {}", qos_line(&e.qos))),
        Detail::Type => {
            let hash = if e.type_hash.is_set() {
                e.type_hash.to_string()
            } else {
                "none announced".to_owned()
            };
            line.push_str(&format!("\n        type {} hash {hash}", e.type_name));
        }
        Detail::None | Detail::PerParticipant => {}
    }
    line
}

/// The vendor of participant `gid`, if known.
fn participant_vendor(input: &Input, gid: Gid) -> Option<VendorId> {
    input
        .participants
        .iter()
        .find(|p| p.gid == gid)
        .and_then(|p| p.vendor)
}

/// The text output: one block a finding, then the summary line.
fn render(input: &Input, findings: &[Finding], all: bool) -> String {
    let mut out = String::new();
    for (n, f) in findings.iter().enumerate() {
        out.push_str(&format!("[{}] {}: {}\n", n + 1, f.kind.json(), f.summary));
        if f.detail == Detail::PerParticipant {
            for p in &f.participants {
                let n = f
                    .endpoints
                    .iter()
                    .filter(|&&i| input.endpoints[i].participant == *p)
                    .count();
                out.push_str(&format!(
                    "    - {} in participant {p}  {}  {}\n",
                    f.subject,
                    vendor_text(participant_vendor(input, *p)),
                    plural(n, "endpoint")
                ));
            }
        } else {
            for &i in &f.endpoints {
                out.push_str(&endpoint_line(&input.endpoints[i], f.detail));
                out.push('\n');
            }
            for p in &f.participants {
                out.push_str(&format!(
                    "    - participant {p}  {}\n",
                    vendor_text(participant_vendor(input, *p))
                ));
            }
        }
        for why in &f.why {
            out.push_str(&format!("    why: {why}\n"));
        }
        out.push_str(&format!("    fix: {}\n\n", f.fix));
    }
    out.push_str(&summary(input, findings, all));
    out.push('\n');
    out
}

/// `3 findings: 1 QoS incompatibility, 2 clients without server (4 nodes, 3 topics, 1 service
/// checked)`, or `No findings (…)`.
fn summary(input: &Input, findings: &[Finding], all: bool) -> String {
    let nodes: usize = input
        .participants
        .iter()
        .flat_map(|p| p.nodes.iter().flatten())
        .filter(|n| all || !names::is_hidden_node(&n.name))
        .count();
    let mut topics = BTreeSet::new();
    let mut services = BTreeSet::new();
    for e in &input.endpoints {
        match (e.role, &e.ros_name) {
            (Some(r), Some(name)) if r.is_service() => services.insert(name),
            (Some(_), Some(name)) => topics.insert(name),
            _ => false,
        };
    }
    let scope = format!(
        "{}, {}, {} checked",
        plural(nodes, "node"),
        plural(topics.len(), "topic"),
        plural(services.len(), "service")
    );
    if findings.is_empty() {
        return format!("No findings ({scope})");
    }
    let mut counts: BTreeMap<Kind, usize> = BTreeMap::new();
    for f in findings {
        *counts.entry(f.kind).or_default() += 1;
    }
    let counts: Vec<String> = counts.into_iter().map(|(k, n)| k.counted(n)).collect();
    format!(
        "{}: {} ({scope})",
        plural(findings.len(), "finding"),
        counts.join(", ")
    )
}

/// One endpoint in JSON.
fn endpoint_json(e: &Endpoint) -> Value {
    json!({
        "gid": e.gid.to_string(),
        "participant": e.participant.to_string(),
        "vendor": e.vendor.map(|v| vendor_text(Some(v))),
        "node": e.node_name(),
        "role": e.role.map(|r| r.json_kind()),
        "part": e.role.and_then(|r| r.part()).map(|p| p.replace(' ', "_")),
        "name": e.ros_name,
        "dds_topic": e.dds_topic,
        "type": e.type_name,
        "type_hash": e.type_hash.is_set().then(|| e.type_hash.to_string()),
        "qos": names::qos_json(&e.qos),
    })
}

/// The JSON document (`docs/cli-json.md`, "graph check").
fn to_json(input: &Input, findings: &[Finding], domain_id: u16) -> Value {
    let findings: Vec<Value> = findings
        .iter()
        .map(|f| {
            json!({
                "kind": f.kind.json(),
                "subject": f.subject,
                "summary": f.summary,
                "endpoints": f.endpoints.iter().map(|&i| endpoint_json(&input.endpoints[i])).collect::<Vec<_>>(),
                "participants": f.participants.iter().map(|p| {
                    let vendor = participant_vendor(input, *p);
                    json!({"gid": p.to_string(), "vendor": vendor.map(|v| vendor_text(Some(v)))})
                }).collect::<Vec<_>>(),
                "why": f.why,
                "fix": f.fix,
            })
        })
        .collect();
    json!({
        "domain_id": domain_id,
        "findings": findings,
    })
}

#[cfg(test)]
mod tests {
    use horus_ros_rmw::qos::{DurabilityPolicy, LivelinessPolicy, ReliabilityPolicy};

    use super::*;

    fn gid(participant: u8, entity: u8, writer: bool) -> Gid {
        let mut data = [0u8; 16];
        data[..12].copy_from_slice(&[participant; 12]);
        data[15] = if writer {
            entity << 4 | 0x03
        } else {
            entity << 4 | 0x04
        };
        Gid::from_bytes(data)
    }

    fn participant(p: u8, vendor: VendorId, nodes: &[&str]) -> Participant {
        Participant {
            gid: participant_gid_from_prefix([p; 12]),
            vendor: Some(vendor),
            nodes: Some(
                nodes
                    .iter()
                    .map(|n| NodeName {
                        name: (*n).to_owned(),
                        namespace: "/".to_owned(),
                    })
                    .collect(),
            ),
            ros: true,
        }
    }

    fn endpoint(p: u8, entity: u8, node: Option<&str>, role: Role, name: &str) -> Endpoint {
        let writer = role.kind() == EndpointKind::Writer;
        let service = role.is_service();
        Endpoint {
            gid: gid(p, entity, writer),
            participant: participant_gid_from_prefix([p; 12]),
            vendor: None,
            node: node.map(|n| NodeName {
                name: n.to_owned(),
                namespace: "/".to_owned(),
            }),
            role: Some(role),
            ros_name: Some(name.to_owned()),
            kind: role.kind(),
            dds_topic: match role {
                Role::Publisher | Role::Subscription => format!("rt{name}"),
                Role::ServerRequestReader | Role::ClientRequestWriter => {
                    format!("rq{name}Request")
                }
                _ => format!("rr{name}Reply"),
            },
            dds_type: if service {
                "example_interfaces::srv::dds_::AddTwoInts_Request_".to_owned()
            } else {
                "std_msgs::msg::dds_::String_".to_owned()
            },
            type_name: if service {
                "example_interfaces/srv/AddTwoInts".to_owned()
            } else {
                "std_msgs/msg/String".to_owned()
            },
            type_hash: TypeHash::ZERO,
            qos: Qos::default(),
        }
    }

    fn input(participants: Vec<Participant>, endpoints: Vec<Endpoint>) -> Input {
        let mut input = Input {
            endpoints,
            participants,
        };
        let vendors: BTreeMap<Gid, Option<VendorId>> = input
            .participants
            .iter()
            .map(|p| (p.gid, p.vendor))
            .collect();
        input.set_vendors(|g| vendors.get(&g).copied().flatten());
        input
    }

    fn kinds(findings: &[Finding]) -> Vec<&'static str> {
        findings.iter().map(|f| f.kind.json()).collect()
    }

    #[test]
    fn a_clean_graph_has_no_findings() {
        let g = input(
            vec![participant(1, VendorId::FAST_DDS, &["talker", "listener"])],
            vec![
                endpoint(1, 1, Some("talker"), Role::Publisher, "/chatter"),
                endpoint(1, 2, Some("listener"), Role::Subscription, "/chatter"),
            ],
        );
        let findings = find(&g, false);
        assert!(findings.is_empty(), "{findings:?}");
        assert_eq!(
            summary(&g, &findings, false),
            "No findings (2 nodes, 1 topic, 0 services checked)"
        );
    }

    #[test]
    fn qos_errors_are_found_with_their_fixes() {
        let mut publisher = endpoint(1, 1, Some("talker"), Role::Publisher, "/chatter");
        publisher.qos = Qos::default()
            .with_reliability(ReliabilityPolicy::BestEffort)
            .with_durability(DurabilityPolicy::Volatile);
        let mut subscription = endpoint(1, 2, Some("listener"), Role::Subscription, "/chatter");
        subscription.qos = Qos::default()
            .with_reliability(ReliabilityPolicy::Reliable)
            .with_durability(DurabilityPolicy::TransientLocal)
            .with_liveliness(LivelinessPolicy::ManualByTopic)
            .with_deadline(std::time::Duration::from_millis(1500));
        publisher.qos = publisher.qos.with_liveliness(LivelinessPolicy::Automatic);
        let g = input(
            vec![participant(1, VendorId::FAST_DDS, &["talker", "listener"])],
            vec![publisher, subscription],
        );
        let findings = find(&g, false);
        assert_eq!(kinds(&findings), ["qos_incompatible"]);
        let f = &findings[0];
        assert_eq!(
            f.why,
            [
                "Best effort publisher and reliable subscription",
                "Volatile publisher and transient local subscription",
                "Subscription has a deadline, but publisher does not",
                "Publisher's liveliness is automatic and subscription's is manual by topic",
            ]
        );
        assert_eq!(
            f.fix,
            "make the subscription BEST_EFFORT or the publisher RELIABLE; make the subscription \
             VOLATILE or the publisher TRANSIENT_LOCAL; give the publisher a deadline of at most \
             1.5 s or remove the subscription's deadline; make the subscription's liveliness \
             AUTOMATIC or the publisher's MANUAL_BY_TOPIC"
        );
        assert_eq!(f.endpoints, [0, 1]);
    }

    #[test]
    fn different_hashes_on_one_topic_are_found_unknown_ones_are_not() {
        let hash = |b: u8| TypeHash::parse(&format!("RIHS01_{}", format!("{b:02x}").repeat(32)));
        let mut a = endpoint(1, 1, Some("a"), Role::Publisher, "/chatter");
        a.type_hash = hash(1).expect("hash");
        let mut b = endpoint(1, 2, Some("b"), Role::Publisher, "/chatter");
        b.type_hash = hash(2).expect("hash");
        let c = endpoint(1, 3, Some("c"), Role::Subscription, "/chatter");
        let g = input(
            vec![participant(1, VendorId::CYCLONE_DDS, &["a", "b", "c"])],
            vec![a.clone(), b, c.clone()],
        );
        let findings = find(&g, false);
        assert_eq!(kinds(&findings), ["type_hash_mismatch"]);
        assert_eq!(findings[0].endpoints, [0, 1]);
        let g = input(
            vec![participant(1, VendorId::CYCLONE_DDS, &["a", "c"])],
            vec![a, c],
        );
        assert!(find(&g, false).is_empty());
    }

    #[test]
    fn conventions_clash_between_fast_dds_and_cyclone_dds_only() {
        let f = Some(VendorId::FAST_DDS);
        let c = Some(VendorId::CYCLONE_DDS);
        let r = Some(VendorId::RUSTDDS);
        assert!(convention_clash(c, f).is_some());
        assert!(convention_clash(f, c).is_some());
        for (client, server) in [(f, f), (c, c), (r, f), (c, r), (None, f), (c, None)] {
            assert_eq!(
                convention_clash(client, server),
                None,
                "{client:?} {server:?}"
            );
        }
        let g = input(
            vec![
                participant(1, VendorId::CYCLONE_DDS, &["caller"]),
                participant(2, VendorId::FAST_DDS, &["adder"]),
            ],
            vec![
                endpoint(1, 1, Some("caller"), Role::ClientRequestWriter, "/add"),
                endpoint(1, 2, Some("caller"), Role::ClientResponseReader, "/add"),
                endpoint(2, 1, Some("adder"), Role::ServerRequestReader, "/add"),
                endpoint(2, 2, Some("adder"), Role::ServerResponseWriter, "/add"),
            ],
        );
        let findings = find(&g, false);
        assert_eq!(kinds(&findings), ["service_wire_convention"]);
        assert_eq!(findings[0].endpoints, [0, 2]);
    }

    #[test]
    fn clients_without_server_duplicates_and_nodeless_participants() {
        let mut bare = endpoint(3, 1, None, Role::Publisher, "/x");
        bare.ros_name = None;
        bare.role = None;
        bare.dds_topic = "bare_chatter".to_owned();
        let g = input(
            vec![
                participant(1, VendorId::RUSTDDS, &["twin", "caller"]),
                participant(2, VendorId::FAST_DDS, &["twin", "_hidden"]),
                Participant {
                    gid: participant_gid_from_prefix([3; 12]),
                    vendor: Some(VendorId::CYCLONE_DDS),
                    nodes: None,
                    ros: false,
                },
                Participant {
                    gid: participant_gid_from_prefix([4; 12]),
                    vendor: Some(VendorId::CYCLONE_DDS),
                    nodes: None,
                    ros: true,
                },
            ],
            vec![
                endpoint(1, 1, Some("caller"), Role::ClientRequestWriter, "/nobody"),
                endpoint(1, 2, Some("caller"), Role::ClientResponseReader, "/nobody"),
                endpoint(2, 1, Some("_hidden"), Role::ClientRequestWriter, "/ignored"),
                endpoint(2, 2, Some("twin"), Role::Publisher, "/twin_topic"),
                bare,
            ],
        );
        let findings = find(&g, false);
        assert_eq!(
            kinds(&findings),
            [
                "duplicate_node_name",
                "participant_without_nodes",
                "participant_without_nodes",
                "client_without_server"
            ]
        );
        assert_eq!(findings[0].subject, "/twin");
        assert_eq!(findings[0].endpoints, [3]);
        assert_eq!(findings[0].participants.len(), 2);
        assert_eq!(findings[1].endpoints, [4]);
        assert_eq!(findings[2].participants.len(), 1);
        assert_eq!(findings[3].subject, "/nobody");
        assert_eq!(findings[3].endpoints, [0]);
        let all = find(&g, true);
        assert_eq!(all.len(), 5, "{all:?}");
        let text = render(&g, &findings, false);
        assert!(
            text.ends_with(
                "4 findings: 1 duplicate node name, 2 participants without nodes, 1 client \
                 without server (3 nodes, 1 topic, 2 services checked)\n"
            ),
            "{text}"
        );
    }
}
