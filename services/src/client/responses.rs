//! The response wait set of a context's blocking clients: whichever caller is waiting takes the
//! responses of every client on the context (leader and followers), so that a response wakes
//! one thread, not every client's. On the rmw_cyclonedds convention every response reaches
//! every client's reader; with a thread per client each response used to wake them all.
//!
//! One caller at a time leads: it waits on the set and hands each response to its call (the
//! call's waker unparks the caller that follows). When its own call ends it passes the lead to
//! the first follower.

use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, Weak};
use std::task::Wake;
use std::thread::Thread;
use std::time::Instant;

use horus_ros_rmw::{Context, RawReader, RawReaderWaker, WaitSet};

use crate::SetupError;

/// A client whose responses the wait set takes.
pub(crate) trait TakeResponses: Send + Sync {
    /// Takes every response that has arrived and hands each to its call.
    fn take_responses(&self);
}

/// One per context (held by the context while a client holds it).
pub(crate) struct ResponseWaitSet {
    set: WaitSet,
    members: Mutex<HashMap<usize, Weak<dyn TakeResponses>>>,
    next_key: AtomicUsize,
    turn: Mutex<Turn>,
}

/// Who waits on the set, and who waits for the lead.
#[derive(Default)]
struct Turn {
    leading: bool,
    followers: VecDeque<Thread>,
}

/// A client's place in its context's wait set (it leaves when dropped).
pub(crate) struct Membership {
    set: Arc<ResponseWaitSet>,
    key: usize,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl ResponseWaitSet {
    /// The wait set of `context`'s blocking clients.
    pub(crate) fn of(context: &Context) -> Result<Arc<Self>, SetupError> {
        context.shared(|| {
            Ok(Self {
                set: WaitSet::new(context)?,
                members: Mutex::new(HashMap::new()),
                next_key: AtomicUsize::new(0),
                turn: Mutex::new(Turn::default()),
            })
        })
    }

    /// Attaches a client's response reader; the client takes part once
    /// [`Membership::register`]ed.
    pub(crate) fn attach(
        self: &Arc<Self>,
        reader: &mut RawReader,
    ) -> Result<Membership, SetupError> {
        let key = self.next_key.fetch_add(1, Ordering::Relaxed);
        self.set.attach(reader, key)?;
        Ok(Membership {
            set: Arc::clone(self),
            key,
        })
    }

    /// A waker for a blocking call made on this thread (see [`wait`](Self::wait)).
    pub(crate) fn call_waker(&self) -> Arc<CallWaker> {
        Arc::new(CallWaker {
            thread: std::thread::current(),
            leading: AtomicBool::new(false),
            set: self.set.waker(),
        })
    }

    /// Waits, at most until `deadline`, until `done` may have become true: while another caller
    /// leads, parked until `waker` is woken or the lead passes to this caller; while leading,
    /// taking every client's responses until `done`. `waker` must be the waker of the call
    /// `done` looks at.
    pub(crate) fn wait(&self, waker: &CallWaker, deadline: Instant, done: impl Fn() -> bool) {
        let mut turn = lock(&self.turn);
        if turn.leading {
            turn.followers.push_back(waker.thread.clone());
            drop(turn);
            // An unpark that came before parking makes it return at once.
            std::thread::park_timeout(deadline.saturating_duration_since(Instant::now()));
            let mut turn = lock(&self.turn);
            let me = waker.thread.id();
            turn.followers.retain(|t| t.id() != me);
            // The lead may have passed to this caller as it left for its own reply: pass it on.
            if !turn.leading {
                if let Some(next) = turn.followers.front() {
                    next.unpark();
                }
            }
            return;
        }
        turn.leading = true;
        drop(turn);
        // Resigns however the lead ends (a panicking client's codec included), passing it on.
        let _lead = Lead { set: self, waker };
        waker.leading.store(true, Ordering::SeqCst);
        let mut ready = Vec::new();
        loop {
            // Checked after `leading` is set: a completion from now on wakes the set.
            if done() {
                break;
            }
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            self.set.wait(deadline - now, &mut ready);
            for key in &ready {
                let member = lock(&self.members).get(key).and_then(Weak::upgrade);
                if let Some(member) = member {
                    member.take_responses();
                }
            }
        }
    }
}

/// The lead of a [`ResponseWaitSet`], held while a caller waits on the set.
struct Lead<'a> {
    set: &'a ResponseWaitSet,
    waker: &'a CallWaker,
}

impl Drop for Lead<'_> {
    fn drop(&mut self) {
        self.waker.leading.store(false, Ordering::SeqCst);
        let mut turn = lock(&self.set.turn);
        turn.leading = false;
        if let Some(next) = turn.followers.front() {
            next.unpark();
        }
    }
}

impl Membership {
    /// Lets the wait set take `client`'s responses.
    pub(crate) fn register(&self, client: Weak<dyn TakeResponses>) {
        lock(&self.set.members).insert(self.key, client);
    }

    /// The wait set.
    pub(crate) fn set(&self) -> &Arc<ResponseWaitSet> {
        &self.set
    }
}

impl Drop for Membership {
    fn drop(&mut self) {
        lock(&self.set.members).remove(&self.key);
    }
}

/// Wakes a blocking call's caller: unparks it while it follows, wakes the set while it leads
/// (unless the caller itself is the one handing over its response).
pub(crate) struct CallWaker {
    thread: Thread,
    leading: AtomicBool,
    set: RawReaderWaker,
}

impl Wake for CallWaker {
    fn wake(self: Arc<Self>) {
        self.wake_by_ref();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        if self.leading.load(Ordering::SeqCst) {
            if std::thread::current().id() != self.thread.id() {
                self.set.wake();
            }
        } else {
            self.thread.unpark();
        }
    }
}
