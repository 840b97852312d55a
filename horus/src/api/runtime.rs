//! The node the current thread is running: set by the scheduler around every `init`, `tick`,
//! `shutdown` (and the other lifecycle calls), so that a [`Topic`](crate::Topic) counts its
//! messages for that node and joins the ROS graph under it, and `hlog!` logs under its name.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::api::node::AtomicHealth;
use crate::api::ros::RosNode;

/// What the scheduler shares with a node's topics and logs.
pub(crate) struct NodeRuntime {
    /// The HORUS node name.
    pub(crate) name: String,
    pub(crate) sent: AtomicU64,
    pub(crate) received: AtomicU64,
    pub(crate) health: AtomicHealth,
    /// The node's ROS side, once its `init` has begun on a scheduler that joins the graph.
    pub(crate) ros: Mutex<Option<Arc<RosNode>>>,
}

impl NodeRuntime {
    pub(crate) fn new(name: String) -> Arc<Self> {
        Arc::new(Self {
            name,
            sent: AtomicU64::new(0),
            received: AtomicU64::new(0),
            health: AtomicHealth::default(),
            ros: Mutex::new(None),
        })
    }

    /// The node's ROS side, if it has one.
    pub(crate) fn ros(&self) -> Option<Arc<RosNode>> {
        self.ros.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }

    pub(crate) fn count_sent(&self) {
        self.sent.fetch_add(1, Ordering::Relaxed);
    }

    pub(crate) fn count_received(&self) {
        self.received.fetch_add(1, Ordering::Relaxed);
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<NodeRuntime>>> = const { RefCell::new(None) };
}

/// Runs `f` with `runtime` as the current node of this thread (restoring the previous one).
pub(crate) fn with_current<R>(runtime: &Arc<NodeRuntime>, f: impl FnOnce() -> R) -> R {
    struct Restore(Option<Arc<NodeRuntime>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let previous = self.0.take();
            CURRENT.with(|c| *c.borrow_mut() = previous);
        }
    }
    let previous = CURRENT.with(|c| c.borrow_mut().replace(Arc::clone(runtime)));
    let _restore = Restore(previous);
    f()
}

/// Swaps `slot` with this thread's current node: the tick path lends a spare strong handle of
/// the node's runtime (held by the scheduler for this only) before the tick and takes it back
/// after, so a tick costs no reference-count traffic. Two calls restore the thread's state.
pub(crate) fn swap_current(slot: &mut Option<Arc<NodeRuntime>>) {
    CURRENT.with(|c| std::mem::swap(&mut *c.borrow_mut(), slot));
}

/// The node running on this thread, if any.
pub(crate) fn current() -> Option<Arc<NodeRuntime>> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Calls `f` with the node running on this thread, without cloning its handle.
pub(crate) fn with_current_ref<R>(f: impl FnOnce(Option<&NodeRuntime>) -> R) -> R {
    CURRENT.with(|c| f(c.borrow().as_deref()))
}
