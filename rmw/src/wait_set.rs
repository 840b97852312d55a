//! [`WaitSet`]: one thread waiting on the data of many readers at once (`rmw_wait`).
//!
//! A reader attached to a set reports its data there for the rest of its life (its own
//! [`wait`](RawReader::wait) then returns only when its waker is woken); dropping the reader
//! detaches it. The set's [`waker`](WaitSet::waker) ends the current or next wait from any
//! thread.

#[cfg(feature = "cyclone")]
use std::sync::Arc;
use std::time::Duration;

use crate::dds_error::DdsError;
use crate::raw::{ReaderImpl, WakerImpl};
use crate::{Backend, Context, RawReader, RawReaderWaker};

/// The token of the set's own waker (no reader key may take it).
const WAKE: usize = usize::MAX;

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

/// Waits on many readers' data at once; one thread waits at a time (a second caller of
/// [`wait`](Self::wait) blocks until the first returns).
pub struct WaitSet {
    imp: Imp,
    waker: RawReaderWaker,
}

enum Imp {
    RustDds(crate::dds::waiter::Waiter),
    /// Raised by the attached readers' data (each reader holds its notice, so dropping the
    /// reader detaches it, as rustdds' poll forgets a closed channel) and by the waker.
    #[cfg(feature = "cyclone")]
    Cyclone(Arc<horus_ros_rmw_cyclone::Signal>),
}

impl std::fmt::Debug for WaitSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("WaitSet")
    }
}

impl WaitSet {
    /// An empty set for readers of `context`'s backend.
    pub fn new(context: &Context) -> Result<Self, WaitSetError> {
        match context.backend() {
            Backend::RustDds => {
                let (waiter, waker) = crate::dds::waiter::Waiter::new(WAKE)
                    .map_err(|e| WaitSetError::Dds(DdsError::Io(e)))?;
                Ok(Self {
                    imp: Imp::RustDds(waiter),
                    waker: RawReaderWaker(WakerImpl::RustDds(waker)),
                })
            }
            #[cfg(feature = "cyclone")]
            Backend::Cyclone => {
                let signal = horus_ros_rmw_cyclone::Signal::new();
                Ok(Self {
                    imp: Imp::Cyclone(Arc::clone(&signal)),
                    waker: RawReaderWaker(WakerImpl::Cyclone(signal)),
                })
            }
            #[cfg(not(feature = "cyclone"))]
            Backend::Cyclone => Err(WaitSetError::OtherBackend),
        }
    }

    /// Attaches `reader` under `key` (reported by [`wait`](Self::wait) when it may have data),
    /// for the rest of the reader's life. May be called while another thread waits.
    pub fn attach(&self, reader: &mut RawReader, key: usize) -> Result<(), WaitSetError> {
        if key == WAKE {
            return Err(WaitSetError::ReservedKey(key));
        }
        match (&self.imp, &mut reader.reader) {
            (Imp::RustDds(waiter), ReaderImpl::RustDds(dds)) => {
                dds.attach_to(waiter, key).map_err(WaitSetError::Dds)
            }
            #[cfg(feature = "cyclone")]
            (Imp::Cyclone(signal), ReaderImpl::Cyclone(cyclone)) => {
                let notice = cyclone.attach_to(signal, key);
                reader.attachments.push(notice);
                Ok(())
            }
            #[cfg(feature = "cyclone")]
            _ => Err(WaitSetError::OtherBackend),
        }
    }

    /// Wakes the current or next [`wait`](Self::wait), from any thread.
    pub fn waker(&self) -> RawReaderWaker {
        self.waker.clone()
    }

    /// Waits until an attached reader may have data or the waker was woken, at most `timeout`
    /// (`None`: no limit). Puts the keys of the readers that may have data in `ready` (cleared
    /// first); returns whether anything was signalled. Take from each until `None`: a reader is
    /// reported once per arrival (or burst of arrivals) after its previous report.
    pub fn wait(&self, timeout: impl Into<Option<Duration>>, ready: &mut Vec<usize>) -> bool {
        ready.clear();
        let timeout = timeout.into();
        match &self.imp {
            Imp::RustDds(waiter) => waiter.wait(timeout, ready),
            #[cfg(feature = "cyclone")]
            Imp::Cyclone(signal) => signal.wait(timeout, ready),
        }
    }
}
