//! Where a context reports its own participant, nodes and endpoints to its open discovery feed
//! (DDS discovery reports only remote entities): a channel plus a way to wake the feed's waiter.

use std::sync::{mpsc, Arc};

use crate::discovery::DiscoveryEvent;
use crate::{LocalEvents, Wake};

/// The sending side of a feed's [`LocalEvents`].
#[derive(Clone)]
pub struct LocalSink {
    tx: mpsc::Sender<DiscoveryEvent>,
    waker: Option<Arc<dyn Wake>>,
}

impl LocalSink {
    /// A sink and the events it sends, for the feed to be opened with; it wakes nobody until
    /// [`wake_with`](Self::wake_with) says whom.
    pub fn new() -> (Self, LocalEvents) {
        let (tx, rx) = mpsc::channel();
        (Self { tx, waker: None }, LocalEvents(rx))
    }

    /// Wakes `waker` (the open feed's) on every event sent from now on.
    pub fn wake_with(&mut self, waker: Arc<dyn Wake>) {
        self.waker = Some(waker);
    }

    /// Sends `event` to the feed; `false` if the feed is gone.
    pub fn send(&self, event: DiscoveryEvent) -> bool {
        let sent = self.tx.send(event).is_ok();
        if let (true, Some(waker)) = (sent, &self.waker) {
            waker.wake();
        }
        sent
    }
}
