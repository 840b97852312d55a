//! Service clients: [`ServiceClient`] (blocking) and [`AsyncServiceClient`] (non-blocking, with
//! [`PendingResponse`] futures).

mod blocking;
pub(crate) mod codec;
pub(crate) mod core;
mod dynamic;
mod pending;
pub(crate) mod responses;

pub use blocking::{ServiceClient, ServiceClientBuilder};
pub use codec::RawResponse;
pub use dynamic::{
    DynamicCallError, DynamicPart, DynamicServiceClient, DynamicServiceClientBuilder,
    DynamicServiceType,
};
pub use pending::{AsyncServiceClient, PendingResponse};
