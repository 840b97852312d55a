//! Waiting: waitsets ([`Waiter`]) blocking in the caller's thread, woken by data, statuses and
//! [`GuardCondition`]s.

use std::sync::Arc;
use std::time::Duration;

use cyclors as c;

use super::*;

/// A guard condition: set from any thread to wake a [`Waiter`] it is attached to. Cheap to
/// clone (all clones are the same condition).
#[derive(Debug, Clone)]
pub struct GuardCondition {
    pub(super) handle: Arc<Handle>,
}

impl GuardCondition {
    /// A new, untriggered guard condition (not tied to a participant).
    pub fn new() -> Result<Self> {
        // SAFETY: DDS_CYCLONEDDS_HANDLE is the library's root pseudo handle (initialising the
        // library if needed); the condition is deleted by Handle::drop.
        let h = check("dds_create_guardcondition", unsafe {
            c::dds_create_guardcondition(c::DDS_CYCLONEDDS_HANDLE)
        })?;
        Ok(Self {
            handle: Handle::new(h, None),
        })
    }

    /// Triggers the condition (wakes waiters until reset).
    pub fn trigger(&self) -> Result<()> {
        // SAFETY: live guard condition.
        check("dds_set_guardcondition", unsafe {
            c::dds_set_guardcondition(self.handle.id, true)
        })?;
        Ok(())
    }

    /// Reads and resets the condition; returns whether it was triggered.
    pub fn take(&self) -> Result<bool> {
        let mut t = false;
        // SAFETY: live guard condition; valid out-pointer.
        check("dds_take_guardcondition", unsafe {
            c::dds_take_guardcondition(self.handle.id, &mut t)
        })?;
        Ok(t)
    }
}

/// Something attached to a [`Waiter`].
#[derive(Debug)]
pub(super) enum Attached {
    /// Kept alive by the waiter.
    Owned(Arc<Handle>),
    /// Watched without being kept alive.
    Observed(std::sync::Weak<Handle>),
}

/// A Cyclone waitset blocking in the calling thread: read conditions (reader has data),
/// status conditions (e.g. matched) and guard conditions, each identified by a caller-chosen
/// token. Things may be attached and detached from other threads while one thread waits
/// (Cyclone's waitset locks its own list).
#[derive(Debug)]
pub struct Waiter {
    pub(super) handle: Arc<Handle>,
    // What is attached, by token: kept alive while attached (read conditions are owned here),
    // except entities watched for their status, which may be deleted while attached.
    pub(super) attached: std::sync::Mutex<Vec<(usize, Attached)>>,
}

impl Waiter {
    /// An empty waiter (not tied to a participant, so anything can be attached).
    pub fn new() -> Result<Self> {
        // SAFETY: DDS_CYCLONEDDS_HANDLE is the library's root pseudo handle; a waitset there
        // may have entities of any participant attached. Deleted by Handle::drop.
        let h = check("dds_create_waitset", unsafe {
            c::dds_create_waitset(c::DDS_CYCLONEDDS_HANDLE)
        })?;
        Ok(Self {
            handle: Handle::new(h, None),
            attached: std::sync::Mutex::new(Vec::new()),
        })
    }

    pub(super) fn attached(&self) -> std::sync::MutexGuard<'_, Vec<(usize, Attached)>> {
        self.attached.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub(super) fn attach(&self, h: Arc<Handle>, token: usize) -> Result<()> {
        // SAFETY: both handles live (we keep `h` alive while attached); the token is an opaque
        // integer Cyclone hands back from dds_waitset_wait.
        check("dds_waitset_attach", unsafe {
            c::dds_waitset_attach(self.handle.id, h.id, token as c::dds_attach_t)
        })?;
        self.attached().push((token, Attached::Owned(h)));
        Ok(())
    }

    pub(super) fn read_condition(&self, reader: &Arc<Handle>, token: usize) -> Result<()> {
        // SAFETY: live reader; the condition is a child of it, owned (and deleted) by the Handle
        // we create, which keeps the reader alive.
        let h = check("dds_create_readcondition", unsafe {
            c::dds_create_readcondition(reader.id, c::DDS_ANY_STATE)
        })?;
        self.attach(Handle::new(h, Some(reader)), token)
    }

    /// Wakes while `reader` holds any sample (level-triggered: take them to reset).
    pub fn attach_reader(&self, reader: &Reader, token: usize) -> Result<()> {
        self.read_condition(&reader.handle, token)
    }

    /// Wakes while `reader` holds any built-in topic sample.
    pub fn attach_builtin(&self, reader: &BuiltinReader, token: usize) -> Result<()> {
        self.read_condition(&reader.handle, token)
    }

    /// Wakes while one of `mask`'s statuses of `entity` is set (reset it with
    /// [`Entity::take_status`] or the status getter). Replaces the entity's status mask.
    ///
    /// The waiter does not keep `entity` alive: deleting it detaches it (Cyclone removes a
    /// deleted entity from every waitset it is attached to).
    pub fn attach_status(&self, entity: &Entity, mask: StatusMask, token: usize) -> Result<()> {
        entity.set_status_mask(mask)?;
        // SAFETY: both handles live (we hold `entity` during the call); the token is opaque.
        check("dds_waitset_attach", unsafe {
            c::dds_waitset_attach(self.handle.id, entity.0.id, token as c::dds_attach_t)
        })?;
        self.attached()
            .push((token, Attached::Observed(Arc::downgrade(&entity.0))));
        Ok(())
    }

    /// Wakes while `guard` is triggered (reset it with [`GuardCondition::take`]).
    pub fn attach_guard(&self, guard: &GuardCondition, token: usize) -> Result<()> {
        self.attach(guard.handle.clone(), token)
    }

    /// Detaches everything attached with `token`.
    pub fn detach(&self, token: usize) -> Result<()> {
        let mut result = Ok(());
        let ws = self.handle.id;
        self.attached().retain(|(t, a)| {
            if *t != token {
                return true;
            }
            let h = match a {
                Attached::Owned(h) => Some(h.clone()),
                // Already deleted: Cyclone detached it then.
                Attached::Observed(w) => w.upgrade(),
            };
            if let Some(h) = h {
                // SAFETY: both handles live (held during the call) and attached.
                if let Err(e) = check("dds_waitset_detach", unsafe {
                    c::dds_waitset_detach(ws, h.id)
                }) {
                    result = Err(e);
                }
            }
            false
        });
        result
    }

    /// Blocks the calling thread until something attached triggers or `timeout` passes;
    /// returns the tokens of what triggered (empty on timeout).
    pub fn wait(&self, timeout: Duration) -> Result<Vec<usize>> {
        self.wait_for(Some(timeout))
    }

    /// [`wait`](Self::wait), with no time limit when `timeout` is `None`.
    pub fn wait_for(&self, timeout: Option<Duration>) -> Result<Vec<usize>> {
        let mut xs: Vec<c::dds_attach_t> = vec![0; self.attached().len().max(1)];
        // SAFETY: live waitset; `xs` has room for `xs.len()` tokens; Cyclone writes at most
        // that many and returns the number triggered (possibly more than fit).
        let n = check("dds_waitset_wait", unsafe {
            c::dds_waitset_wait(
                self.handle.id,
                xs.as_mut_ptr(),
                xs.len(),
                duration_to_dds(timeout),
            )
        })? as usize;
        Ok(xs[..n.min(xs.len())].iter().map(|t| *t as usize).collect())
    }
}
