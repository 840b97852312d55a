//! Same-host shared memory, as rmw_zenoh_cpp 0.2.x (Jazzy) does it (`src/detail/shm_context.hpp`,
//! `shm_context.cpp`, `zenoh_config.cpp`, `rmw_context_impl_s.cpp`, `rmw_publisher_data.cpp`):
//!
//! - the one switch is the session configuration's `transport/shared_memory/enabled` (off in
//!   rmw_zenoh's default configuration and in ours: [`config`](super::config)); turn it on with
//!   `ZENOH_CONFIG_OVERRIDE='transport/shared_memory/enabled=true'` or in the file
//!   `ZENOH_SESSION_CONFIG_URI` names. When it is on, the context makes one POSIX
//!   shared-memory provider (rmw_zenoh's `ShmContext`: `zenoh::PosixShmProvider` over a
//!   `MemoryLayout(alloc_size, 1-byte alignment)`);
//! - its size is `ZENOH_SHM_ALLOC_SIZE` bytes, 48 MiB when unset, not a number or not positive
//!   (`zenoh_shm_alloc_size()`; 16 MiB before rmw_zenoh 0.2.8, ros2/rmw_zenoh#832);
//! - a published message of `ZENOH_SHM_MESSAGE_SIZE_THRESHOLD` bytes or more (512 when unset,
//!   not a number or not positive: `zenoh_shm_message_size_threshold()`; rmw_zenoh compares
//!   `max_data_length >= msgsize_threshold`) goes out in a buffer of that provider, allocated
//!   with garbage collection and defragmentation (`alloc_gc_defrag`), instead of a heap one;
//!   when the allocation fails it goes out on the heap (rmw_zenoh logs "Failed to allocate a
//!   SHM buffer, fallback to non-SHM" at debug level; we warn once per context).
//!
//! Only publishers use the provider, as in rmw_zenoh (`PublisherData::publish` and
//! `publish_serialized_message` take the `ShmContext`; `ClientData::send_request` and
//! `ServiceData::send_response` do not). Zenoh's own transport optimization
//! (`transport/shared_memory/transport_optimization`, on by default in zenoh 1.8: a 16 MiB pool,
//! messages of 3072 bytes or more) still carries large requests and replies through shared
//! memory on links where both ends enabled it.
//!
//! Zenoh negotiates shared memory per link: a buffer crosses as a reference only where both
//! ends of the link enabled it and share the host's `/dev/shm`; elsewhere zenoh sends its bytes.
//! Two sessions of one host reach each other on a direct peer link (gossip autoconnect, as
//! rmw_zenoh configures it), so the router need not enable it for them; a message that crosses
//! the router (`horus-ros router`, which reads the same key from `ZENOH_CONFIG_OVERRIDE` or
//! `ZENOH_ROUTER_CONFIG_URI`) stays in shared memory only if the router enabled it too
//! (`tests/zenoh_shm.rs` checks both).
//!
//! What a subscription received keeps its publisher's buffer until it is taken (as rmw_zenoh's
//! queue keeps its `zenoh::Bytes`), and so does a TRANSIENT_LOCAL publisher's cache: size the
//! pool for the messages in flight and held.

use std::sync::atomic::{AtomicBool, Ordering};

use zenoh::shm::{
    Defragment, GarbageCollect, PosixShmProviderBackend, ShmProvider, ShmProviderBuilder, ZShmMut,
};
use zenoh::Wait;

/// The configuration key that turns shared memory on (rmw_zenoh's `Z_CONFIG_SHARED_MEMORY_KEY`).
pub const SHM_ENABLED_KEY: &str = "transport/shared_memory/enabled";
/// rmw_zenoh's variable: the size in bytes of a context's shared-memory pool.
pub const SHM_ALLOC_SIZE_ENV: &str = "ZENOH_SHM_ALLOC_SIZE";
/// rmw_zenoh's variable: the size in bytes from which a message goes through shared memory.
pub const SHM_MESSAGE_SIZE_THRESHOLD_ENV: &str = "ZENOH_SHM_MESSAGE_SIZE_THRESHOLD";
/// rmw_zenoh's default pool size: 48 MiB (since 0.2.8, ros2/rmw_zenoh#832).
pub const DEFAULT_SHM_ALLOC_SIZE: usize = 48 * 1024 * 1024;
/// rmw_zenoh's default threshold: 512 bytes.
pub const DEFAULT_SHM_MESSAGE_SIZE_THRESHOLD: usize = 512;

/// Why a context's shared-memory provider could not be made.
#[derive(Debug, thiserror::Error)]
#[error("zenoh: could not create the shared-memory provider of {size} bytes: {cause}")]
pub struct ShmProviderError {
    /// The pool size asked for.
    pub size: usize,
    /// What zenoh said.
    pub cause: String,
}

/// Whether the session configuration turns shared memory on (the key reads `true`).
pub fn enabled(config: &zenoh::Config) -> bool {
    config
        .get_json(SHM_ENABLED_KEY)
        .is_ok_and(|v| v.trim() == "true")
}

/// A size variable as rmw_zenoh reads it: its value when it is a positive integer, else
/// `default`.
fn size_from(value: Option<String>, default: usize) -> usize {
    value
        .and_then(|v| v.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or(default)
}

/// A context's shared-memory provider and threshold (rmw_zenoh's `ShmContext`).
pub(crate) struct ShmContext {
    provider: ShmProvider<PosixShmProviderBackend>,
    threshold: usize,
    /// Whether a failed allocation was logged (once per context).
    warned: AtomicBool,
}

impl std::fmt::Debug for ShmContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShmContext")
            .field("threshold", &self.threshold)
            .finish_non_exhaustive()
    }
}

impl ShmContext {
    /// The provider of a session whose configuration is `config`, sized and with a threshold
    /// from the environment through `get`; `None` when the configuration leaves shared memory
    /// off.
    pub(crate) fn for_session(
        config: &zenoh::Config,
        get: impl Fn(&str) -> Option<String>,
    ) -> Result<Option<Self>, ShmProviderError> {
        if !enabled(config) {
            return Ok(None);
        }
        let size = size_from(get(SHM_ALLOC_SIZE_ENV), DEFAULT_SHM_ALLOC_SIZE);
        let threshold = size_from(
            get(SHM_MESSAGE_SIZE_THRESHOLD_ENV),
            DEFAULT_SHM_MESSAGE_SIZE_THRESHOLD,
        );
        // shm_context.cpp: a POSIX provider over a layout of `alloc_size` bytes aligned on one
        // byte (the default alignment of a size-only layout).
        let provider = ShmProviderBuilder::default_backend(size)
            .wait()
            .map_err(|e| ShmProviderError {
                size,
                cause: e.to_string(),
            })?;
        // rmw_zenoh 0.2.9 logs both sizes when it makes its ShmContext (ros2/rmw_zenoh#837).
        tracing::info!(
            alloc_size = size,
            threshold,
            "zenoh: shared memory enabled: a pool of {size} bytes for messages of {threshold} \
             bytes or more"
        );
        Ok(Some(Self {
            provider,
            threshold,
            warned: AtomicBool::new(false),
        }))
    }

    /// A shared-memory buffer of `len` bytes for a message of that size, if it reaches the
    /// threshold and the pool has room (a failure is logged once; the caller then uses the
    /// heap, as rmw_zenoh falls back to non-SHM).
    pub(crate) fn buffer(&self, len: usize) -> Option<ZShmMut> {
        if len < self.threshold {
            return None;
        }
        match self
            .provider
            .alloc(len)
            .with_policy::<GarbageCollect<Defragment>>()
            .wait()
        {
            Ok(buffer) => Some(buffer),
            Err(e) => {
                if !self.warned.swap(true, Ordering::Relaxed) {
                    tracing::warn!(
                        len,
                        "zenoh: could not allocate a shared-memory buffer ({e:?}), the message \
                         goes on the heap (set {SHM_ALLOC_SIZE_ENV} for a larger pool; further \
                         failures of this context are not logged)"
                    );
                }
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_read_as_rmw_zenoh_reads_them() {
        assert_eq!(size_from(None, 7), 7);
        assert_eq!(size_from(Some("1024".to_owned()), 7), 1024);
        assert_eq!(size_from(Some("0".to_owned()), 7), 7);
        assert_eq!(size_from(Some("-5".to_owned()), 7), 7);
        assert_eq!(size_from(Some("lots".to_owned()), 7), 7);
    }

    #[test]
    fn off_by_default_on_by_the_one_key() {
        let none = |_: &str| None;
        let session = super::super::config::config(super::super::config::ConfigKind::Session, none)
            .expect("session");
        assert!(!enabled(&session));
        assert!(ShmContext::for_session(&session, none)
            .expect("no provider")
            .is_none());
        let on = |k: &str| {
            (k == super::super::config::CONFIG_OVERRIDE_ENV)
                .then(|| format!("{SHM_ENABLED_KEY}=true"))
        };
        let session = super::super::config::config(super::super::config::ConfigKind::Session, on)
            .expect("session");
        assert!(enabled(&session));
        let small = |k: &str| match k {
            SHM_ALLOC_SIZE_ENV => Some("65536".to_owned()),
            SHM_MESSAGE_SIZE_THRESHOLD_ENV => Some("1000".to_owned()),
            _ => None,
        };
        let shm = ShmContext::for_session(&session, small)
            .expect("a provider")
            .expect("enabled");
        assert!(shm.buffer(999).is_none(), "under the threshold");
        assert_eq!(shm.buffer(1000).map(|b| b.len()), Some(1000));
        assert!(shm.buffer(1 << 20).is_none(), "larger than the pool");
    }
}
