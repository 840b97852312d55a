//! [`Managed`]: a scheduled node run as a ROS 2 managed (lifecycle) node, opt-in.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::Arc;
use std::time::Duration;

use horus_ros_lifecycle::{CallbackReturn, LifecycleCallbacks, LifecycleNode, State};

use crate::api::error::{Error, Result};
use crate::api::node::{Node, TopicMetadata};

/// How long a transition callback waits for the scheduler to run the node's `init` or
/// `shutdown` (at its next tick) by default.
pub const DEFAULT_TRANSITION_TIMEOUT: Duration = Duration::from_secs(10);

/// A scheduled [`Node`] managed as rclcpp_lifecycle's and rclpy's lifecycle nodes are: its ROS
/// node gets the lifecycle services and `~/transition_event` (horus-ros-lifecycle's
/// [`LifecycleNode`]), and the transitions drive the node:
///
/// | Transition | What runs |
/// |---|---|
/// | `configure` | the node's [`init`](Node::init) (`Err` → FAILURE, a panic → ERROR) |
/// | `activate` / `deactivate` | [`tick`](Node::tick) runs only while `active` |
/// | `cleanup` | the node's [`shutdown`](Node::shutdown) (`Err` → FAILURE: still inactive and configured) |
/// | `shutdown` | the node's `shutdown` if it is configured (→ finalized either way) |
/// | an error (`errorprocessing`) | `shutdown` if configured; back to `unconfigured` |
///
/// `init` and `shutdown` run on the scheduler's thread, at the node's next tick, with the node
/// current (so [`Topic`](crate::Topic)s and [`current`](crate::current) work as usual): the
/// transition's callback waits for that, at most the [transition
/// timeout](Self::transition_timeout) (then ERROR). The node starts `unconfigured`; the
/// scheduler's own `init` only creates the lifecycle interface, and at exit the node's
/// `shutdown` runs if it is still configured.
///
/// Needs the scheduler's ROS side (not [`Scheduler::without_ros`](crate::Scheduler::without_ros)).
///
/// ```no_run
/// use horus::prelude::*;
/// use horus::Managed;
///
/// struct Camera { frames: u64 }
///
/// impl Node for Camera {
///     fn name(&self) -> &str { "camera" }
///     fn init(&mut self) -> Result<()> { Ok(()) } // open the device: on `configure`
///     fn tick(&mut self) { self.frames += 1 }     // only while `active`
///     fn shutdown(&mut self) -> Result<()> { Ok(()) } // on `cleanup` / `shutdown`
/// }
///
/// fn main() -> Result<()> {
///     let mut sched = Scheduler::new();
///     // `ros2 lifecycle set /camera configure`, then `activate`, start its ticks.
///     sched.add(Managed::new(Camera { frames: 0 })).build()?;
///     sched.run()
/// }
/// ```
pub struct Managed<N: Node> {
    inner: N,
    timeout: Duration,
    active: Arc<AtomicBool>,
    configured: bool,
    requests: Option<Receiver<Request>>,
    lifecycle: Option<LifecycleNode>,
}

impl<N: Node> std::fmt::Debug for Managed<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Managed")
            .field("node", &self.inner.name())
            .field("configured", &self.configured)
            .field("active", &self.active.load(Ordering::Acquire))
            .finish_non_exhaustive()
    }
}

impl<N: Node> Managed<N> {
    /// `node`, managed.
    pub fn new(node: N) -> Self {
        Self {
            inner: node,
            timeout: DEFAULT_TRANSITION_TIMEOUT,
            active: Arc::new(AtomicBool::new(false)),
            configured: false,
            requests: None,
            lifecycle: None,
        }
    }

    /// How long a transition waits for the scheduler to run `init` / `shutdown` (default
    /// [`DEFAULT_TRANSITION_TIMEOUT`]); past it the callback returns ERROR.
    pub fn transition_timeout(mut self, timeout: Duration) -> Self {
        self.timeout = timeout;
        self
    }

    /// The managed node.
    pub fn inner(&self) -> &N {
        &self.inner
    }

    /// Runs one request on the scheduler's thread.
    fn handle(&mut self, work: Work) -> CallbackReturn {
        match work {
            Work::Configure => match catch_unwind(AssertUnwindSafe(|| self.inner.init())) {
                Ok(Ok(())) => {
                    self.configured = true;
                    CallbackReturn::Success
                }
                Ok(Err(e)) => {
                    crate::hlog!(error, "configure: init failed: {}", e);
                    CallbackReturn::Failure
                }
                Err(_) => {
                    crate::hlog!(error, "configure: init panicked");
                    CallbackReturn::Error
                }
            },
            Work::Cleanup | Work::Shutdown | Work::Error => {
                self.active.store(false, Ordering::Release);
                if !self.configured {
                    return CallbackReturn::Success;
                }
                let result = catch_unwind(AssertUnwindSafe(|| self.inner.shutdown()));
                match (work, result) {
                    (_, Ok(Ok(()))) => {
                        self.configured = false;
                        CallbackReturn::Success
                    }
                    // A cleanup whose shutdown failed leaves the node configured (and the
                    // state machine inactive: rcl's `transition_failure`).
                    (Work::Cleanup, Ok(Err(e))) => {
                        crate::hlog!(error, "cleanup: shutdown failed: {}", e);
                        CallbackReturn::Failure
                    }
                    // `shutdown` ends in finalized either way.
                    (Work::Shutdown | Work::Configure, Ok(Err(e))) => {
                        crate::hlog!(error, "shutdown failed: {}", e);
                        self.configured = false;
                        CallbackReturn::Failure
                    }
                    // Error processing gives the node up whatever its shutdown says.
                    (Work::Error, Ok(Err(e))) => {
                        crate::hlog!(error, "error processing: shutdown failed: {}", e);
                        self.configured = false;
                        CallbackReturn::Success
                    }
                    (Work::Error, Err(_)) => {
                        crate::hlog!(error, "error processing: shutdown panicked");
                        self.configured = false;
                        CallbackReturn::Failure
                    }
                    (_, Err(_)) => {
                        crate::hlog!(error, "shutdown panicked");
                        self.configured = false;
                        CallbackReturn::Error
                    }
                }
            }
        }
    }
}

/// What a callback asks the scheduler's thread to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Work {
    Configure,
    Cleanup,
    Shutdown,
    Error,
}

struct Request {
    work: Work,
    reply: SyncSender<CallbackReturn>,
}

/// The lifecycle callbacks of a [`Managed`] node: activation flips the tick flag; the rest is
/// handed to the scheduler's thread.
struct Relay {
    requests: SyncSender<Request>,
    active: Arc<AtomicBool>,
    timeout: Duration,
    name: String,
}

impl Relay {
    fn ask(&self, work: Work) -> CallbackReturn {
        let (reply, answer) = mpsc::sync_channel(1);
        // Transitions run one at a time: at most one request is ever pending.
        match self.requests.try_send(Request { work, reply }) {
            Ok(()) => {}
            Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) => {
                return CallbackReturn::Error
            }
        }
        match answer.recv_timeout(self.timeout) {
            Ok(result) => result,
            Err(RecvTimeoutError::Timeout) => {
                tracing::error!(
                    node = %self.name,
                    "{work:?}: the scheduler did not run the node within {:?}",
                    self.timeout
                );
                CallbackReturn::Error
            }
            Err(RecvTimeoutError::Disconnected) => CallbackReturn::Error,
        }
    }
}

impl LifecycleCallbacks for Relay {
    fn on_configure(&mut self, _previous: State) -> CallbackReturn {
        self.ask(Work::Configure)
    }
    fn on_cleanup(&mut self, _previous: State) -> CallbackReturn {
        self.ask(Work::Cleanup)
    }
    fn on_shutdown(&mut self, _previous: State) -> CallbackReturn {
        self.ask(Work::Shutdown)
    }
    fn on_activate(&mut self, _previous: State) -> CallbackReturn {
        self.active.store(true, Ordering::Release);
        CallbackReturn::Success
    }
    fn on_deactivate(&mut self, _previous: State) -> CallbackReturn {
        self.active.store(false, Ordering::Release);
        CallbackReturn::Success
    }
    fn on_error(&mut self, _previous: State) -> CallbackReturn {
        self.active.store(false, Ordering::Release);
        self.ask(Work::Error)
    }
}

impl<N: Node> Node for Managed<N> {
    fn name(&self) -> &str {
        self.inner.name()
    }

    /// Creates the lifecycle interface on the node's ROS node; the node itself stays
    /// unconfigured (its `init` runs on `configure`).
    fn init(&mut self) -> Result<()> {
        let ros = crate::current::ros_node()?;
        let (requests, queue) = mpsc::sync_channel(1);
        let relay = Relay {
            requests,
            active: Arc::clone(&self.active),
            timeout: self.timeout,
            name: ros.fully_qualified_name(),
        };
        let lifecycle = LifecycleNode::builder()
            .node(&ros)
            .callbacks(relay)
            .build()
            .map_err(Error::from)?;
        self.requests = Some(queue);
        self.lifecycle = Some(lifecycle);
        Ok(())
    }

    /// Runs the pending transition work, then the node's tick if it is active.
    fn tick(&mut self) {
        while let Some(request) = self.requests.as_ref().and_then(|q| q.try_recv().ok()) {
            let result = self.handle(request.work);
            let _ = request.reply.send(result);
        }
        if self.active.load(Ordering::Acquire) {
            self.inner.tick();
        }
    }

    /// Removes the lifecycle interface, then shuts the node down if it is configured.
    fn shutdown(&mut self) -> Result<()> {
        // A transition waiting for us is answered ERROR at once (its reply sender goes).
        self.requests = None;
        self.lifecycle = None;
        self.active.store(false, Ordering::Release);
        if std::mem::replace(&mut self.configured, false) {
            self.inner.shutdown()
        } else {
            Ok(())
        }
    }

    fn is_safe_state(&self) -> bool {
        self.inner.is_safe_state()
    }

    fn enter_safe_state(&mut self) {
        self.inner.enter_safe_state();
    }

    fn on_error(&mut self, error: &str) {
        self.inner.on_error(error);
    }

    fn publishers(&self) -> Vec<TopicMetadata> {
        self.inner.publishers()
    }

    fn subscribers(&self) -> Vec<TopicMetadata> {
        self.inner.subscribers()
    }
}
