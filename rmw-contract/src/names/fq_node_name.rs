//! Fully-qualified node names (`/ns/name`).
//!
//! Joined as rcl `src/rcl/node.c` builds `fq_name` (jazzy): `"%s%s"` when the
//! namespace ends with `/` (i.e. is `/`), else `"%s/%s"`; ros2cli prints the
//! same string.

use super::namespace::{Namespace, NamespaceError};
use super::node_name::{NodeName, NodeNameError};

/// Why a string is not a valid fully-qualified node name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FqNodeNameError {
    /// The string does not start with `/` (index 0).
    #[error("fully-qualified node name must be absolute, it must lead with a '/'")]
    NotAbsolute,
    /// The part before the last `/` is not a valid namespace.
    #[error("invalid namespace in fully-qualified node name: {0}")]
    Namespace(NamespaceError),
    /// The part after the last `/` is not a valid node name; its index is
    /// relative to that part.
    #[error("invalid node name in fully-qualified node name: {0}")]
    NodeName(NodeNameError),
}

/// A node's namespace and name together, shown as `/ns/name`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FullyQualifiedNodeName {
    full: String,
    namespace: Namespace,
    name: NodeName,
}

impl FullyQualifiedNodeName {
    /// Parses `/ns/name`: the namespace is everything before the last `/`
    /// (`/` when that is empty), the node name everything after it.
    pub fn new(fq_name: &str) -> Result<Self, FqNodeNameError> {
        if !fq_name.starts_with('/') {
            return Err(FqNodeNameError::NotAbsolute);
        }
        let split = fq_name.rfind('/').unwrap_or(0);
        let (ns, name) = (&fq_name[..split], &fq_name[split + 1..]);
        let namespace = if ns.is_empty() {
            Namespace::root()
        } else if ns == "/" {
            // "//name" would not join back to itself.
            return Err(FqNodeNameError::Namespace(
                NamespaceError::RepeatedForwardSlash { index: 1 },
            ));
        } else {
            Namespace::new(ns).map_err(FqNodeNameError::Namespace)?
        };
        let name = NodeName::new(name).map_err(FqNodeNameError::NodeName)?;
        Ok(Self::from_parts(&namespace, &name))
    }

    /// Joins a namespace and a node name as rcl does.
    pub fn from_parts(namespace: &Namespace, name: &NodeName) -> Self {
        let full = if namespace.is_root() {
            format!("/{name}")
        } else {
            format!("{namespace}/{name}")
        };
        Self {
            full,
            namespace: namespace.clone(),
            name: name.clone(),
        }
    }

    /// The joined `/ns/name` string.
    pub fn as_str(&self) -> &str {
        &self.full
    }

    /// The namespace part.
    pub fn namespace(&self) -> &Namespace {
        &self.namespace
    }

    /// The node-name part.
    pub fn name(&self) -> &NodeName {
        &self.name
    }
}

impl core::fmt::Display for FullyQualifiedNodeName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.full)
    }
}

impl core::str::FromStr for FullyQualifiedNodeName {
    type Err = FqNodeNameError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::new(s)
    }
}

impl TryFrom<&str> for FullyQualifiedNodeName {
    type Error = FqNodeNameError;

    fn try_from(s: &str) -> Result<Self, Self::Error> {
        Self::new(s)
    }
}

impl AsRef<str> for FullyQualifiedNodeName {
    fn as_ref(&self) -> &str {
        &self.full
    }
}
