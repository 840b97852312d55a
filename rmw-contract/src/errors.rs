//! What a backend's participant answers when a feed or a wait set cannot be made.

use crate::dds_error::DdsError;

/// Why a `DiscoveryFeed` could not be opened.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DiscoveryFeedError {
    /// The context already has a feed (rustdds keeps one discovery event queue per participant).
    #[error("this context already has a discovery feed")]
    AlreadyOpen,
    /// The wake-up machinery (an OS poll instance) could not be set up.
    #[error("could not set up waiting for discovery events: {cause}")]
    Poll {
        /// What the OS (rustdds backend) or Cyclone DDS said.
        cause: DdsError,
    },
    /// A reader (`ros_discovery_info` or a built-in topic) could not be created.
    #[error("could not create a discovery reader: {cause}")]
    Reader {
        /// What the DDS layer said.
        cause: DdsError,
    },
}

/// Why a wait set could not be made, or a reader not attached.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WaitSetError {
    /// The DDS layer refused.
    #[error("wait set: {0}")]
    Dds(DdsError),
    /// The reader belongs to another backend than the set.
    #[error("wait set: the reader is of another DDS backend than the set")]
    OtherBackend,
    /// `usize::MAX` is the set's own.
    #[error("wait set: key {0} is reserved")]
    ReservedKey(usize),
}
