//! [`TypeRegistry`]: the types a node uses, by RIHS01 hash, for `~/get_type_description` (rcl
//! 9.2 `node_type_cache.c` and `rcl_node_type_description_service_handle_request` in `node.c`).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use horus_ros_msgs::type_description_interfaces::msg::{TypeDescription, TypeSource};
use horus_ros_msgs::type_description_interfaces::srv::{
    GetTypeDescriptionRequest, GetTypeDescriptionResponse,
};
use horus_ros_msgs::{Message, Service, TypeHash};

/// rcl's `failure_reason` when the requested hash does not parse.
pub const FAILURE_PARSE_HASH: &str = "Failed to parse type hash";
/// rcl's `failure_reason` when no type with the requested hash is registered.
pub const FAILURE_NOT_IN_USE: &str = "Type not currently in use by this node";

#[derive(Debug, Clone)]
struct Entry {
    description: TypeDescription,
    sources: Vec<TypeSource>,
    /// How many times the type was registered (rcl counts registrations too).
    registrations: usize,
}

/// The type descriptions a node serves on `~/get_type_description`, keyed by their RIHS01 hash.
/// Cloning gives another handle to the same registry.
#[derive(Debug, Clone, Default)]
pub struct TypeRegistry {
    inner: Arc<Mutex<HashMap<TypeHash, Entry>>>,
}

impl TypeRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    fn lock(&self) -> MutexGuard<'_, HashMap<TypeHash, Entry>> {
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Registers the message type `M` (as rcl does for each publisher and subscription) and
    /// returns its hash.
    pub fn register_type<M: Message>(&self) -> TypeHash {
        self.register_with_hash(M::type_hash(), M::type_description(), Vec::new())
    }

    /// Registers the service type `S` under its service hash (as rcl does for each service
    /// server and client) and returns that hash.
    pub fn register_service<S: Service>(&self) -> TypeHash {
        self.register_with_hash(S::type_hash(), S::type_description(), Vec::new())
    }

    /// Registers a description (and the sources to return with it; may be empty) under its
    /// computed RIHS01 hash, which is returned.
    pub fn register_description(
        &self,
        description: TypeDescription,
        sources: Vec<TypeSource>,
    ) -> TypeHash {
        let hash = description.compute_type_hash();
        self.register_with_hash(hash, description, sources)
    }

    fn register_with_hash(
        &self,
        hash: TypeHash,
        description: TypeDescription,
        sources: Vec<TypeSource>,
    ) -> TypeHash {
        let mut map = self.lock();
        let entry = map.entry(hash).or_insert_with(|| Entry {
            description,
            sources,
            registrations: 0,
        });
        entry.registrations += 1;
        hash
    }

    /// Drops one registration of `hash` (the type leaves the registry with its last one).
    /// Returns false if `hash` is not registered.
    pub fn unregister(&self, hash: &TypeHash) -> bool {
        let mut map = self.lock();
        let Some(entry) = map.get_mut(hash) else {
            return false;
        };
        entry.registrations = entry.registrations.saturating_sub(1);
        if entry.registrations == 0 {
            map.remove(hash);
        }
        true
    }

    /// The description registered under `hash`.
    pub fn get(&self, hash: &TypeHash) -> Option<TypeDescription> {
        self.lock().get(hash).map(|e| e.description.clone())
    }

    /// Whether `hash` is registered.
    pub fn contains(&self, hash: &TypeHash) -> bool {
        self.lock().contains_key(hash)
    }

    /// The hashes registered, in no particular order.
    pub fn hashes(&self) -> Vec<TypeHash> {
        self.lock().keys().copied().collect()
    }

    /// Answers a `GetTypeDescription` request as rcl: looks the type up by `type_hash` only
    /// (`type_name` is not checked); `failure_reason` is [`FAILURE_PARSE_HASH`] or
    /// [`FAILURE_NOT_IN_USE`]; sources are included when `include_type_sources` (they are empty
    /// for types registered from their Rust definition: the `.msg` text is not known).
    pub fn handle_request(
        &self,
        request: &GetTypeDescriptionRequest,
    ) -> GetTypeDescriptionResponse {
        let mut response = GetTypeDescriptionResponse::default();
        let Ok(hash) = TypeHash::parse(&request.type_hash) else {
            tracing::debug!(hash = %request.type_hash, "failed to parse type hash");
            response.failure_reason = FAILURE_PARSE_HASH.to_owned();
            return response;
        };
        let map = self.lock();
        let Some(entry) = map.get(&hash) else {
            response.failure_reason = FAILURE_NOT_IN_USE.to_owned();
            return response;
        };
        response.type_description = entry.description.clone();
        if request.include_type_sources {
            response.type_sources = entry.sources.clone();
        }
        response.successful = true;
        response
    }
}
