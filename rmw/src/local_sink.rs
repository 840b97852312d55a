//! Where a context reports its own participant, nodes and endpoints to its open discovery feed
//! (DDS discovery reports only remote entities): a channel plus a way to wake the feed's waiter.

use std::sync::{mpsc, Arc};

use crate::discovery::DiscoveryEvent;

/// Wakes a discovery feed blocked in its backend's wait.
pub(crate) trait Wake: Send + Sync {
    /// Wakes the feed; a failure only delays the event until the feed's next wake-up.
    fn wake(&self);
}

/// The sending side of a feed's local event channel.
#[derive(Clone)]
pub(crate) struct LocalSink {
    tx: mpsc::Sender<DiscoveryEvent>,
    waker: Arc<dyn Wake>,
}

impl LocalSink {
    /// A sink waking the feed through `waker`, and the receiving side for the feed.
    pub(crate) fn new(waker: Arc<dyn Wake>) -> (Self, mpsc::Receiver<DiscoveryEvent>) {
        let (tx, rx) = mpsc::channel();
        (Self { tx, waker }, rx)
    }

    /// Sends `event` to the feed; `false` if the feed is gone.
    pub(crate) fn send(&self, event: DiscoveryEvent) -> bool {
        let sent = self.tx.send(event).is_ok();
        if sent {
            self.waker.wake();
        }
        sent
    }
}
