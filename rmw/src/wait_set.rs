//! [`WaitSet`]: one thread waiting on the data of many readers at once (`rmw_wait`).
//!
//! A reader attached to a set reports its data there for the rest of its life (its own
//! [`wait`](RawReader::wait) then returns only when its waker is woken); dropping the reader
//! detaches it. The set's [`waker`](WaitSet::waker) ends the current or next wait from any
//! thread.

use std::time::Duration;

use crate::contract::WaitSetBackend;
pub use crate::contract::WaitSetError;
use crate::{Context, RawReader, RawReaderWaker};

/// The key no reader may take (backends may use it for the set's own waker).
const RESERVED: usize = usize::MAX;

/// Waits on many readers' data at once; one thread waits at a time (a second caller of
/// [`wait`](Self::wait) blocks until the first returns).
pub struct WaitSet {
    set: Box<dyn WaitSetBackend>,
    waker: RawReaderWaker,
}

impl std::fmt::Debug for WaitSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("WaitSet")
    }
}

impl WaitSet {
    /// An empty set for readers of `context`'s backend.
    pub fn new(context: &Context) -> Result<Self, WaitSetError> {
        let set = context.inner().participant.create_wait_set()?;
        let waker = RawReaderWaker(set.waker());
        Ok(Self { set, waker })
    }

    /// Attaches `reader` under `key` (reported by [`wait`](Self::wait) when it may have data),
    /// for the rest of the reader's life. May be called while another thread waits.
    pub fn attach(&self, reader: &mut RawReader, key: usize) -> Result<(), WaitSetError> {
        if key == RESERVED {
            return Err(WaitSetError::ReservedKey(key));
        }
        reader.reader.attach_to(self.set.as_ref(), key)
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
        self.set.wait(timeout.into(), ready)
    }
}
