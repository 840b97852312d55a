//! [`DdsError`]: the DDS layer refused an operation or failed in it.

/// A backend's own error, kept as it gave it (any backend: see `crate::contract`).
pub type BackendCause = Box<dyn std::error::Error + Send + Sync>;

/// Boxes a backend's error as a [`BackendCause`].
pub fn boxed(e: impl std::error::Error + Send + Sync + 'static) -> BackendCause {
    Box::new(e)
}

/// Why the backend refused an operation or failed in it: the backend's own error, shown in the
/// message (the variant says which operation), or what our side of the backend found wrong.
///
/// Held as the cause of `ContextError::Participant`,
/// `EndpointError::Dds`, `PublishError`,
/// `TakeError`, [`DiscoveryFeedError`](crate::DiscoveryFeedError) and
/// [`WaitSetError::Dds`](crate::WaitSetError::Dds). No backend's types show in it: what a
/// backend reports is kept as a [`BackendCause`], which callers may downcast.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DdsError {
    /// The topic of a reader or writer could not be created.
    #[error("topic: {0}")]
    Topic(BackendCause),
    /// An entity could not be created: the participant, its publisher or subscriber, the
    /// `ros_discovery_info` topic, a reader or a writer.
    #[error("{0}")]
    Create(BackendCause),
    /// A sample could not be written.
    #[error("{0}")]
    Write(BackendCause),
    /// A sample could not be taken (e.g. one the backend could not decode, which is consumed).
    #[error("{0}")]
    Read(BackendCause),
    /// Any other call of the backend failed (e.g. a Cyclone DDS call: the function, its return
    /// code and its text).
    #[error("{0}")]
    Backend(BackendCause),
    /// The OS poll a reader waits on could not be set up.
    #[error("poll: {0}")]
    Poll(std::io::Error),
    /// An OS call of the backend's waiting failed (setting up a wait set's or a discovery
    /// feed's poll, or moving a reader to a wait set's poll).
    #[error("{0}")]
    Io(std::io::Error),
    /// The context's participant was deleted (the process is ending on a signal: see
    /// `signal_handler`).
    #[error("the participant was deleted")]
    ParticipantDeleted,
    /// A sample taken is shorter than its 4-byte CDR encapsulation header (it is consumed).
    #[error("sample of {len} bytes is shorter than its encapsulation header")]
    ShortSample {
        /// The sample's length in bytes.
        len: usize,
    },
    /// A sample taken is in an encoding other than plain CDR, e.g. PL_CDR or XCDR2 (it is
    /// consumed).
    #[error("unsupported CDR encapsulation {id:02x?}")]
    UnsupportedEncapsulation {
        /// The sample's encapsulation identifier.
        id: [u8; 2],
    },
    /// A `related_sample_identity` was asked of a backend that cannot send one (nothing was
    /// sent; see [`Capabilities::carries_sample_identity`](crate::Capabilities)).
    #[error("this backend cannot send related_sample_identity")]
    RelatedSampleIdentityUnsupported,
    /// A loan was written by a writer of another backend than the one that lent it (nothing
    /// was sent).
    #[error("the loan was lent by another backend's writer")]
    ForeignLoan,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_as_the_backend_and_keeps_its_error() {
        use std::error::Error as _;
        let create = || std::io::Error::new(std::io::ErrorKind::InvalidInput, "no");
        let e = DdsError::Topic(boxed(create()));
        // The message shows the backend's error, kept in the variant (so no `source()`).
        assert_eq!(e.to_string(), format!("topic: {}", create()));
        let DdsError::Topic(cause) = &e else {
            panic!("{e:?}")
        };
        assert!(cause.downcast_ref::<std::io::Error>().is_some());
        assert!(e.source().is_none());
        let io = || std::io::Error::from(std::io::ErrorKind::Other);
        assert_eq!(DdsError::Poll(io()).to_string(), format!("poll: {}", io()));
        assert_eq!(DdsError::Io(io()).to_string(), io().to_string());
        assert_eq!(
            DdsError::UnsupportedEncapsulation { id: [0, 0x0a] }.to_string(),
            "unsupported CDR encapsulation [00, 0a]"
        );
        assert!(DdsError::ShortSample { len: 3 }.source().is_none());
    }
}
