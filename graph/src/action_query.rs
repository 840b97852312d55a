//! Action queries: actions are not entities of the graph but names derived from their feedback
//! topics, as rcl_action's `graph.c` derives them (`rcl_action_get_names_and_types`,
//! `rcl_action_get_server_names_and_types_by_node` from the node's publishers,
//! `rcl_action_get_client_names_and_types_by_node` from its subscriptions, each through
//! `_filter_action_names`); and ros2action's `get_action_clients_and_servers` (ros2cli 0.32,
//! `ros2action/api/__init__.py`) over every node.

use crate::cache::GraphCache;
use crate::error::GraphError;
use crate::query::{NamesAndTypes, NodeInfo};

/// What marks an action's feedback topic (rcl_action `names.c`: `<action>/_action/feedback`).
pub const ACTION_FEEDBACK_SUFFIX: &str = "/_action/feedback";
/// What marks an action's feedback message type (`pkg/action/Name_FeedbackMessage`).
pub const ACTION_FEEDBACK_TYPE_SUFFIX: &str = "_FeedbackMessage";

/// One node's use of an action: the node and the action types it uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionUser {
    /// The node (its enclave as [`GraphCache::node_names`] reports it).
    pub node: NodeInfo,
    /// The action's types as the node uses them (`pkg/action/Name`), sorted.
    pub types: Vec<String>,
}

/// The nodes that serve and that are clients of one action (ros2action's
/// `get_action_clients_and_servers`), each in the order of [`GraphCache::node_names`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ActionEndpoints {
    /// Nodes with an action client of the action.
    pub clients: Vec<ActionUser>,
    /// Nodes with an action server of the action.
    pub servers: Vec<ActionUser>,
}

/// rcl_action `_filter_action_names`: of topic names and types, those whose name contains
/// `/_action/feedback`, the name cut by that suffix's length and each type containing
/// `_FeedbackMessage` cut by that suffix's length.
pub fn filter_action_names(topics: &NamesAndTypes) -> NamesAndTypes {
    fn cut(s: &str, len: usize) -> String {
        let end = s.len().saturating_sub(len);
        s.get(..end).unwrap_or(s).to_owned()
    }
    let mut out = NamesAndTypes::new();
    for (name, types) in topics {
        if !name.contains(ACTION_FEEDBACK_SUFFIX) {
            continue;
        }
        let entry = out
            .entry(cut(name, ACTION_FEEDBACK_SUFFIX.len()))
            .or_default();
        for ty in types {
            if ty.contains(ACTION_FEEDBACK_TYPE_SUFFIX) {
                entry.insert(cut(ty, ACTION_FEEDBACK_TYPE_SUFFIX.len()));
            } else {
                entry.insert(ty.clone());
            }
        }
    }
    out
}

impl GraphCache {
    /// Every action of the graph with its types (`rcl_action_get_names_and_types`: from all
    /// topics, hidden ones included — an action's topics are always hidden).
    pub fn action_names_and_types(&self) -> NamesAndTypes {
        filter_action_names(&self.topic_names_and_types(true))
    }

    /// The actions a node serves (it publishes their feedback), with types.
    pub fn action_server_names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
    ) -> Result<NamesAndTypes, GraphError> {
        Ok(filter_action_names(
            &self.publisher_names_and_types_by_node(name, namespace)?,
        ))
    }

    /// The actions a node is a client of (it subscribes to their feedback), with types.
    pub fn action_client_names_and_types_by_node(
        &self,
        name: &str,
        namespace: &str,
    ) -> Result<NamesAndTypes, GraphError> {
        Ok(filter_action_names(
            &self.subscription_names_and_types_by_node(name, namespace)?,
        ))
    }

    /// The clients and servers of the action `action` (a full name), node by node in the
    /// order of [`node_names`](Self::node_names).
    pub fn action_clients_and_servers(&self, action: &str) -> ActionEndpoints {
        let mut out = ActionEndpoints::default();
        for node in self.node_names() {
            let types_of = |found: Result<NamesAndTypes, GraphError>| {
                found
                    .ok()
                    .and_then(|mut nt| nt.remove(action))
                    .map(|types| types.into_iter().collect::<Vec<_>>())
            };
            if let Some(types) =
                types_of(self.action_client_names_and_types_by_node(&node.name, &node.namespace))
            {
                out.clients.push(ActionUser {
                    node: node.clone(),
                    types,
                });
            }
            if let Some(types) =
                types_of(self.action_server_names_and_types_by_node(&node.name, &node.namespace))
            {
                out.servers.push(ActionUser { node, types });
            }
        }
        out
    }
}
