//! Errors of graph queries.

/// Why a graph query failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum GraphError {
    /// `no_mangle = true` asked of a service query: DDS services live on mangled `rq/`/`rr/`
    /// topics (rmw `get_service_endpoint_info.h`; rmw_fastrtps returns `RMW_RET_INVALID_ARGUMENT`).
    #[error(
        "'no_mangle' is not supported for services because they rely on internally mangled \
         topic names; query publishers/subscriptions info by topic instead"
    )]
    NoMangleUnsupported,
    /// No known node has this name and namespace (`RMW_RET_NODE_NAME_NON_EXISTENT`).
    #[error("node '{name}' in namespace '{namespace}' is not known")]
    NodeNotFound {
        /// The node name asked for.
        name: String,
        /// The namespace asked for.
        namespace: String,
    },
}
