//! [`DdsError`]: the DDS layer refused an operation or failed in it.

/// Why the DDS layer refused an operation or failed in it: the backend's own error where it
/// gives a typed one (held in the variant: a variant that only forwards it is transparent, so
/// an error chain does not print the message twice; `topic:` and `poll:` add context and keep
/// it as their [`source`](std::error::Error::source)), or what our side of the backend found
/// wrong.
///
/// Held as the source of [`ContextError::Participant`](crate::ContextError::Participant),
/// [`EndpointError::Dds`](crate::EndpointError::Dds), [`PublishError`](crate::PublishError),
/// [`TakeError`](crate::TakeError), [`DiscoveryFeedError`](crate::DiscoveryFeedError) and
/// [`WaitSetError::Dds`](crate::WaitSetError::Dds). Its text is the backend's message.
///
/// The `RustDds*` variants come from the rustdds backend, `Cyclone` (cargo feature `cyclone`)
/// from the Cyclone DDS backend; more may be added.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DdsError {
    /// rustdds could not create the topic of a reader or writer.
    #[error("topic: {0}")]
    RustDdsTopic(rustdds::dds::CreateError),
    /// rustdds could not create an entity: the participant, its publisher or subscriber, the
    /// `ros_discovery_info` topic, a reader or a writer.
    #[error(transparent)]
    RustDdsCreate(rustdds::dds::CreateError),
    /// rustdds could not write a sample.
    #[error(transparent)]
    RustDdsWrite(rustdds::dds::WriteError<()>),
    /// rustdds could not take a sample (e.g. one it could not decode, which is consumed).
    #[error(transparent)]
    RustDdsRead(rustdds::dds::ReadError),
    /// The OS poll a rustdds reader waits on could not be set up.
    #[error("poll: {0}")]
    Poll(std::io::Error),
    /// An OS call of the rustdds backend's waiting failed (setting up a wait set's or a
    /// discovery feed's poll, or moving a reader to a wait set's poll).
    #[error(transparent)]
    Io(std::io::Error),
    /// A Cyclone DDS call failed (the function, Cyclone's return code and its text).
    #[cfg(feature = "cyclone")]
    #[error(transparent)]
    Cyclone(horus_ros_rmw_cyclone::Error),
    /// The context's participant was deleted (the process is ending on a signal: see
    /// [`signal_handler`](crate::signal_handler)).
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
    /// A `related_sample_identity` was asked for on the Cyclone backend, which cannot send one
    /// (nothing was sent).
    #[error(
        "the Cyclone backend cannot send related_sample_identity (Cyclone DDS has no API for it)"
    )]
    RelatedSampleIdentityUnsupported,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_as_the_backend_and_keeps_its_error() {
        use std::error::Error as _;
        let create = || rustdds::dds::CreateError::BadParameter {
            reason: "no".to_owned(),
        };
        let e = DdsError::RustDdsTopic(create());
        // The message shows the backend's error, kept typed in the variant (so no `source()`).
        assert_eq!(e.to_string(), format!("topic: {}", create()));
        assert!(matches!(
            e,
            DdsError::RustDdsTopic(rustdds::dds::CreateError::BadParameter { .. })
        ));
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
