//! Graph cache.
