//! Waiting without polling for backends whose middleware pushes (calls back on threads of its
//! own, as Zenoh does, or an in-process bus): a [`Signal`] (a flag and a condition variable)
//! for a reader or a feed, raised from those threads; a [`WaitSet`] that collects the keys of
//! the attached readers that got data; a reader's bounded [`SampleQueue`]; a feed's bounded
//! [`FeedQueue`] and the [`PushFeed`] over it. Written once here for every such backend; the DDS
//! backends wait on their middleware's own primitives instead (mio for rustdds, a Cyclone DDS
//! waitset).

use std::collections::{BTreeSet, VecDeque};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::{DiscoveryEvent, FeedBackend, LocalEvents, WaitSetBackend, WaitSetError, Wake};

/// Locks a mutex whose data stays consistent even if a holder panicked.
pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Waits on `cv` until `done` holds, at most `timeout` (`None`: no limit); whether it held.
fn wait_on<'a, T>(
    cv: &Condvar,
    mut guard: MutexGuard<'a, T>,
    timeout: Option<Duration>,
    mut done: impl FnMut(&mut T) -> bool,
) -> (MutexGuard<'a, T>, bool) {
    // A timeout too long to represent waits without limit.
    let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
    loop {
        if done(&mut guard) {
            return (guard, true);
        }
        guard = match deadline {
            None => cv.wait(guard).unwrap_or_else(|p| p.into_inner()),
            Some(d) => match d.checked_duration_since(Instant::now()) {
                Some(left) if !left.is_zero() => {
                    cv.wait_timeout(guard, left)
                        .unwrap_or_else(|p| p.into_inner())
                        .0
                }
                _ => return (guard, false),
            },
        };
    }
}

/// A flag raised by [`Wake::wake`] and lowered by the wait that sees it (edge-triggered).
#[derive(Default)]
pub struct Signal {
    raised: Mutex<bool>,
    cv: Condvar,
}

impl Signal {
    /// Waits until raised (and lowers it), at most `timeout`; whether it was raised.
    pub fn wait(&self, timeout: Option<Duration>) -> bool {
        let guard = lock(&self.raised);
        let (_guard, raised) = wait_on(&self.cv, guard, timeout, std::mem::take);
        raised
    }
}

impl Wake for Signal {
    fn wake(&self) {
        *lock(&self.raised) = true;
        self.cv.notify_all();
    }
}

/// What a wait set shares with its readers: the keys ready, and whether its waker was woken.
#[derive(Default)]
pub struct SetState {
    ready: Mutex<(BTreeSet<usize>, bool)>,
    cv: Condvar,
}

impl SetState {
    /// Marks `key` ready (`None`: the set's own waker), waking the waiter.
    pub fn mark(&self, key: Option<usize>) {
        let mut ready = lock(&self.ready);
        match key {
            Some(key) => {
                ready.0.insert(key);
            }
            None => ready.1 = true,
        }
        self.cv.notify_all();
    }
}

impl Wake for SetState {
    fn wake(&self) {
        self.mark(None);
    }
}

/// Waits on many readers' data at once.
#[derive(Default)]
pub struct WaitSet {
    /// What the readers attached to it mark.
    pub shared: Arc<SetState>,
}

impl WaitSetBackend for WaitSet {
    fn wait(&self, timeout: Option<Duration>, ready: &mut Vec<usize>) -> bool {
        let guard = lock(&self.shared.ready);
        let (mut guard, signalled) =
            wait_on(&self.shared.cv, guard, timeout, |r| !r.0.is_empty() || r.1);
        ready.extend(std::mem::take(&mut guard.0));
        guard.1 = false;
        signalled
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::clone(&self.shared) as Arc<dyn Wake>
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// A reader's bounded queue of samples (the oldest goes when it is full) and whom a new sample
/// wakes: the reader's own [`Signal`], or the wait set it is attached to.
pub struct SampleQueue<T> {
    state: Mutex<QueueState<T>>,
    signal: Arc<Signal>,
    depth: usize,
}

struct QueueState<T> {
    samples: VecDeque<T>,
    attached: Option<(Arc<SetState>, usize)>,
}

impl<T> SampleQueue<T> {
    /// A queue keeping at most `depth` samples (at least one).
    pub fn new(depth: usize) -> Self {
        Self {
            state: Mutex::new(QueueState {
                samples: VecDeque::new(),
                attached: None,
            }),
            signal: Arc::default(),
            depth: depth.max(1),
        }
    }

    /// Queues `sample` (the oldest goes when full) and wakes the reader or its wait set.
    pub fn deliver(&self, sample: T) {
        let mut state = lock(&self.state);
        if state.samples.len() >= self.depth {
            state.samples.pop_front();
        }
        state.samples.push_back(sample);
        match &state.attached {
            Some((set, key)) => set.mark(Some(*key)),
            None => self.signal.wake(),
        }
    }

    /// The oldest sample queued, taken.
    pub fn pop(&self) -> Option<T> {
        lock(&self.state).samples.pop_front()
    }

    /// Waits until a sample came or the reader was woken, at most `timeout` (see
    /// [`Signal::wait`]).
    pub fn wait(&self, timeout: Option<Duration>) -> bool {
        self.signal.wait(timeout)
    }

    /// What ends the reader's wait.
    pub fn waker(&self) -> Arc<dyn Wake> {
        Arc::clone(&self.signal) as Arc<dyn Wake>
    }

    /// Reports this queue's samples to `set` (a [`WaitSet`]) under `key` from now on, marking
    /// it at once if samples are queued; a set of another kind is
    /// [`WaitSetError::OtherBackend`].
    pub fn attach_to(&self, set: &dyn WaitSetBackend, key: usize) -> Result<(), WaitSetError> {
        let set = set
            .as_any()
            .downcast_ref::<WaitSet>()
            .ok_or(WaitSetError::OtherBackend)?;
        let mut state = lock(&self.state);
        if !state.samples.is_empty() {
            set.shared.mark(Some(key));
        }
        state.attached = Some((Arc::clone(&set.shared), key));
        Ok(())
    }
}

/// The discovery events a backend's threads queue for a context's open feed, bounded (beyond
/// `capacity`, the oldest go, with a warning).
pub struct FeedQueue {
    events: Mutex<VecDeque<DiscoveryEvent>>,
    signal: Arc<Signal>,
    capacity: usize,
}

impl FeedQueue {
    /// A queue starting with `events` (what the feed reports first), keeping at most `capacity`.
    pub fn new(events: VecDeque<DiscoveryEvent>, capacity: usize) -> Self {
        Self {
            events: Mutex::new(events),
            signal: Arc::default(),
            capacity: capacity.max(1),
        }
    }

    /// Queues `event` and wakes the feed.
    pub fn push(&self, event: DiscoveryEvent) {
        let mut events = lock(&self.events);
        if events.len() >= self.capacity {
            tracing::warn!("a discovery feed is full: its oldest event dropped");
            events.pop_front();
        }
        events.push_back(event);
        drop(events);
        self.signal.wake();
    }
}

/// A context's open feed on a backend that pushes: the context's own events first, then the
/// queue's. `closing` is dropped with it (what tells the backend the feed is gone).
pub struct PushFeed {
    queue: Arc<FeedQueue>,
    local: LocalEvents,
    _closing: Box<dyn Send>,
}

impl PushFeed {
    /// The feed of `queue` and the context's `local` events; `closing` goes when it goes.
    pub fn new(queue: Arc<FeedQueue>, local: LocalEvents, closing: impl Send + 'static) -> Self {
        Self {
            queue,
            local,
            _closing: Box::new(closing),
        }
    }
}

impl FeedBackend for PushFeed {
    fn try_next(&mut self) -> Option<DiscoveryEvent> {
        self.local
            .try_next()
            .or_else(|| lock(&self.queue.events).pop_front())
    }

    fn wait(&mut self, limit: Option<Duration>) -> std::io::Result<bool> {
        Ok(self.queue.signal.wait(limit))
    }

    fn waker(&self) -> Arc<dyn Wake> {
        Arc::clone(&self.queue.signal) as Arc<dyn Wake>
    }
}
