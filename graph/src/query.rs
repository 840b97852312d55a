//! Name queries: nodes, topics and services with their types, by node, and counts
//! (rmw_dds_common `graph_cache.cpp` `get_node_names`, `get_names_and_types`,
//! `get_*_names_and_types_by_node`, `get_*_count`; demangling as rmw_fastrtps_shared_cpp
//! `rmw_node_info_and_types.cpp`, `rmw_service_names_and_types.cpp`, `rmw_count.cpp`, jazzy).

use std::collections::{BTreeMap, BTreeSet};

use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo};
use horus_ros_rmw::names::{
    DemangledTopic, RosTypeName, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX,
};
use horus_ros_rmw::qos::EndpointKind;

use crate::cache::{GraphCache, TopicEntry, TypeUse};
use crate::endpoint::EndpointEntry;
use crate::error::GraphError;
use crate::{CREATED_BY_BARE_DDS_APP, NODE_NAMESPACE_UNKNOWN, NODE_NAME_UNKNOWN};

/// Names (sorted) each with its set of demangled types (sorted).
pub type NamesAndTypes = BTreeMap<String, BTreeSet<String>>;

/// One node of the graph, as `rcl_get_node_names_with_enclaves` reports it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct NodeInfo {
    /// Node namespace.
    pub namespace: String,
    /// Node name.
    pub name: String,
    /// Enclave of its participant, when known.
    pub enclave: Option<String>,
}

/// Who created an endpoint, as rmw_dds_common's `EndpointCreator`.
pub(crate) enum Creator<'a> {
    /// A node listed in its participant's `ros_discovery_info`.
    Node(&'a NodeEntitiesInfo),
    /// The participant is known but none of its nodes lists the endpoint.
    UnknownNode,
    /// The participant is not known.
    BareDds,
}

impl<'a> Creator<'a> {
    /// The node name and namespace to report.
    pub(crate) fn name_and_namespace(&self) -> (&'a str, &'a str) {
        match self {
            Self::Node(n) => (&n.node_name, &n.node_namespace),
            Self::UnknownNode => (NODE_NAME_UNKNOWN, NODE_NAMESPACE_UNKNOWN),
            Self::BareDds => (CREATED_BY_BARE_DDS_APP, CREATED_BY_BARE_DDS_APP),
        }
    }
}

/// `_demangle_if_ros_type`: `pkg/msg/Name` for a ROS type, else the DDS name unchanged.
pub(crate) fn demangle_type(dds_type: &str) -> String {
    RosTypeName::from_dds_type_name(dds_type)
        .map(|t| t.as_str().to_owned())
        .unwrap_or_else(|_| dds_type.to_owned())
}

/// `_demangle_service_type_only`: `pkg/srv/Name` from a request or response type.
pub(crate) fn demangle_service_type(dds_type: &str) -> Option<String> {
    RosTypeName::from_dds_service_type_name(dds_type)
        .ok()
        .map(|(t, _)| t.as_str().to_owned())
}

/// Which names a query demangles from DDS topic names.
#[derive(Clone, Copy)]
enum Family {
    /// `rt/` topics, message types.
    Topics,
    /// `rq/` and `rr/` topics, service types.
    Services,
    /// `rq/` topics only (a node's servers read requests).
    ServiceRequests,
    /// `rr/` topics only (a node's clients read replies).
    ServiceReplies,
}

impl Family {
    /// The ROS name of a topic, if it belongs to this family.
    fn name(self, topic: &TopicEntry) -> Option<&str> {
        match (self, &topic.demangled) {
            (Self::Topics, DemangledTopic::Topic(t)) => Some(t.as_str()),
            (
                Self::Services,
                DemangledTopic::ServiceRequest(s) | DemangledTopic::ServiceReply(s),
            )
            | (Self::ServiceRequests, DemangledTopic::ServiceRequest(s))
            | (Self::ServiceReplies, DemangledTopic::ServiceReply(s)) => Some(s.as_str()),
            _ => None,
        }
    }

    /// The demangled type this family reports for a DDS type used on a topic of it.
    fn demangled_type(self, used: &TypeUse) -> Option<&str> {
        match self {
            Self::Topics => Some(&used.message_type),
            Self::Services | Self::ServiceRequests | Self::ServiceReplies => {
                used.service_type.as_deref()
            }
        }
    }
}

/// Adds a demangled name and its type (types that fail to demangle are left out).
fn insert(out: &mut NamesAndTypes, name: &str, ty: Option<&str>) {
    let types = match out.get_mut(name) {
        Some(types) => types,
        None => out.entry(name.to_owned()).or_default(),
    };
    if let Some(ty) = ty {
        if !types.contains(ty) {
            types.insert(ty.to_owned());
        }
    }
}

impl GraphCache {
    /// Who created `e` (rmw_dds_common `__find_name_and_namespace_from_entity_gid`).
    pub(crate) fn creator(&self, e: &EndpointEntry) -> Creator<'_> {
        let Some(participant) = self.participants.get(&e.participant_prefix()) else {
            return Creator::BareDds;
        };
        participant
            .node_listing(e)
            .map_or(Creator::UnknownNode, Creator::Node)
    }

    /// Every node of every participant with its enclave, duplicates kept, sorted by
    /// (namespace, name, enclave) (rmw_dds_common lists them in participant order).
    pub fn node_names(&self) -> Vec<NodeInfo> {
        // The node index is already in (namespace, name) order; only enclaves need sorting.
        let mut nodes = Vec::with_capacity(self.index.node_count);
        for (namespace, names) in &self.index.nodes {
            for (name, places) in names {
                let start = nodes.len();
                nodes.extend(places.iter().map(|(prefix, _)| {
                    NodeInfo {
                        namespace: namespace.clone(),
                        name: name.clone(),
                        enclave: self
                            .participants
                            .get(prefix)
                            .and_then(|p| p.enclave.clone()),
                    }
                }));
                if nodes.len() - start > 1 {
                    nodes[start..].sort_by(|a, b| a.enclave.cmp(&b.enclave));
                }
            }
        }
        nodes
    }

    /// Number of nodes (`get_number_of_nodes`), duplicates counted.
    pub fn node_count(&self) -> usize {
        self.index.node_count
    }

    /// Linear in the number of DDS topics (not endpoints): each topic keeps its types.
    fn names_and_types(&self, family: Family, include_hidden: bool) -> NamesAndTypes {
        let mut out = NamesAndTypes::new();
        for topic in self.index.topics.values() {
            if topic.hidden && !include_hidden {
                continue;
            }
            if let Some(name) = family.name(topic) {
                for used in topic.types.values() {
                    insert(&mut out, name, family.demangled_type(used));
                }
            }
        }
        out
    }

    /// Topic names (from `rt/` topics only) with their demangled types; hidden names
    /// (a `/`-token starting with `_`) only when `include_hidden`.
    pub fn topic_names_and_types(&self, include_hidden: bool) -> NamesAndTypes {
        self.names_and_types(Family::Topics, include_hidden)
    }

    /// Service names (from both `rq/…Request` and `rr/…Reply` topics) with their service
    /// types (`pkg/srv/Name`); hidden names only when `include_hidden`.
    pub fn service_names_and_types(&self, include_hidden: bool) -> NamesAndTypes {
        self.names_and_types(Family::Services, include_hidden)
    }

    /// The first node with this name and namespace (rmw_dds_common `__find_node`: with
    /// duplicate names only the first, in participant order, is used).
    fn find_node(&self, name: &str, namespace: &str) -> Result<&NodeEntitiesInfo, GraphError> {
        self.index
            .nodes
            .get(namespace)
            .and_then(|names| names.get(name))
            .and_then(|places| places.first())
            .and_then(|(prefix, index)| self.participants.get(prefix)?.nodes.get(*index))
            .ok_or_else(|| GraphError::NodeNotFound {
                name: name.to_owned(),
                namespace: namespace.to_owned(),
            })
    }

    fn names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
        kind: EndpointKind,
        family: Family,
    ) -> Result<NamesAndTypes, GraphError> {
        let node = self.find_node(name, namespace)?;
        let gids: &[Gid] = match kind {
            EndpointKind::Reader => &node.reader_gid_seq,
            EndpointKind::Writer => &node.writer_gid_seq,
        };
        let mut out = NamesAndTypes::new();
        for e in gids.iter().filter_map(|gid| self.endpoints.get(gid)) {
            let Some(topic) = self.index.topics.get(e.dds_topic_name.as_str()) else {
                continue;
            };
            if let Some(name) = family.name(topic) {
                let ty = topic
                    .types
                    .get(e.dds_type_name.as_str())
                    .and_then(|used| family.demangled_type(used));
                insert(&mut out, name, ty);
            }
        }
        Ok(out)
    }

    /// Topics a node publishes, with types (its writers on `rt/` topics).
    pub fn publisher_names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
    ) -> Result<NamesAndTypes, GraphError> {
        self.names_and_types_by_node(name, namespace, EndpointKind::Writer, Family::Topics)
    }

    /// Topics a node subscribes to, with types (its readers on `rt/` topics).
    pub fn subscription_names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
    ) -> Result<NamesAndTypes, GraphError> {
        self.names_and_types_by_node(name, namespace, EndpointKind::Reader, Family::Topics)
    }

    /// Services a node serves, with types: its readers on `rq/…Request` topics
    /// (rmw_fastrtps `__rmw_get_service_names_and_types_by_node`).
    pub fn service_names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
    ) -> Result<NamesAndTypes, GraphError> {
        self.names_and_types_by_node(
            name,
            namespace,
            EndpointKind::Reader,
            Family::ServiceRequests,
        )
    }

    /// Services a node is a client of, with types: its readers on `rr/…Reply` topics
    /// (rmw_fastrtps `__rmw_get_client_names_and_types_by_node`).
    pub fn client_names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
    ) -> Result<NamesAndTypes, GraphError> {
        self.names_and_types_by_node(
            name,
            namespace,
            EndpointKind::Reader,
            Family::ServiceReplies,
        )
    }

    /// Number of endpoints of `kind` on a DDS topic.
    pub(crate) fn count(&self, dds_topic: &str, kind: EndpointKind) -> usize {
        self.index
            .topics
            .get(dds_topic)
            .map_or(0, |topic| topic.gids(kind).len())
    }

    /// Publishers of a topic (writers on `rt/<topic>`), nodes known or not.
    pub fn count_publishers(&self, topic: &str) -> usize {
        self.count(&format!("{ROS_TOPIC_PREFIX}{topic}"), EndpointKind::Writer)
    }

    /// Subscriptions of a topic (readers on `rt/<topic>`).
    pub fn count_subscribers(&self, topic: &str) -> usize {
        self.count(&format!("{ROS_TOPIC_PREFIX}{topic}"), EndpointKind::Reader)
    }

    /// Servers of a service: writers on `rr/<service>Reply` (rmw_fastrtps `rmw_count.cpp`).
    pub fn count_services(&self, service: &str) -> usize {
        self.count(
            &format!("{ROS_SERVICE_RESPONSE_PREFIX}{service}{SERVICE_REPLY_SUFFIX}"),
            EndpointKind::Writer,
        )
    }

    /// Clients of a service: readers on `rr/<service>Reply` (rmw_fastrtps `rmw_count.cpp`).
    pub fn count_clients(&self, service: &str) -> usize {
        self.count(
            &format!("{ROS_SERVICE_RESPONSE_PREFIX}{service}{SERVICE_REPLY_SUFFIX}"),
            EndpointKind::Reader,
        )
    }
}
