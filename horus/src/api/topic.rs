//! [`Topic<T>`]: a HORUS topic on a ROS 2 topic.

use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use horus_ros_msgs::Message;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Node as RosNode, Publisher, Subscription};

use crate::api::names::ros_topic_name;
use crate::api::runtime::{current, with_current_ref};

/// Why a [`Topic`] could not be created or used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TopicError {
    /// The HORUS name has no ROS equivalent (see [`names`](crate::names)).
    #[error("topic name '{name}' cannot be mapped to a ROS topic name ('.' becomes '/'; the result must be a valid ROS name): {reason}")]
    Unmappable {
        /// The name given.
        name: String,
        /// The ROS rule it breaks.
        reason: crate::names::TopicNameError,
    },
    /// The topic's node has no ROS side (a scheduler built with `without_ros`).
    #[error(
        "topic '{0}' is used by a node of a scheduler without ROS: nothing is sent or received"
    )]
    NoRos(String),
    /// The DDS endpoint could not be created.
    #[error("topic '{name}': {reason}")]
    Endpoint {
        /// The topic.
        name: String,
        /// What the ROS layer said.
        reason: String,
    },
    /// Publishing failed.
    #[error("topic '{name}': {reason}")]
    Send {
        /// The topic.
        name: String,
        /// What the ROS layer said.
        reason: String,
    },
}

/// A typed topic: `send` publishes, `try_recv` / `recv` receive, on the ROS 2 topic the name
/// maps to (`motor.cmd` → `motor/cmd`, relative to the node's namespace; remapped by
/// `--ros-args -r`), with the message's ROS type name and RIHS01 hash and rclcpp's default QoS
/// (`rclcpp::QoS(10)`: KEEP_LAST 10, RELIABLE, VOLATILE).
///
/// Creating one checks the name only: the DDS writer (at the first `send`) and reader (at the
/// first `try_recv`/`recv`, or [`connect_subscriber`](Self::connect_subscriber)) are created
/// under the ROS node of the HORUS node that first uses them, so a topic constructed before its
/// node is registered is listed under that node in `ros2 node info`. Used outside any
/// scheduled node, it belongs to the process's default node (`horus_<program>_<pid>`, shared
/// with the servers and clients made without a node: `horus_ros_services::default_node`).
pub struct Topic<T: Message> {
    name: String,
    ros_name: String,
    qos: Qos,
    state: Mutex<State<T>>,
    /// Signalled when a waiting receiver puts the subscription back ([`Lent`]).
    returned: Condvar,
}

struct State<T: Message> {
    publisher: Option<Publisher<T>>,
    /// `None` before the reader is created, and while a receiver waits on it (`lent`).
    subscription: Option<Subscription<T>>,
    /// Whether a receiver has taken the subscription out to wait on it without the lock.
    lent: bool,
    /// The fully-qualified topic of the subscription, once created.
    subscription_topic: Option<String>,
    /// Whether a send or subscribe failure was logged.
    reported: bool,
    /// Samples skipped because they could not be taken (malformed).
    skipped: u64,
}

/// What one attempt to take a message gave.
enum Taken<T> {
    Message(T),
    /// Nothing is queued.
    Empty,
    /// [`MAX_SKIPPED_PER_TAKE`] samples in a row could not be taken: more may be queued.
    Busy,
    /// Another thread is waiting on the subscription.
    Lent,
    /// The subscription could not be created.
    Failed(TopicError),
}

/// Most samples skipped (malformed) in one take before the lock is let go.
const MAX_SKIPPED_PER_TAKE: usize = 256;

/// The subscription of a [`Topic`] taken out of its state by the thread waiting on it; put back
/// (and the other receivers woken) when dropped, also on unwind.
struct Lent<'t, T: Message> {
    topic: &'t Topic<T>,
    subscription: Option<Subscription<T>>,
}

impl<T: Message> Drop for Lent<'_, T> {
    fn drop(&mut self) {
        let mut state = self.topic.lock();
        state.subscription = self.subscription.take();
        state.lent = false;
        drop(state);
        self.topic.returned.notify_all();
    }
}

impl<T: Message> std::fmt::Debug for Topic<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Topic")
            .field("name", &self.name)
            .field("ros_name", &self.ros_name)
            .field("type", &T::TYPE_NAME)
            .finish()
    }
}

impl<T: Message> Topic<T> {
    /// A topic named `name` (HORUS or ROS form). Fails if the name cannot be mapped to a ROS
    /// name; never panics.
    pub fn new(name: &str) -> Result<Self, TopicError> {
        Self::with_qos(name, Qos::default_profile())
    }

    /// A topic with a QoS of its own.
    pub fn with_qos(name: &str, qos: Qos) -> Result<Self, TopicError> {
        let ros_name = ros_topic_name(name).map_err(|reason| TopicError::Unmappable {
            name: name.to_owned(),
            reason,
        })?;
        Ok(Self {
            name: name.to_owned(),
            ros_name,
            qos,
            state: Mutex::new(State {
                publisher: None,
                subscription: None,
                lent: false,
                subscription_topic: None,
                reported: false,
                skipped: 0,
            }),
            returned: Condvar::new(),
        })
    }

    /// The name given.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The ROS name it maps to, before expansion (e.g. `motor/cmd`).
    pub fn ros_name(&self) -> &str {
        &self.ros_name
    }

    /// The fully-qualified ROS topic once an endpoint exists (e.g. `/robot1/motor/cmd`).
    pub fn resolved_name(&self) -> Option<String> {
        let state = self.lock();
        state
            .publisher
            .as_ref()
            .map(|p| p.topic_name().to_string())
            .or_else(|| state.subscription_topic.clone())
    }

    /// How many received samples could not be taken (malformed) and were skipped.
    pub fn skipped_samples(&self) -> u64 {
        self.lock().skipped
    }

    fn lock(&self) -> MutexGuard<'_, State<T>> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Publishes `message`. Errors are logged (once per topic) and the message dropped: `tick`
    /// must not fail on a send. Use [`try_send`](Self::try_send) to see them.
    pub fn send(&self, message: T) {
        if let Err(err) = self.try_send(message) {
            let mut state = self.lock();
            if !state.reported {
                state.reported = true;
                drop(state);
                crate::hlog!(error, "{}", err);
            }
        }
    }

    /// Publishes `message`, returning what went wrong.
    pub fn try_send(&self, message: T) -> Result<(), TopicError> {
        let mut state = self.lock();
        if state.publisher.is_none() {
            let node = self.ros_node()?;
            let publisher = node
                .create_publisher::<T>(&self.ros_name, &self.qos)
                .map_err(|e| self.endpoint_error(e))?;
            state.publisher = Some(publisher);
        }
        if let Some(publisher) = &state.publisher {
            publisher.publish(message).map_err(|e| TopicError::Send {
                name: self.name.clone(),
                reason: e.to_string(),
            })?;
        }
        drop(state);
        with_current_ref(|n| {
            if let Some(n) = n {
                n.count_sent()
            }
        });
        Ok(())
    }

    /// Creates the subscriber now (else at the first `try_recv`), so that messages sent from
    /// then on are received.
    pub fn connect_subscriber(&self) -> Result<(), TopicError> {
        let mut state = self.lock();
        self.ensure_subscription(&mut state).map(|_| ())
    }

    /// The subscription, created if there is none yet; `None` while a receiver waits on it.
    fn ensure_subscription<'s>(
        &self,
        state: &'s mut State<T>,
    ) -> Result<Option<&'s mut Subscription<T>>, TopicError> {
        if state.lent {
            return Ok(None);
        }
        if state.subscription.is_none() {
            let node = self.ros_node()?;
            let subscription = node
                .create_subscription::<T>(&self.ros_name, &self.qos)
                .map_err(|e| self.endpoint_error(e))?;
            state.subscription_topic = Some(subscription.topic_name().to_string());
            state.subscription = Some(subscription);
        }
        Ok(state.subscription.as_mut())
    }

    /// Takes the next message, skipping (counting and logging) samples that cannot be taken:
    /// wake-ups are edge-triggered, so good samples behind a bad one must be taken now.
    fn take(&self, state: &mut State<T>) -> Taken<T> {
        let subscription = match self.ensure_subscription(state) {
            Ok(Some(subscription)) => subscription,
            Ok(None) => return Taken::Lent,
            Err(err) => return Taken::Failed(err),
        };
        let mut skipped = 0_u64;
        let mut first_error = None;
        let mut taken = Taken::Busy;
        for _ in 0..MAX_SKIPPED_PER_TAKE {
            match subscription.try_take() {
                Ok(Some(message)) => {
                    taken = Taken::Message(message);
                    break;
                }
                Ok(None) => {
                    taken = Taken::Empty;
                    break;
                }
                Err(err) => {
                    skipped += 1;
                    if first_error.is_none() {
                        first_error = Some(err);
                    }
                }
            }
        }
        if let Some(err) = first_error {
            if state.skipped == 0 {
                crate::hlog!(warn, "topic '{}': skipped a sample: {}", self.name, err);
            } else {
                tracing::debug!(topic = %self.name, "skipped {skipped} sample(s): {err}");
            }
            state.skipped += skipped;
        }
        taken
    }

    /// Counts a received message for the current node.
    fn count_received() {
        with_current_ref(|n| {
            if let Some(n) = n {
                n.count_received()
            }
        });
    }

    /// Logs `err` if it is the topic's first.
    fn report(&self, mut state: MutexGuard<'_, State<T>>, err: &TopicError) {
        let first = !state.reported;
        state.reported = true;
        drop(state);
        if first {
            crate::hlog!(error, "{}", err);
        }
    }

    /// The next message if one has arrived (never blocks). Malformed samples are skipped
    /// (counted in [`skipped_samples`](Self::skipped_samples)); a failure to subscribe is
    /// logged and reads as `None`. While another thread waits in [`recv`](Self::recv) on this
    /// topic, that thread takes what arrives and this returns `None`.
    pub fn try_recv(&self) -> Option<T> {
        let mut state = self.lock();
        match self.take(&mut state) {
            Taken::Message(message) => {
                drop(state);
                Self::count_received();
                Some(message)
            }
            Taken::Failed(err) => {
                self.report(state, &err);
                None
            }
            Taken::Empty | Taken::Busy | Taken::Lent => None,
        }
    }

    /// Waits for the next message, at most `timeout` (woken by its arrival, not polling). Not
    /// for `tick`: use [`try_recv`](Self::try_recv) there. Sending on this topic from another
    /// thread meanwhile does not wait for it.
    pub fn recv_timeout(&self, timeout: Duration) -> Option<T> {
        self.wait_recv(Some(Instant::now() + timeout))
    }

    /// Waits for the next message (blocking; `None` only if the subscriber cannot be created).
    /// Not for `tick`: use [`try_recv`](Self::try_recv) there. Sending on this topic from
    /// another thread meanwhile does not wait for it.
    pub fn recv(&self) -> Option<T> {
        self.wait_recv(None)
    }

    /// Takes the next message, waiting until `end` (`None`: no limit) without holding the
    /// state lock: the subscription is taken out of the state while its reader is waited on,
    /// and the other receivers wait for it to be put back.
    fn wait_recv(&self, end: Option<Instant>) -> Option<T> {
        let mut state = self.lock();
        loop {
            let busy = match self.take(&mut state) {
                Taken::Message(message) => {
                    drop(state);
                    Self::count_received();
                    return Some(message);
                }
                Taken::Failed(err) => {
                    self.report(state, &err);
                    return None;
                }
                Taken::Empty => false,
                Taken::Busy => true,
                Taken::Lent => {
                    // Another receiver waits on the reader: wait until it puts it back.
                    state = match left(end)? {
                        None => self.returned.wait(state).unwrap_or_else(|p| p.into_inner()),
                        Some(left) => {
                            self.returned
                                .wait_timeout(state, left)
                                .unwrap_or_else(|p| p.into_inner())
                                .0
                        }
                    };
                    continue;
                }
            };
            let left = left(end)?;
            let mut lent = Lent {
                topic: self,
                subscription: state.subscription.take(),
            };
            state.lent = true;
            drop(state);
            if let Some(subscription) = &mut lent.subscription {
                if busy {
                    // More samples may be queued, which would not wake the wait again.
                    subscription.waker().wake();
                }
                subscription.wait(left);
            }
            drop(lent);
            state = self.lock();
        }
    }

    /// The topic's messages from now on as a bounded [`futures_core::Stream`] of
    /// `Result<T, Lagged>` (feature `tokio`), for async code. It has a subscription of its own
    /// (under the ROS node [`try_recv`](Self::try_recv) would use), independent of
    /// `try_recv`/`recv`: both get every message. At most `capacity` messages are buffered; when
    /// the consumer falls behind the oldest are dropped and it gets `Err(Lagged(n))` before the
    /// newest (see [`horus_ros_rmw::stream`]). Woken by arriving messages, never polled.
    ///
    /// ```no_run
    /// use futures_util::StreamExt;
    /// use horus::prelude::*;
    ///
    /// #[tokio::main]
    /// async fn main() -> Result<()> {
    ///     let chatter = Topic::<StringMsg>::new("chatter")?;
    ///     let mut messages = chatter.stream(64)?;
    ///     while let Some(message) = messages.next().await {
    ///         match message {
    ///             Ok(m) => println!("I heard: [{}]", m.data),
    ///             Err(lagged) => println!("{lagged}"),
    ///         }
    ///     }
    ///     Ok(())
    /// }
    /// ```
    #[cfg(feature = "tokio")]
    pub fn stream(&self, capacity: usize) -> Result<TopicStream<T>, TopicError> {
        let node = self.ros_node()?;
        let subscription = node
            .create_subscription::<T>(&self.ros_name, &self.qos)
            .map_err(|e| self.endpoint_error(e))?;
        subscription
            .into_stream(capacity)
            .map_err(|e| self.endpoint_error(e))
    }

    fn endpoint_error(&self, e: impl std::fmt::Display) -> TopicError {
        TopicError::Endpoint {
            name: self.name.clone(),
            reason: e.to_string(),
        }
    }

    /// The ROS node to create endpoints under: the current HORUS node's, else the process's.
    fn ros_node(&self) -> Result<RosNode, TopicError> {
        match current() {
            Some(runtime) => match runtime.ros() {
                Some(ros) => Ok(ros.node().clone()),
                None => Err(TopicError::NoRos(self.name.clone())),
            },
            None => process_node().map_err(|reason| TopicError::Endpoint {
                name: self.name.clone(),
                reason,
            }),
        }
    }
}

/// A [`Topic`]'s messages as a bounded stream ([`Topic::stream`]; feature `tokio`).
#[cfg(feature = "tokio")]
pub type TopicStream<T> = horus_ros_rmw::stream::SubscriptionStream<T>;

/// How long a dropped topic waits for its readers to acknowledge what it sent.
pub const DROP_FLUSH_TIMEOUT: Duration = Duration::from_secs(1);

impl<T: Message> Drop for Topic<T> {
    /// Before the writer leaves the graph, its readers get what it sent last (the zero command
    /// a `shutdown` sends just before the process exits), waiting at most
    /// [`DROP_FLUSH_TIMEOUT`] for their acknowledgments.
    fn drop(&mut self) {
        let state = self.state.get_mut().unwrap_or_else(|p| p.into_inner());
        if let Some(publisher) = &state.publisher {
            if !publisher.wait_for_acknowledgments(DROP_FLUSH_TIMEOUT) {
                tracing::debug!(topic = %self.name, "readers did not acknowledge everything");
            }
        }
    }
}

/// The time left until `end`: `Some(None)` for no limit, `None` once it has passed.
fn left(end: Option<Instant>) -> Option<Option<Duration>> {
    match end {
        None => Some(None),
        Some(end) => end.checked_duration_since(Instant::now()).map(Some),
    }
}

/// The node of topics used outside any scheduled node: the process's default node, shared with
/// the servers and clients made without a node (one participant per process).
fn process_node() -> Result<RosNode, String> {
    horus_ros_services::default_node().map_err(|e| e.to_string())
}
