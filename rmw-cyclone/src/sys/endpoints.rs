//! Writers and readers of serialized samples, and the endpoints they are matched with.

use std::collections::HashMap;
use std::ffi::c_void;
use std::sync::{Arc, Mutex};

use cyclors as c;

use super::*;
use crate::signal::{Notice, Signal};
use crate::Guid;

/// One reference to a Cyclone serdata, released (`ddsi_serdata_unref`) on drop.
pub(super) struct SerdataRef(pub(super) *mut c::ddsi_serdata);

impl SerdataRef {
    /// Copies the serialized form (encapsulation header + body) out of the sample.
    pub(super) fn to_vec(&self) -> Vec<u8> {
        // SAFETY: `self.0` is a live serdata (we hold a reference). to_ser_ref returns a
        // pointer/length into its serialized payload and a reference that keeps that memory
        // alive, which to_ser_unref gives back right after we copied the bytes.
        unsafe {
            let size = c::ddsi_serdata_size(self.0) as usize;
            let mut iov = c::ddsrt_iovec_t {
                iov_base: std::ptr::null_mut(),
                iov_len: 0,
            };
            let r = c::ddsi_serdata_to_ser_ref(self.0, 0, size, &mut iov);
            if r.is_null() || iov.iov_base.is_null() {
                return Vec::new();
            }
            let v = std::slice::from_raw_parts(iov.iov_base as *const u8, iov.iov_len as usize)
                .to_vec();
            c::ddsi_serdata_to_ser_unref(r, &iov);
            v
        }
    }
}

impl Drop for SerdataRef {
    fn drop(&mut self) {
        // SAFETY: we own exactly one reference to this serdata and give it back once.
        unsafe { c::ddsi_serdata_unref(self.0) }
    }
}

/// A blob-topic writer.
#[derive(Debug)]
pub struct Writer {
    pub(super) handle: Arc<Handle>,
}

impl Writer {
    /// The writer as an [`Entity`] (GUID, instance handle, status).
    pub fn entity(&self) -> Entity {
        Entity(self.handle.clone())
    }

    /// Waits at most `limit` until every matched reliable reader acknowledged what this writer
    /// wrote (`dds_wait_for_acks`); whether they all did.
    pub fn wait_for_acks(&self, limit: Duration) -> Result<bool> {
        // SAFETY: live writer (we hold it); any timeout value is valid.
        let rc = unsafe { c::dds_wait_for_acks(self.handle.id, duration_to_dds(Some(limit))) };
        if rc == c::DDS_RETCODE_TIMEOUT {
            return Ok(false);
        }
        check("dds_wait_for_acks", rc)?;
        Ok(true)
    }

    /// Writes one serialized sample: `cdr` is the 4-byte encapsulation header followed by the
    /// CDR body, exactly as it should appear on the wire.
    pub fn write(&self, cdr: &[u8]) -> Result<()> {
        if cdr.len() < 4 {
            return Err(error(
                "write",
                "a serialized sample needs its 4-byte encapsulation header",
            ));
        }
        let mut st: *const c::ddsi_sertype = std::ptr::null();
        // SAFETY: valid out-pointer; live writer. The sertype belongs to the writer's topic,
        // which this writer keeps alive, so the pointer stays valid during this call.
        check("dds_get_entity_sertype", unsafe {
            c::dds_get_entity_sertype(self.handle.id, &mut st)
        })?;
        let iov = c::ddsrt_iovec_t {
            iov_base: cdr.as_ptr() as *mut c_void,
            iov_len: cdr.len() as _,
        };
        // SAFETY: `st` is the live blob sertype; the iovec describes `cdr`, which the blob
        // serdata copies (it keeps no pointer to it). On success we own one reference.
        let sd = unsafe {
            c::ddsi_serdata_from_ser_iov(st, c::ddsi_serdata_kind_SDK_DATA, 1, &iov, cdr.len())
        };
        if sd.is_null() {
            return Err(error(
                "ddsi_serdata_from_ser_iov",
                "could not build a serdata",
            ));
        }
        // SAFETY: dds_writecdr consumes our reference on every path except three early
        // returns that cannot happen here: a NULL serdata (checked above), a handle that is not
        // a live writer (ours is live until our Drop) and a topic with a content filter (our
        // blob topics never get one). So ownership of the reference is transferred.
        check("dds_writecdr", unsafe {
            c::dds_writecdr(self.handle.id, sd)
        })?;
        Ok(())
    }

    /// The readers currently matched with this writer (their GUIDs and USER_DATA).
    pub fn matched_subscriptions(&self) -> Result<Vec<MatchedEndpoint>> {
        matched(&self.handle, Direction::Subscriptions)
    }

    /// PUBLICATION_MATCHED: (current matched count, change since last read); reading resets
    /// the status.
    pub fn publication_matched(&self) -> Result<(u32, i32)> {
        let mut st = c::dds_publication_matched_status_t {
            total_count: 0,
            total_count_change: 0,
            current_count: 0,
            current_count_change: 0,
            last_subscription_handle: 0,
        };
        // SAFETY: valid out-pointer; live writer.
        check("dds_get_publication_matched_status", unsafe {
            c::dds_get_publication_matched_status(self.handle.id, &mut st)
        })?;
        Ok((st.current_count, st.current_count_change))
    }
}

/// One sample taken from a [`Reader`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sample {
    /// The serialized sample: 4-byte encapsulation header + CDR body.
    pub cdr: Vec<u8>,
    /// The writer's local instance handle (Cyclone's `publication_handle`).
    pub publication_handle: u64,
    /// The writer's GUID (from `publication_handle`, looked up once per writer and cached);
    /// `None` if the writer was already gone when the sample was taken.
    pub writer_guid: Option<Guid>,
    /// The writer's source timestamp, nanoseconds since the Unix epoch.
    pub source_timestamp_ns: i64,
}

/// A blob-topic reader.
#[derive(Debug)]
pub struct Reader {
    pub(super) handle: Arc<Handle>,
    pub(super) writers: Mutex<HashMap<u64, Guid>>,
    pub(super) hooks: Arc<DataHooks>,
}

/// How many writers' GUIDs a reader remembers by instance handle; past it the cache starts
/// over (writers that come and go must not grow it).
const WRITER_CACHE: usize = 1024;

/// The [`Signal`]s a reader's data raises, shared with its DATA_AVAILABLE listener.
#[derive(Debug, Default)]
pub(super) struct DataHooks(Mutex<Vec<Arc<Notice>>>);

impl DataHooks {
    fn raise_all(&self) {
        for notice in lock(&self.0).iter() {
            notice.raise();
        }
    }
}

/// The reader's DATA_AVAILABLE listener. Cyclone calls it after storing a sample and
/// releasing the reader's history cache (`dds_reader_data_available_cb`), in the thread that
/// delivered the sample: a lock, a push and a notify, nothing that blocks or panics.
unsafe extern "C" fn on_data_available(_reader: c::dds_entity_t, arg: *mut c_void) {
    // SAFETY: `arg` is the reader's `DataHooks`, which the reader's Handle keeps alive until
    // dds_delete returned; dds_delete first waits for listeners in progress and resets the
    // listener (dds_entity.c, `really_delete_pinned_closed_locked`).
    let hooks = unsafe { &*(arg as *const DataHooks) };
    hooks.raise_all();
}

/// A `dds_listener_t` with only `on_data_available` set, deleted on drop (Cyclone copies a
/// listener into the entity it is given to).
pub(super) struct DataListener(pub(super) *mut c::dds_listener_t);

impl DataListener {
    /// A listener that raises `hooks`' signals; `hooks` must outlive every entity given it.
    pub(super) fn new(hooks: &Arc<DataHooks>) -> Result<Self> {
        // SAFETY: dds_create_listener allocates a listener (NULL default argument); owned by
        // the returned value and deleted once in Drop.
        let l = unsafe { c::dds_create_listener(std::ptr::null_mut()) };
        if l.is_null() {
            return Err(error("dds_create_listener", "out of memory"));
        }
        let listener = Self(l);
        // SAFETY: live listener; the callback has the signature Cyclone expects; the argument
        // points to `hooks`, kept alive by the caller as documented. reset_on_invoke: the
        // DATA_AVAILABLE status is consumed by the listener (nothing waits on it).
        check("dds_lset_data_available_arg", unsafe {
            c::dds_lset_data_available_arg(
                listener.0,
                Some(on_data_available),
                Arc::as_ptr(hooks) as *mut c_void,
                true,
            )
        })?;
        Ok(listener)
    }
}

impl Drop for DataListener {
    fn drop(&mut self) {
        // SAFETY: we own the listener and delete it once.
        unsafe { c::dds_delete_listener(self.0) }
    }
}

/// While it lives, a reader's arrivals raise one [`Signal`] (see [`Reader::notify`]).
#[derive(Debug)]
#[must_use = "dropping the notice detaches the reader from the signal at once"]
pub struct DataNotice {
    hooks: Arc<DataHooks>,
    notice: Arc<Notice>,
}

impl Drop for DataNotice {
    fn drop(&mut self) {
        lock(&self.hooks.0).retain(|n| !Arc::ptr_eq(n, &self.notice));
    }
}

impl Reader {
    /// The reader as an [`Entity`] (GUID, instance handle, status).
    pub fn entity(&self) -> Entity {
        Entity(self.handle.clone())
    }

    /// Takes the next valid sample, if any (never blocks). Invalid samples (instance state
    /// changes without data) are consumed and skipped.
    pub fn take(&self) -> Result<Option<Sample>> {
        loop {
            let mut sd: *mut c::ddsi_serdata = std::ptr::null_mut();
            let mut si = zeroed_sample_info();
            // SAFETY: room for one serdata pointer and one sample info; live reader. When it
            // returns 1 we own one reference to `sd`, handed to SerdataRef at once.
            let n = check("dds_takecdr", unsafe {
                c::dds_takecdr(self.handle.id, &mut sd, 1, &mut si, c::DDS_ANY_STATE)
            })?;
            if n == 0 || sd.is_null() {
                return Ok(None);
            }
            let sd = SerdataRef(sd);
            if !si.valid_data {
                continue;
            }
            let cdr = sd.to_vec();
            drop(sd);
            let writer_guid = self.writer_guid(si.publication_handle);
            return Ok(Some(Sample {
                cdr,
                publication_handle: si.publication_handle,
                writer_guid,
                source_timestamp_ns: si.source_timestamp,
            }));
        }
    }

    /// Raises `signal` with `token` after each arrival of data (Cyclone stored it and released
    /// the reader), until the returned notice is dropped; raised at once if samples are already
    /// there (or if that cannot be told). See [`Signal::wait`].
    pub fn notify(&self, signal: &Arc<Signal>, token: usize) -> DataNotice {
        let notice = Notice::new(signal, token);
        lock(&self.hooks.0).push(Arc::clone(&notice));
        // After the push: a sample stored from now on raises the notice itself.
        if self.has_data().unwrap_or(true) {
            notice.raise();
        }
        DataNotice {
            hooks: Arc::clone(&self.hooks),
            notice,
        }
    }

    /// Whether the reader holds any sample (a read condition asked once).
    fn has_data(&self) -> Result<bool> {
        // SAFETY: live reader; the condition is its child, deleted by the Handle right after.
        let rc = Handle::new(
            check("dds_create_readcondition", unsafe {
                c::dds_create_readcondition(self.handle.id, c::DDS_ANY_STATE)
            })?,
            Some(&self.handle),
        );
        // SAFETY: live read condition.
        let triggered = check("dds_triggered", unsafe { c::dds_triggered(rc.id) })?;
        Ok(triggered > 0)
    }

    pub(super) fn writer_guid(&self, ih: u64) -> Option<Guid> {
        if let Some(g) = lock(&self.writers).get(&ih) {
            return Some(*g);
        }
        // SAFETY: live reader; returns a malloc'd endpoint description or NULL (writer not, or
        // no longer, matched). Freed right after copying the key.
        let guid = unsafe {
            let ep = c::dds_get_matched_publication_data(self.handle.id, ih);
            if ep.is_null() {
                return None;
            }
            let g = (*ep).key.v;
            c::dds_builtintopic_free_endpoint(ep);
            Guid(g)
        };
        let mut writers = lock(&self.writers);
        if writers.len() >= WRITER_CACHE {
            writers.clear();
        }
        writers.insert(ih, guid);
        Some(guid)
    }

    /// The writers currently matched with this reader (their GUIDs and USER_DATA).
    pub fn matched_publications(&self) -> Result<Vec<MatchedEndpoint>> {
        matched(&self.handle, Direction::Publications)
    }
}

pub(super) fn zeroed_sample_info() -> c::dds_sample_info_t {
    c::dds_sample_info_t {
        sample_state: 0,
        view_state: 0,
        instance_state: 0,
        valid_data: false,
        source_timestamp: 0,
        instance_handle: 0,
        publication_handle: 0,
        disposed_generation_count: 0,
        no_writers_generation_count: 0,
        sample_rank: 0,
        generation_rank: 0,
        absolute_generation_rank: 0,
    }
}

/// A remote (or local) endpoint matched with one of ours.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MatchedEndpoint {
    /// The endpoint's GUID.
    pub guid: Guid,
    /// Its participant's GUID.
    pub participant_guid: Guid,
    /// Its USER_DATA.
    pub user_data: Vec<u8>,
}

pub(super) enum Direction {
    Subscriptions,
    Publications,
}

pub(super) fn matched(h: &Handle, dir: Direction) -> Result<Vec<MatchedEndpoint>> {
    let mut ihs = vec![0u64; 16];
    let n = loop {
        // SAFETY: `ihs` has room for `ihs.len()` handles; live endpoint. The call returns the
        // total number matched, which may exceed the buffer (then we retry with a larger one).
        let n = check("dds_get_matched_endpoints", unsafe {
            match dir {
                Direction::Subscriptions => {
                    c::dds_get_matched_subscriptions(h.id, ihs.as_mut_ptr(), ihs.len())
                }
                Direction::Publications => {
                    c::dds_get_matched_publications(h.id, ihs.as_mut_ptr(), ihs.len())
                }
            }
        })? as usize;
        if n <= ihs.len() {
            break n;
        }
        ihs.resize(n, 0);
    };
    let mut out = Vec::with_capacity(n);
    for ih in &ihs[..n] {
        // SAFETY: live endpoint; returns a malloc'd description or NULL if that endpoint went
        // away meanwhile; its qos pointer is valid until it is freed, right after copying.
        unsafe {
            let ep = match dir {
                Direction::Subscriptions => c::dds_get_matched_subscription_data(h.id, *ih),
                Direction::Publications => c::dds_get_matched_publication_data(h.id, *ih),
            };
            if ep.is_null() {
                continue;
            }
            out.push(MatchedEndpoint {
                guid: Guid((*ep).key.v),
                participant_guid: Guid((*ep).participant_key.v),
                user_data: qos_user_data((*ep).qos),
            });
            c::dds_builtintopic_free_endpoint(ep);
        }
    }
    Ok(out)
}
