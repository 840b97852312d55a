//! QoS: [`QosBox`], the owned `dds_qos_t` an [`EndpointQos`] becomes.

use std::ffi::{c_void, CStr};
use std::os::raw::c_char;
use std::time::Duration;

use cyclors as c;

use super::*;
use crate::qos::{Durability, EndpointQos, History, Liveliness, Reliability};

/// An owned `dds_qos_t`, deleted on drop.
pub(super) struct QosBox(pub(super) *mut c::dds_qos_t);

impl QosBox {
    pub(super) fn new() -> Result<Self> {
        // SAFETY: plain allocation; the result is checked for NULL and freed in Drop.
        let q = unsafe { c::dds_create_qos() };
        if q.is_null() {
            return Err(error("dds_create_qos", "out of memory"));
        }
        Ok(Self(q))
    }

    pub(super) fn user_data(&mut self, data: &[u8]) {
        // SAFETY: `self.0` is a live QoS we own; Cyclone copies `len` bytes from `data`.
        unsafe { c::dds_qset_userdata(self.0, data.as_ptr().cast(), data.len()) };
    }

    pub(super) fn endpoint(&mut self, q: &EndpointQos) {
        let reliability = match q.reliability {
            Reliability::BestEffort => c::dds_reliability_kind_DDS_RELIABILITY_BEST_EFFORT,
            Reliability::Reliable => c::dds_reliability_kind_DDS_RELIABILITY_RELIABLE,
        };
        let durability = match q.durability {
            Durability::Volatile => c::dds_durability_kind_DDS_DURABILITY_VOLATILE,
            Durability::TransientLocal => c::dds_durability_kind_DDS_DURABILITY_TRANSIENT_LOCAL,
        };
        let (history, depth) = match q.history {
            History::KeepLast(n) => (
                c::dds_history_kind_DDS_HISTORY_KEEP_LAST,
                i32::try_from(n).unwrap_or(i32::MAX),
            ),
            History::KeepAll => (c::dds_history_kind_DDS_HISTORY_KEEP_ALL, -1),
        };
        let liveliness = match q.liveliness {
            Liveliness::Automatic => c::dds_liveliness_kind_DDS_LIVELINESS_AUTOMATIC,
            Liveliness::ManualByTopic => c::dds_liveliness_kind_DDS_LIVELINESS_MANUAL_BY_TOPIC,
        };
        // SAFETY: setters on a live QoS object we own; all arguments are plain values.
        unsafe {
            c::dds_qset_reliability(
                self.0,
                reliability,
                duration_to_dds(Some(q.max_blocking_time)),
            );
            c::dds_qset_durability(self.0, durability);
            c::dds_qset_history(self.0, history, depth);
            if q.durability == Durability::TransientLocal {
                // As rmw_cyclonedds `create_readwrite_qos` (jazzy): Cyclone keeps what it
                // resends to late joiners by the durability service QoS (default: the last
                // sample), so it gets the history's kind and depth.
                c::dds_qset_durability_service(
                    self.0,
                    0,
                    history,
                    depth,
                    c::DDS_LENGTH_UNLIMITED,
                    c::DDS_LENGTH_UNLIMITED,
                    c::DDS_LENGTH_UNLIMITED,
                );
            }
            c::dds_qset_deadline(self.0, duration_to_dds(q.deadline));
            c::dds_qset_lifespan(self.0, duration_to_dds(q.lifespan));
            c::dds_qset_liveliness(self.0, liveliness, duration_to_dds(q.liveliness_lease));
            // As rmw_cyclonedds `create_readwrite_qos` (jazzy): no autodispose of unregistered
            // instances (set on readers too, where Cyclone ignores it).
            c::dds_qset_writer_data_lifecycle(self.0, false);
        }
    }
}

impl Drop for QosBox {
    fn drop(&mut self) {
        // SAFETY: we own this QoS object and delete it exactly once.
        unsafe { c::dds_delete_qos(self.0) }
    }
}

/// USER_DATA of a QoS owned by Cyclone (borrowed), copied out; empty if absent.
///
/// # Safety
/// `q` must be NULL or point to a valid `dds_qos_t` for the duration of the call.
pub(super) unsafe fn qos_user_data(q: *const c::dds_qos_t) -> Vec<u8> {
    if q.is_null() {
        return Vec::new();
    }
    let mut p: *mut c_void = std::ptr::null_mut();
    let mut n: usize = 0;
    // SAFETY: `q` is valid (caller's contract); dds_qget_userdata stores a freshly allocated
    // copy of `n` bytes (plus a NUL) in `p`, which we copy out and free with dds_free.
    unsafe {
        if !c::dds_qget_userdata(q, &mut p, &mut n) || p.is_null() {
            return Vec::new();
        }
        let v = std::slice::from_raw_parts(p as *const u8, n).to_vec();
        c::dds_free(p);
        v
    }
}

/// The endpoint QoS subset of a QoS owned by Cyclone; policies absent keep the defaults.
///
/// # Safety
/// `q` must be NULL or point to a valid `dds_qos_t` for the duration of the call.
pub(super) unsafe fn qos_endpoint(q: *const c::dds_qos_t) -> Option<EndpointQos> {
    if q.is_null() {
        return None;
    }
    let mut out = EndpointQos::default();
    let (mut rk, mut mbt, mut dk, mut hk, mut depth) = (0, 0, 0, 0, 0);
    let (mut deadline, mut lifespan, mut lk, mut lease) = (0, 0, 0, 0);
    // SAFETY: `q` is valid (caller's contract); every out-pointer is a live local.
    unsafe {
        if c::dds_qget_reliability(q, &mut rk, &mut mbt) {
            out.reliability = if rk == c::dds_reliability_kind_DDS_RELIABILITY_RELIABLE {
                Reliability::Reliable
            } else {
                Reliability::BestEffort
            };
            out.max_blocking_time = duration_from_dds(mbt).unwrap_or(Duration::MAX);
        }
        if c::dds_qget_durability(q, &mut dk) {
            out.durability = if dk == c::dds_durability_kind_DDS_DURABILITY_VOLATILE {
                Durability::Volatile
            } else {
                Durability::TransientLocal
            };
        }
        if c::dds_qget_history(q, &mut hk, &mut depth) {
            out.history = if hk == c::dds_history_kind_DDS_HISTORY_KEEP_ALL {
                History::KeepAll
            } else {
                History::KeepLast(u32::try_from(depth).unwrap_or(1))
            };
        }
        if c::dds_qget_deadline(q, &mut deadline) {
            out.deadline = duration_from_dds(deadline);
        }
        if c::dds_qget_lifespan(q, &mut lifespan) {
            out.lifespan = duration_from_dds(lifespan);
        }
        if c::dds_qget_liveliness(q, &mut lk, &mut lease) {
            out.liveliness = if lk == c::dds_liveliness_kind_DDS_LIVELINESS_MANUAL_BY_TOPIC {
                Liveliness::ManualByTopic
            } else {
                Liveliness::Automatic
            };
            out.liveliness_lease = duration_from_dds(lease);
        }
    }
    Some(out)
}

/// Copies a C string owned by Cyclone; empty if NULL.
///
/// # Safety
/// `p` must be NULL or point to a NUL-terminated string valid for the duration of the call.
pub(super) unsafe fn owned_string(p: *const c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: non-NULL and NUL-terminated (caller's contract).
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}
