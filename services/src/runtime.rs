//! Where servers and clients live when the caller names no node: a process-wide default node
//! (in a context configured from the environment), and one live [`Graph`] per context shared by
//! every server and client of that context.

use std::sync::{Arc, Mutex, OnceLock};

use horus_ros_graph::Graph;
use horus_ros_msgs::{Message, Service, TypeHash};
use horus_ros_rmw::{Context, Node, ServiceEndpointRole, WeakNode};

use crate::naming::{default_name_of_type, ServiceTopics};
use crate::{EndpointOptions, SetupError};

/// A node and the graph of its context.
#[derive(Clone)]
pub(crate) struct Runtime {
    pub(crate) node: Node,
    pub(crate) graph: Arc<Graph>,
}

impl Runtime {
    /// `node` if given, else the process's default node; and its context's graph, told the hash
    /// of the service type `S` (which Jazzy peers do not send).
    fn for_service<S: Service>(node: Option<&Node>) -> Result<Self, SetupError> {
        let runtime = Self::for_node(node)?;
        runtime
            .graph
            .set_service_type_hash(S::TYPE_NAME, S::type_hash());
        Ok(runtime)
    }

    /// Where an endpoint of the compiled service `S` in `role` lives, as `options` set it (every
    /// server and client of a compiled type is set up so): [`for_service`](Self::for_service)
    /// on the options' node, and the topics of the options' name (default:
    /// [`default_service_name`](crate::default_service_name)) and QoS.
    pub(crate) fn endpoint<S: Service>(
        options: &EndpointOptions,
        role: ServiceEndpointRole,
    ) -> Result<(Self, ServiceTopics), SetupError> {
        Self::for_service::<S>(options.node.as_ref())?.with_topics(
            options,
            role,
            (S::TYPE_NAME, S::type_hash()),
            (S::Request::dds_type_name(), S::Request::type_hash()),
            (S::Response::dds_type_name(), S::Response::type_hash()),
        )
    }

    /// This runtime, and the topics on its node of an endpoint in `role` of the service type
    /// `service_type` (`pkg/srv/Name`, with its RIHS01 hash) whose request and response have
    /// these DDS type names and hashes, as `options` set it: its name (default: the type's name
    /// in snake case) and QoS.
    /// [`endpoint`](Self::endpoint) for a compiled type; on [`for_node`](Self::for_node) for a
    /// type known at run time.
    pub(crate) fn with_topics(
        self,
        options: &EndpointOptions,
        role: ServiceEndpointRole,
        (service_type, service_hash): (&str, TypeHash),
        request: (String, TypeHash),
        response: (String, TypeHash),
    ) -> Result<(Self, ServiceTopics), SetupError> {
        let name = options
            .name
            .clone()
            .unwrap_or_else(|| default_name_of_type(service_type));
        let topics = ServiceTopics::resolve(
            &self.node,
            &name,
            &options.qos,
            role,
            service_hash,
            request,
            response,
        )?;
        Ok((self, topics))
    }

    /// `node` if given, else the process's default node; and its context's graph.
    pub(crate) fn for_node(node: Option<&Node>) -> Result<Self, SetupError> {
        let node = match node {
            Some(n) => n.clone(),
            None => default_node()?,
        };
        let graph = graph_of(node.context())?;
        Ok(Self { node, graph })
    }
}

/// The process's default node, `horus_<program>_<pid>` in a context from the environment: the
/// one node of every server, client and HORUS topic made without a node of its own, so that a
/// process has one participant. Created on first use and kept while one of them holds it, so
/// the process leaves the graph cleanly when the last of them is dropped.
pub fn default_node() -> Result<Node, SetupError> {
    static DEFAULT: OnceLock<Mutex<WeakNode>> = OnceLock::new();
    let slot = DEFAULT.get_or_init(|| Mutex::new(WeakNode::default()));
    let mut weak = slot.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(node) = weak.upgrade() {
        return Ok(node);
    }
    let context = Context::from_env()?;
    let node = context.create_node(&default_node_name(), "/")?;
    *weak = node.downgrade();
    Ok(node)
}

/// `horus_<program>_<pid>`, with characters a node name cannot hold replaced by `_`.
fn default_node_name() -> String {
    let program = std::env::args()
        .next()
        .and_then(|a| {
            std::path::Path::new(&a)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
        })
        .unwrap_or_default();
    let program: String = program
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    format!("horus_{program}_{}", std::process::id())
}

/// The graph of `context`, shared with everything else in the process that looks at it.
fn graph_of(context: &Context) -> Result<Arc<Graph>, SetupError> {
    Ok(Graph::of(context)?)
}

#[cfg(test)]
mod tests {
    #[test]
    fn default_node_name_is_a_valid_node_name() {
        let name = super::default_node_name();
        assert!(horus_ros_rmw::names::NodeName::new(&name).is_ok(), "{name}");
    }
}
