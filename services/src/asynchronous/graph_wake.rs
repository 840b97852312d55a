//! Waking a task when the graph changes: a [`GraphWatcher`] holding the task's waker.

use std::sync::{Arc, Mutex};
use std::task::Waker;

use horus_ros_graph::{Graph, GraphView, GraphWatcher};

/// Wakes the waker it holds at the next change of the graph it watches. Registered with the
/// graph (which keeps it weakly) for as long as the future holding it lives.
pub(crate) struct GraphWake {
    waker: Mutex<Option<Waker>>,
}

impl GraphWake {
    /// A watcher of `graph`, waking nothing yet.
    pub(crate) fn watch(graph: &Graph) -> Arc<Self> {
        let wake = Arc::new(Self {
            waker: Mutex::new(None),
        });
        let weak: std::sync::Weak<dyn GraphWatcher> = Arc::downgrade(&wake) as _;
        graph.watch(weak);
        wake
    }

    /// Wakes `waker` at the next change (replacing the one held).
    pub(crate) fn set(&self, waker: &Waker) {
        let mut slot = self.waker.lock().unwrap_or_else(|p| p.into_inner());
        match &mut *slot {
            Some(w) if w.will_wake(waker) => {}
            slot => *slot = Some(waker.clone()),
        }
    }
}

impl GraphWatcher for GraphWake {
    fn graph_changed(&self, _graph: &GraphView<'_>) {
        let waker = self.waker.lock().unwrap_or_else(|p| p.into_inner()).take();
        if let Some(waker) = waker {
            waker.wake();
        }
    }
}
