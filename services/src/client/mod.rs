//! Service clients: [`ServiceClient`] (blocking) and [`AsyncServiceClient`] (non-blocking, with
//! [`PendingResponse`] futures).

mod blocking;
pub(crate) mod core;
mod pending;

pub use blocking::{ServiceClient, ServiceClientBuilder};
pub use pending::{AsyncServiceClient, PendingResponse};
