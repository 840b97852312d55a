//! [`Node`]: a named member of the ROS graph, announced on `ros_discovery_info`.

use std::sync::Arc;

use crate::context::Context;
use crate::dds::entities::{EndpointSide, NodeKey};
use crate::discovery::DiscoveredEndpoint;
use crate::names::{Namespace, NamespaceError, NodeName, NodeNameError};
use crate::Gid;

/// Why a [`Node`] could not be created.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NodeError {
    /// The node name breaks ROS's rules.
    #[error("invalid node name '{name}': {cause}")]
    InvalidName {
        /// The name given.
        name: String,
        /// Which rule it breaks.
        cause: NodeNameError,
    },
    /// The namespace breaks ROS's rules.
    #[error("invalid node namespace '{namespace}': {cause}")]
    InvalidNamespace {
        /// The namespace given (after rcl's normalisation).
        namespace: String,
        /// Which rule it breaks.
        cause: NamespaceError,
    },
}

/// A ROS node. Creating one announces it on `ros_discovery_info` (the participant republishes its
/// whole `ParticipantEntitiesInfo`, as rmw_dds_common does); dropping the last handle to it (the
/// node and every endpoint created through it) withdraws it the same way.
#[derive(Clone)]
pub struct Node {
    inner: Arc<NodeInner>,
}

pub(crate) struct NodeInner {
    pub(crate) context: Context,
    pub(crate) key: NodeKey,
    pub(crate) name: NodeName,
    pub(crate) namespace: Namespace,
}

impl std::fmt::Debug for Node {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Node")
            .field("fully_qualified_name", &self.fully_qualified_name())
            .finish()
    }
}

impl Context {
    /// Creates a node named `name` in `namespace`.
    ///
    /// As rcl's `rcl_node_init`: an empty namespace means `/`, a relative one is made absolute
    /// (`ns` → `/ns`); then the name and namespace are validated with rmw's rules.
    ///
    /// The context's `--ros-args` apply first, as `rcl_node_init` applies them: `__node:=`
    /// renames the node, `__ns:=` replaces the namespace (rules prefixed with a node name apply
    /// to that node only; the first match wins).
    pub fn create_node(&self, name: &str, namespace: &str) -> Result<Node, NodeError> {
        let arguments = self.arguments();
        let namespace = arguments.remap_namespace(name).unwrap_or(namespace);
        let name = arguments.remap_node_name(name).unwrap_or(name);
        let node_name = NodeName::new(name).map_err(|source| NodeError::InvalidName {
            name: name.to_owned(),
            cause: source,
        })?;
        let normalized = match namespace {
            "" => "/".to_owned(),
            ns if ns.starts_with('/') => ns.to_owned(),
            ns => format!("/{ns}"),
        };
        let node_namespace =
            Namespace::new(&normalized).map_err(|source| NodeError::InvalidNamespace {
                namespace: normalized.clone(),
                cause: source,
            })?;
        let key = self
            .inner()
            .add_node(node_namespace.as_str(), node_name.as_str());
        tracing::debug!(node = %name, namespace = %node_namespace, "created node");
        Ok(Node {
            inner: Arc::new(NodeInner {
                context: self.clone(),
                key,
                name: node_name,
                namespace: node_namespace,
            }),
        })
    }
}

/// A handle to a [`Node`] that does not keep it alive.
#[derive(Clone, Debug, Default)]
pub struct WeakNode(std::sync::Weak<NodeInner>);

impl WeakNode {
    /// The node, if something still keeps it alive.
    pub fn upgrade(&self) -> Option<Node> {
        self.0.upgrade().map(|inner| Node { inner })
    }
}

impl Node {
    /// A handle that does not keep the node alive.
    pub fn downgrade(&self) -> WeakNode {
        WeakNode(Arc::downgrade(&self.inner))
    }

    /// The node's name.
    pub fn name(&self) -> &NodeName {
        &self.inner.name
    }

    /// The node's namespace.
    pub fn namespace(&self) -> &Namespace {
        &self.inner.namespace
    }

    /// `/namespace/name`, as `rcl_node_get_fully_qualified_name`.
    pub fn fully_qualified_name(&self) -> String {
        if self.inner.namespace.is_root() {
            format!("/{}", self.inner.name)
        } else {
            format!("{}/{}", self.inner.namespace, self.inner.name)
        }
    }

    /// The context the node lives in.
    pub fn context(&self) -> &Context {
        &self.inner.context
    }

    pub(crate) fn inner(&self) -> &Arc<NodeInner> {
        &self.inner
    }
}

/// An endpoint's place under its node in `ros_discovery_info`: listed when created, withdrawn
/// when dropped. Endpoint types hold it before their DDS entity, so that (as
/// `rmw_destroy_publisher` does) the GID is withdrawn before the entity is deleted.
pub(crate) struct Registration {
    node: Arc<NodeInner>,
    side: EndpointSide,
    gid: Gid,
}

impl Registration {
    /// Lists `endpoint` under `node`.
    pub(crate) fn new(node: &Node, side: EndpointSide, endpoint: DiscoveredEndpoint) -> Self {
        let node = Arc::clone(node.inner());
        let gid = endpoint.gid;
        node.context.inner().add_endpoint(node.key, side, endpoint);
        Self { node, side, gid }
    }

    /// Records `endpoint` as `node`'s without listing it under any node in
    /// `ros_discovery_info` (see [`Node::create_raw_reader_unlisted`]); dropping it withdraws
    /// it from the context's own feed.
    pub(crate) fn unlisted(node: &Node, side: EndpointSide, endpoint: DiscoveredEndpoint) -> Self {
        let node = Arc::clone(node.inner());
        let gid = endpoint.gid;
        node.context.inner().add_unlisted_endpoint(endpoint);
        Self { node, side, gid }
    }

    /// The endpoint's GID.
    pub(crate) fn gid(&self) -> Gid {
        self.gid
    }
}

impl Drop for Registration {
    fn drop(&mut self) {
        let (key, side, gid) = (self.node.key, self.side, self.gid);
        self.node.context.inner().remove_endpoint(key, side, gid);
    }
}

impl Drop for NodeInner {
    fn drop(&mut self) {
        self.context.inner().remove_node(self.key);
    }
}
