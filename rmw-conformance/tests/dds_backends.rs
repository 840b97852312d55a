//! The conformance suite on the two DDS backends: contexts of this process, each a DDS
//! participant. The two backends speak to each other, so each runs in domains of its own (the
//! suite's domain plus an offset). Run inside `scripts/isolated`.

use horus_ros_rmw::{Backend, Context};
use horus_ros_rmw_conformance::conformance_tests;

/// A context on `backend` in `domain`.
fn context_on(backend: Backend, domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .backend(backend)
        .build()
        .expect("context")
}

/// The rustdds backend, in domains 31 to 41.
mod rustdds {
    use super::*;

    fn context(domain: u32) -> Context {
        context_on(Backend::RustDds, domain + 30)
    }

    conformance_tests!(context);
}

/// The Cyclone DDS backend, in domains 51 to 61.
mod cyclone {
    use super::*;

    fn context(domain: u32) -> Context {
        context_on(Backend::Cyclone, domain + 50)
    }

    conformance_tests!(context);
}
