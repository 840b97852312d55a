//! The only module of the crate with `unsafe` code: every call into Cyclone DDS (through the
//! `cyclors` bindings) is here, each `unsafe` block with a `SAFETY:` comment saying why it holds.
//!
//! Ownership rules, enforced by the types rather than by callers:
//! - Every Cyclone entity (domain, participant, topic, reader, writer, read condition,
//!   waitset, guard condition) is owned by a [`Handle`] that deletes it on drop. A handle keeps
//!   its parent's handle alive (an `Arc`), so a parent is never deleted before its children in
//!   Rust, and Cyclone's recursive delete never leaves us holding a stale handle.
//! - QoS objects ([`QosBox`]), sample references ([`SerdataRef`]) and loans ([`Loan`]) are RAII
//!   values freed/unref'd/returned on drop, on every path, including errors and panics.
//! - One listener only: a reader's DATA_AVAILABLE listener raises the
//!   [`Signal`](crate::Signal)s the reader is attached to ([`Reader::notify`]): a lock, a push
//!   and a notify on Cyclone's thread, never user code. Other waiting is done with waitsets in
//!   the caller's thread ([`Waiter`]); other threads wake it with a [`GuardCondition`].
//!
//! One concept per file: [`handle`] (entities), [`domain`], [`qos`], [`participant`] (and
//! topics), [`endpoints`] (writers and readers), [`builtin`] (built-in topic readers) and
//! [`wait`] (waitsets and guard conditions); the signals themselves are safe code
//! (`crate::signal`).
#![allow(unsafe_code)]

use std::ffi::{CStr, CString};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use cyclors as c;

mod builtin;
mod domain;
mod endpoints;
mod handle;
mod participant;
mod qos;
mod sertype;
mod wait;

pub use builtin::*;
pub use domain::*;
pub use endpoints::*;
pub use handle::*;
pub use participant::*;
use qos::*;
pub use sertype::HEAD_LEN;
pub use wait::*;

// ---------------------------------------------------------------------------------------------
// Errors

/// A failed Cyclone DDS call: the operation, Cyclone's return code and its text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    /// The Cyclone function (or binding operation) that failed.
    pub op: &'static str,
    /// Cyclone's `dds_return_t` (negative), or -1 for failures without a code.
    pub code: i32,
    /// Cyclone's description of `code` (`dds_strretcode`), or ours.
    pub message: String,
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} failed: {} ({})", self.op, self.message, self.code)
    }
}

impl std::error::Error for Error {}

/// Result of this crate's operations.
pub type Result<T> = std::result::Result<T, Error>;

pub(super) fn error(op: &'static str, message: &str) -> Error {
    Error {
        op,
        code: -1,
        message: message.to_owned(),
    }
}

/// Turns a `dds_return_t` (or an entity handle, positive on success) into a `Result`.
pub(super) fn check(op: &'static str, rc: i32) -> Result<i32> {
    if rc >= 0 {
        return Ok(rc);
    }
    // SAFETY: dds_strretcode accepts any value and returns a pointer to a static, NUL-terminated
    // string that is never freed.
    let message = unsafe { CStr::from_ptr(c::dds_strretcode(rc)) }
        .to_string_lossy()
        .into_owned();
    Err(Error {
        op,
        code: rc,
        message,
    })
}

pub(super) fn cstring(op: &'static str, s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| error(op, "string contains a NUL byte"))
}

pub(super) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

pub(super) fn duration_to_dds(d: Option<Duration>) -> c::dds_duration_t {
    d.map_or(i64::MAX, |d| {
        i64::try_from(d.as_nanos()).unwrap_or(i64::MAX)
    })
}

pub(super) fn duration_from_dds(ns: c::dds_duration_t) -> Option<Duration> {
    (ns != i64::MAX && ns >= 0).then(|| Duration::from_nanos(ns as u64))
}
