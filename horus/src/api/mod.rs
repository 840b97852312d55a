//! The implementation; the crate root re-exports its public surface.

pub(crate) mod clock;
pub mod current;
pub(crate) mod error;
pub(crate) mod log;
pub(crate) mod macros;
pub(crate) mod managed;
pub(crate) mod metrics;
pub mod names;
pub(crate) mod node;
pub(crate) mod policy;
pub(crate) mod ros;
pub(crate) mod runtime;
pub(crate) mod scheduler;
pub(crate) mod topic;
pub(crate) mod units;
