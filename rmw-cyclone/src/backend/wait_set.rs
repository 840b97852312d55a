//! The Cyclone wait set: one [`cyc::Signal`] raised by the attached readers' data (each reader
//! holds its notice, so dropping the reader detaches it, as rustdds' poll forgets a closed
//! channel) and by the set's waker. The rustdds side is `rustdds/wait_set.rs`.

use std::sync::Arc;
use std::time::Duration;

use crate as cyc;

use horus_ros_rmw_contract::{WaitSetBackend, Wake};

/// Wakes whoever waits on a signal.
pub(crate) struct SignalWake(pub(crate) Arc<cyc::Signal>);

impl Wake for SignalWake {
    fn wake(&self) {
        self.0.wake();
    }
}

/// Waits on many readers' data at once.
pub(crate) struct WaitSet {
    pub(crate) signal: Arc<cyc::Signal>,
}

impl WaitSet {
    /// An empty set.
    pub(crate) fn new() -> Self {
        Self {
            signal: cyc::Signal::new(),
        }
    }
}

impl WaitSetBackend for WaitSet {
    fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool {
        self.signal.wait(timeout, ready)
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::new(SignalWake(Arc::clone(&self.signal)))
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
