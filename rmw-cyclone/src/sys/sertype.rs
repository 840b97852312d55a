//! The sertype of our blob topics: `cyclors`' blob sertype (raw CDR that Cyclone never
//! interprets), with a sample form added so that a content filter can judge a sample by its
//! first bytes.
//!
//! Cyclone evaluates a topic's filter when it stores a sample in a reader
//! (`dds_rhc_default.c` `content_filter_accepts`): it allocates a sample through the sertype
//! (`realloc_samples`), deserializes into it (`to_sample`), calls the filter, and frees it
//! (`free_samples`). The blob sertype of `cyclors` (`cyclocut/src/cdds_blob.c`) implements
//! none of the three, so a filter on its topics would crash. Ours copies its operation tables
//! and adds them: a sample is the first [`HEAD_LEN`] bytes of the serialized data.

use std::ffi::c_void;
use std::os::raw::c_char;
use std::sync::OnceLock;

use cyclors as c;

use super::*;

/// How many leading bytes of a serialized sample a filter sees: the 4-byte encapsulation header
/// and rmw_cyclonedds' 16-byte request header (`cdds_request_header_t`: client GUID and
/// sequence number).
pub const HEAD_LEN: usize = 4 + 16;

/// A sample as a filter sees it (what `realloc_samples` allocates and `to_sample` fills).
#[repr(C)]
struct BlobHead {
    len: usize,
    bytes: [u8; HEAD_LEN],
}

/// The operation tables of our sertype: `cyclors`' own, with the sample operations added.
struct Ops {
    sertype: c::ddsi_sertype_ops,
    serdata: c::ddsi_serdata_ops,
}

// SAFETY: two tables of pointers to static C functions (and a null `arg`), built once and never
// written again; Cyclone only reads them, from any thread.
unsafe impl Send for Ops {}
// SAFETY: as for Send.
unsafe impl Sync for Ops {}

static OPS: OnceLock<Ops> = OnceLock::new();

/// Our tables, built on first use from those of a probe topic of `cyclors`' blob sertype made
/// (and deleted at once) on `participant`. A topic announces nothing: no peer sees the probe.
fn ops(participant: c::dds_entity_t) -> Result<&'static Ops> {
    if let Some(ops) = OPS.get() {
        return Ok(ops);
    }
    let name = cstring("cdds_create_blob_topic", "horus_ros_sertype_probe")?;
    let type_name = cstring("cdds_create_blob_topic", "horus_ros::SertypeProbe")?;
    // SAFETY: live participant; both strings valid for the call and only read.
    let h = check("cdds_create_blob_topic", unsafe {
        c::cdds_create_blob_topic(
            participant,
            name.as_ptr() as *mut c_char,
            type_name.as_ptr() as *mut c_char,
            true,
        )
    })?;
    // Deletes the probe topic on every path (its participant outlives this call).
    let probe = Handle::new(h, None);
    let mut st: *const c::ddsi_sertype = std::ptr::null();
    // SAFETY: live topic; `st` is a valid out-pointer. The sertype stays alive while the topic
    // does (we hold it in `probe`).
    check("dds_get_entity_sertype", unsafe {
        c::dds_get_entity_sertype(probe.id, &mut st)
    })?;
    if st.is_null() {
        return Err(error("dds_get_entity_sertype", "no sertype"));
    }
    // SAFETY: `st` is the live blob sertype of `probe`; its `ops` and `serdata_ops` point to
    // `cyclors`' static tables, copied here by value.
    let (mut sertype, mut serdata) = unsafe { (*(*st).ops, *(*st).serdata_ops) };
    drop(probe);
    sertype.free = Some(free_sertype);
    sertype.zero_samples = Some(zero_samples);
    sertype.realloc_samples = Some(realloc_samples);
    sertype.free_samples = Some(free_samples);
    serdata.to_sample = Some(to_sample);
    Ok(OPS.get_or_init(|| Ops { sertype, serdata }))
}

/// A keyless topic of our blob sertype on `participant` (see [`Participant::blob_topic`]).
pub(super) fn create_topic(
    participant: c::dds_entity_t,
    topic_name: &str,
    type_name: &str,
) -> Result<c::dds_entity_t> {
    let ops = ops(participant)?;
    let name = cstring("dds_create_topic_sertype", topic_name)?;
    let type_name = cstring("dds_create_topic_sertype", type_name)?;
    // SAFETY: a zeroed ddsi_sertype is what ddsi_sertype_init_flags expects to fill; it copies
    // the type name; our tables are 'static. The sertype is freed by `free_sertype` (Box) when
    // Cyclone drops its last reference.
    let st: *mut c::ddsi_sertype = Box::into_raw(Box::new(unsafe { std::mem::zeroed() }));
    // SAFETY: see above.
    unsafe {
        c::ddsi_sertype_init_flags(
            st,
            type_name.as_ptr(),
            &ops.sertype,
            &ops.serdata,
            c::DDSI_SERTYPE_FLAG_TOPICKIND_NO_KEY,
        )
    };
    let mut registered = st;
    // SAFETY: live participant; valid name; `registered` points to our initialised sertype,
    // whose reference moves to Cyclone (which may swap in an equal one already registered).
    // No QoS, listener or plist. On failure the sertype may leak, as with `cyclors`'
    // `cdds_create_blob_topic`: Cyclone releases it on some error paths and not on others.
    check("dds_create_topic_sertype", unsafe {
        c::dds_create_topic_sertype(
            participant,
            name.as_ptr(),
            &mut registered,
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
        )
    })
}

/// The filter of a topic: judges a sample by its first [`HEAD_LEN`] bytes (fewer if it is
/// shorter), encapsulation header included.
pub(super) type HeadFilter = Box<dyn Fn(&[u8]) -> bool + Send + Sync>;

/// Sets `filter` on `topic` (for the readers created from it afterwards). The returned box must
/// outlive the topic: Cyclone calls the filter with a pointer to it.
pub(super) fn set_filter(topic: c::dds_entity_t, filter: HeadFilter) -> Result<Box<HeadFilter>> {
    let filter = Box::new(filter);
    let spec = c::dds_topic_filter {
        mode: c::dds_topic_filter_mode_DDS_TOPIC_FILTER_SAMPLE_ARG,
        f: c::dds_topic_filter_function_union {
            sample_arg: Some(call_filter),
        },
        arg: &*filter as *const HeadFilter as *mut c_void,
    };
    // SAFETY: live topic; `spec` valid for the call (Cyclone copies it); `arg` points into a box
    // the caller keeps until the topic is deleted.
    check("dds_set_topic_filter_extended", unsafe {
        c::dds_set_topic_filter_extended(topic, &spec)
    })?;
    Ok(filter)
}

unsafe extern "C" fn call_filter(sample: *const c_void, arg: *mut c_void) -> bool {
    // SAFETY: Cyclone passes the sample `realloc_samples` allocated and `to_sample` filled,
    // and the `arg` of `set_filter`, a live HeadFilter.
    let (head, filter) = unsafe { (&*(sample as *const BlobHead), &*(arg as *const HeadFilter)) };
    let bytes = &head.bytes[..head.len.min(HEAD_LEN)];
    // No unwinding into C: a panicking filter keeps the sample.
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| filter(bytes))).unwrap_or(true)
}

unsafe extern "C" fn free_sertype(tp: *mut c::ddsi_sertype) {
    // SAFETY: called once by Cyclone when the last reference goes; `tp` came from Box::into_raw
    // in `create_topic` and was initialised by ddsi_sertype_init_flags.
    unsafe {
        c::ddsi_sertype_fini(tp);
        drop(Box::from_raw(tp));
    }
}

unsafe extern "C" fn zero_samples(_tp: *const c::ddsi_sertype, samples: *mut c_void, count: usize) {
    // SAFETY: Cyclone passes an array of `count` samples of ours.
    unsafe { std::ptr::write_bytes(samples as *mut BlobHead, 0, count) }
}

unsafe extern "C" fn realloc_samples(
    ptrs: *mut *mut c_void,
    _tp: *const c::ddsi_sertype,
    old: *mut c_void,
    old_count: usize,
    count: usize,
) {
    let size = std::mem::size_of::<BlobHead>();
    // SAFETY: as Cyclone's own sertypes do (`sertype_default_realloc_samples`): `old` is an
    // array of `old_count` samples from dds_alloc/dds_realloc (or null), resized with
    // dds_realloc (which aborts rather than return null); `ptrs` has room for `count` pointers.
    unsafe {
        let new = if old_count == count {
            old
        } else {
            c::dds_realloc(old, size * count)
        } as *mut u8;
        if count > old_count {
            std::ptr::write_bytes(new.add(size * old_count), 0, size * (count - old_count));
        }
        for i in 0..count {
            *ptrs.add(i) = new.add(i * size) as *mut c_void;
        }
    }
}

unsafe extern "C" fn free_samples(
    _tp: *const c::ddsi_sertype,
    ptrs: *mut *mut c_void,
    count: usize,
    op: c::dds_free_op_t,
) {
    // Our samples own nothing: only the array itself is freed, when asked to.
    if count > 0 && op & c::DDS_FREE_ALL_BIT != 0 {
        // SAFETY: `ptrs[0]` is the start of the array `realloc_samples` allocated.
        unsafe { c::dds_free(*ptrs) }
    }
}

unsafe extern "C" fn to_sample(
    d: *const c::ddsi_serdata,
    sample: *mut c_void,
    _bufptr: *mut *mut c_void,
    _buflim: *mut c_void,
) -> bool {
    // SAFETY: `d` is a live serdata of our sertype (the blob serdata of `cyclors`, whose
    // to_ser_ref gives a pointer into its payload and a reference that to_ser_unref returns);
    // `sample` is one of ours.
    unsafe {
        let head = &mut *(sample as *mut BlobHead);
        let want = (c::ddsi_serdata_size(d) as usize).min(HEAD_LEN);
        let mut iov = c::ddsrt_iovec_t {
            iov_base: std::ptr::null_mut(),
            iov_len: 0,
        };
        let r = c::ddsi_serdata_to_ser_ref(d, 0, want, &mut iov);
        if r.is_null() {
            return false;
        }
        let n = (iov.iov_len as usize).min(want);
        if n > 0 && !iov.iov_base.is_null() {
            std::ptr::copy_nonoverlapping(iov.iov_base as *const u8, head.bytes.as_mut_ptr(), n);
        }
        head.len = n;
        c::ddsi_serdata_to_ser_unref(r, &iov);
        true
    }
}
