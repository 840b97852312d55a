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
//! - No listener is ever installed: Cyclone's own threads never run code of ours. Waiting is done
//!   with waitsets in the caller's thread ([`Waiter`]); other threads wake it with a
//!   [`GuardCondition`].
#![allow(unsafe_code)]

use std::collections::HashMap;
use std::ffi::{c_void, CStr, CString};
use std::os::raw::c_char;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use cyclors as c;

use crate::qos::{Durability, EndpointQos, History, Liveliness, Reliability};
use crate::Guid;

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

fn error(op: &'static str, message: &str) -> Error {
    Error {
        op,
        code: -1,
        message: message.to_owned(),
    }
}

/// Turns a `dds_return_t` (or an entity handle, positive on success) into a `Result`.
fn check(op: &'static str, rc: i32) -> Result<i32> {
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

fn cstring(op: &'static str, s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| error(op, "string contains a NUL byte"))
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn duration_to_dds(d: Option<Duration>) -> c::dds_duration_t {
    d.map_or(i64::MAX, |d| {
        i64::try_from(d.as_nanos()).unwrap_or(i64::MAX)
    })
}

fn duration_from_dds(ns: c::dds_duration_t) -> Option<Duration> {
    (ns != i64::MAX && ns >= 0).then(|| Duration::from_nanos(ns as u64))
}

// ---------------------------------------------------------------------------------------------
// Entity handles

/// An owned Cyclone entity: `dds_delete`d on drop, after which the parent (if any) is released.
#[derive(Debug)]
struct Handle {
    id: c::dds_entity_t,
    // Dropped after `Drop::drop` ran, so the child is always deleted before its parent.
    _parent: Option<Arc<Handle>>,
}

impl Handle {
    fn new(id: c::dds_entity_t, parent: Option<&Arc<Handle>>) -> Arc<Self> {
        Arc::new(Self {
            id,
            _parent: parent.cloned(),
        })
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: `id` is an entity we created and nobody else deletes: parents outlive their
        // children (see `_parent`), so it is still live. Entity handles are table indices,
        // not pointers; dds_delete of a live handle is always sound.
        let _ = unsafe { c::dds_delete(self.id) };
    }
}

/// A shared reference to one of our entities, for GUID/handle queries and status conditions.
#[derive(Debug, Clone)]
pub struct Entity(Arc<Handle>);

impl Entity {
    /// The entity's DDS GUID (16 bytes: 12-byte prefix of its participant + entity id).
    pub fn guid(&self) -> Result<Guid> {
        let mut g = c::dds_guid_t { v: [0; 16] };
        // SAFETY: `g` is a valid, writable dds_guid_t; the handle is live (we own it).
        check("dds_get_guid", unsafe {
            c::dds_get_guid(self.0.id, &mut g)
        })?;
        Ok(Guid(g.v))
    }

    /// The entity's local instance handle. For a writer this is the value rmw_cyclonedds puts
    /// in a service request header as the client's writer id.
    pub fn instance_handle(&self) -> Result<u64> {
        let mut ih: c::dds_instance_handle_t = 0;
        // SAFETY: valid out-pointer; live handle.
        check("dds_get_instance_handle", unsafe {
            c::dds_get_instance_handle(self.0.id, &mut ih)
        })?;
        Ok(ih)
    }

    /// Reads and resets the given communication statuses; returns those that were set.
    pub fn take_status(&self, mask: StatusMask) -> Result<StatusMask> {
        let mut s = 0u32;
        // SAFETY: valid out-pointer; live handle.
        check("dds_take_status", unsafe {
            c::dds_take_status(self.0.id, &mut s, mask.0)
        })?;
        Ok(StatusMask(s))
    }

    /// A handle that does not keep the entity alive (e.g. for a registry of live endpoints).
    pub fn downgrade(&self) -> WeakEntity {
        WeakEntity(Arc::downgrade(&self.0))
    }

    /// The readers matched with this entity, a writer (their GUIDs and USER_DATA); an error
    /// for anything else.
    pub fn matched_subscriptions(&self) -> Result<Vec<MatchedEndpoint>> {
        matched(&self.0, Direction::Subscriptions)
    }

    /// The writers matched with this entity, a reader (their GUIDs and USER_DATA); an error
    /// for anything else.
    pub fn matched_publications(&self) -> Result<Vec<MatchedEndpoint>> {
        matched(&self.0, Direction::Publications)
    }

    fn set_status_mask(&self, mask: StatusMask) -> Result<()> {
        // SAFETY: live handle; any mask value is accepted or rejected with an error code.
        check("dds_set_status_mask", unsafe {
            c::dds_set_status_mask(self.0.id, mask.0)
        })?;
        Ok(())
    }
}

/// An [`Entity`] that may already be deleted.
#[derive(Debug, Clone)]
pub struct WeakEntity(std::sync::Weak<Handle>);

impl WeakEntity {
    /// The entity, if something still keeps it alive.
    pub fn upgrade(&self) -> Option<Entity> {
        self.0.upgrade().map(Entity)
    }
}

/// A set of DDS communication statuses (for [`Waiter::attach_status`] and
/// [`Entity::take_status`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StatusMask(pub u32);

impl StatusMask {
    /// A writer matched or unmatched a reader.
    pub const PUBLICATION_MATCHED: Self =
        Self(1 << c::dds_status_id_DDS_PUBLICATION_MATCHED_STATUS_ID);
    /// A reader matched or unmatched a writer.
    pub const SUBSCRIPTION_MATCHED: Self =
        Self(1 << c::dds_status_id_DDS_SUBSCRIPTION_MATCHED_STATUS_ID);
    /// A reader has new data.
    pub const DATA_AVAILABLE: Self = Self(1 << c::dds_status_id_DDS_DATA_AVAILABLE_STATUS_ID);
    /// A matched writer's liveliness changed.
    pub const LIVELINESS_CHANGED: Self =
        Self(1 << c::dds_status_id_DDS_LIVELINESS_CHANGED_STATUS_ID);
    /// A reader's requested deadline was missed.
    pub const REQUESTED_DEADLINE_MISSED: Self =
        Self(1 << c::dds_status_id_DDS_REQUESTED_DEADLINE_MISSED_STATUS_ID);

    /// Whether every status of `other` is in `self`.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
}

impl std::ops::BitOr for StatusMask {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
}

// ---------------------------------------------------------------------------------------------
// Domains

struct DomainSlot {
    handle: Arc<Handle>,
    config: String,
    refs: usize,
}

static DOMAINS: Mutex<Option<HashMap<u32, DomainSlot>>> = Mutex::new(None);

/// A reference to a Cyclone domain configured from an XML string, shared per domain id within
/// the process like rmw_cyclonedds' `CddsDomain`: the first reference creates the domain
/// (`dds_create_domain`), the last one deletes it; asking for a domain id that is already
/// configured differently is an error (Cyclone allows one configuration per id per process).
#[derive(Debug)]
pub struct Domain {
    id: u32,
    handle: Arc<Handle>,
}

impl Domain {
    /// Creates domain `id` from `config` (Cyclone's comma-separated XML fragments / URIs, as
    /// [`crate::config::domain_config`] builds), or shares it if it already exists with the
    /// same configuration.
    pub fn acquire(id: u32, config: &str) -> Result<Self> {
        let mut domains = lock(&DOMAINS);
        let map = domains.get_or_insert_with(HashMap::new);
        if let Some(slot) = map.get_mut(&id) {
            if slot.config != config {
                return Err(Error {
                    op: "dds_create_domain",
                    code: c::DDS_RETCODE_PRECONDITION_NOT_MET,
                    message: format!(
                        "domain {id} is already configured differently in this process"
                    ),
                });
            }
            slot.refs += 1;
            return Ok(Self {
                id,
                handle: slot.handle.clone(),
            });
        }
        let cfg = cstring("dds_create_domain", config)?;
        // SAFETY: `cfg` is a valid NUL-terminated string for the duration of the call; Cyclone
        // parses it and keeps no pointer to it.
        let h = check("dds_create_domain", unsafe {
            c::dds_create_domain(id, cfg.as_ptr())
        })?;
        let handle = Handle::new(h, None);
        map.insert(
            id,
            DomainSlot {
                handle: handle.clone(),
                config: config.to_owned(),
                refs: 1,
            },
        );
        Ok(Self { id, handle })
    }

    /// The DDS domain id.
    pub fn id(&self) -> u32 {
        self.id
    }
}

impl Drop for Domain {
    fn drop(&mut self) {
        let mut domains = lock(&DOMAINS);
        if let Some(map) = domains.as_mut() {
            if let Some(slot) = map.get_mut(&self.id) {
                slot.refs -= 1;
                if slot.refs == 0 {
                    // Drops the slot's Arc; the domain entity goes with the last Arc (ours or a
                    // participant's), i.e. after every participant created in it.
                    map.remove(&self.id);
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// QoS

/// An owned `dds_qos_t`, deleted on drop.
struct QosBox(*mut c::dds_qos_t);

impl QosBox {
    fn new() -> Result<Self> {
        // SAFETY: plain allocation; the result is checked for NULL and freed in Drop.
        let q = unsafe { c::dds_create_qos() };
        if q.is_null() {
            return Err(error("dds_create_qos", "out of memory"));
        }
        Ok(Self(q))
    }

    fn user_data(&mut self, data: &[u8]) {
        // SAFETY: `self.0` is a live QoS we own; Cyclone copies `len` bytes from `data`.
        unsafe { c::dds_qset_userdata(self.0, data.as_ptr().cast(), data.len()) };
    }

    fn endpoint(&mut self, q: &EndpointQos) {
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
unsafe fn qos_user_data(q: *const c::dds_qos_t) -> Vec<u8> {
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
unsafe fn qos_endpoint(q: *const c::dds_qos_t) -> Option<EndpointQos> {
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
unsafe fn owned_string(p: *const c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: non-NULL and NUL-terminated (caller's contract).
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

// ---------------------------------------------------------------------------------------------
// Participant

/// A DDS domain participant with USER_DATA (for ROS: `enclave=/;`). Cheap to clone; the
/// participant is deleted when the last clone and the last entity created from it are dropped.
#[derive(Debug, Clone)]
pub struct Participant {
    handle: Arc<Handle>,
    domain: Arc<Domain>,
}

impl Participant {
    /// Creates a participant in `domain` with the given USER_DATA.
    pub fn new(domain: Domain, user_data: &[u8]) -> Result<Self> {
        let mut q = QosBox::new()?;
        q.user_data(user_data);
        // SAFETY: the domain exists (held by `domain`); the QoS pointer is valid for the call
        // (Cyclone copies it); NULL listener: no callbacks.
        let h = check("dds_create_participant", unsafe {
            c::dds_create_participant(domain.id, q.0, std::ptr::null())
        })?;
        // The participant's parent is the domain entity: deleted only after the participant.
        Ok(Self {
            handle: Handle::new(h, Some(&domain.handle)),
            domain: Arc::new(domain),
        })
    }

    /// The participant as an [`Entity`] (GUID, instance handle).
    pub fn entity(&self) -> Entity {
        Entity(self.handle.clone())
    }

    /// The participant's GUID (its GID in ROS terms).
    pub fn guid(&self) -> Result<Guid> {
        self.entity().guid()
    }

    /// The domain id.
    pub fn domain_id(&self) -> u32 {
        self.domain.id
    }

    /// A keyless topic of opaque serialized samples (the "blob" sertype of `cyclors`' cyclocut,
    /// as zenoh-plugin-ros2dds uses): any topic and type name; Cyclone never interprets the
    /// bytes, it just carries them with their 4-byte encapsulation header.
    pub fn blob_topic(&self, topic_name: &str, type_name: &str) -> Result<Topic> {
        let n = cstring("cdds_create_blob_topic", topic_name)?;
        let t = cstring("cdds_create_blob_topic", type_name)?;
        // SAFETY: live participant; both strings are valid for the call and only read (the
        // `*mut` in the signature is historical): the sertype duplicates the type name and
        // dds_create_topic_sertype copies the topic name. The sertype's ownership moves to
        // the topic.
        let h = check("cdds_create_blob_topic", unsafe {
            c::cdds_create_blob_topic(
                self.handle.id,
                n.as_ptr() as *mut c_char,
                t.as_ptr() as *mut c_char,
                true,
            )
        })?;
        Ok(Topic {
            handle: Handle::new(h, Some(&self.handle)),
            name: topic_name.to_owned(),
            type_name: type_name.to_owned(),
        })
    }

    /// A writer of `topic` with `qos` and USER_DATA (for ROS: `typehash=RIHS01_…;`).
    pub fn writer(&self, topic: &Topic, qos: &EndpointQos, user_data: &[u8]) -> Result<Writer> {
        let mut q = QosBox::new()?;
        q.endpoint(qos);
        q.user_data(user_data);
        // SAFETY: live participant and topic (both held); QoS valid for the call; no listener.
        let h = check("dds_create_writer", unsafe {
            c::dds_create_writer(self.handle.id, topic.handle.id, q.0, std::ptr::null())
        })?;
        // The writer keeps the topic (and through it the participant) alive.
        Ok(Writer {
            handle: Handle::new(h, Some(&topic.handle)),
        })
    }

    /// A reader of `topic` with `qos` and USER_DATA.
    pub fn reader(&self, topic: &Topic, qos: &EndpointQos, user_data: &[u8]) -> Result<Reader> {
        let mut q = QosBox::new()?;
        q.endpoint(qos);
        q.user_data(user_data);
        // SAFETY: as for `writer`.
        let h = check("dds_create_reader", unsafe {
            c::dds_create_reader(self.handle.id, topic.handle.id, q.0, std::ptr::null())
        })?;
        Ok(Reader {
            handle: Handle::new(h, Some(&topic.handle)),
            writers: Mutex::new(HashMap::new()),
        })
    }

    /// A reader of one of the DDS built-in discovery topics (default QoS: reliable,
    /// transient-local, so it also gets everything discovered before it was created).
    pub fn builtin_reader(&self, topic: BuiltinTopic) -> Result<BuiltinReader> {
        let pseudo = match topic {
            BuiltinTopic::Participant => c::DDS_BUILTIN_TOPIC_DCPSPARTICIPANT,
            BuiltinTopic::Publication => c::DDS_BUILTIN_TOPIC_DCPSPUBLICATION,
            BuiltinTopic::Subscription => c::DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION,
        };
        // SAFETY: live participant; `pseudo` is one of Cyclone's built-in topic pseudo handles;
        // NULL QoS and listener.
        let h = check("dds_create_reader(builtin)", unsafe {
            c::dds_create_reader(self.handle.id, pseudo, std::ptr::null(), std::ptr::null())
        })?;
        Ok(BuiltinReader {
            handle: Handle::new(h, Some(&self.handle)),
            topic,
        })
    }
}

/// A blob topic (see [`Participant::blob_topic`]).
#[derive(Debug)]
pub struct Topic {
    handle: Arc<Handle>,
    name: String,
    type_name: String,
}

impl Topic {
    /// The topic name as on the wire (for ROS: `rt/…`, `rq/…`, `rr/…`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The DDS type name (for ROS: `pkg::msg::dds_::Type_`).
    pub fn type_name(&self) -> &str {
        &self.type_name
    }
}

// ---------------------------------------------------------------------------------------------
// Serialized samples

/// One reference to a Cyclone serdata, released (`ddsi_serdata_unref`) on drop.
struct SerdataRef(*mut c::ddsi_serdata);

impl SerdataRef {
    /// Copies the serialized form (encapsulation header + body) out of the sample.
    fn to_vec(&self) -> Vec<u8> {
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
    handle: Arc<Handle>,
}

impl Writer {
    /// The writer as an [`Entity`] (GUID, instance handle, status).
    pub fn entity(&self) -> Entity {
        Entity(self.handle.clone())
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
    handle: Arc<Handle>,
    writers: Mutex<HashMap<u64, Guid>>,
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

    fn writer_guid(&self, ih: u64) -> Option<Guid> {
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
        lock(&self.writers).insert(ih, guid);
        Some(guid)
    }

    /// The writers currently matched with this reader (their GUIDs and USER_DATA).
    pub fn matched_publications(&self) -> Result<Vec<MatchedEndpoint>> {
        matched(&self.handle, Direction::Publications)
    }
}

fn zeroed_sample_info() -> c::dds_sample_info_t {
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

enum Direction {
    Subscriptions,
    Publications,
}

fn matched(h: &Handle, dir: Direction) -> Result<Vec<MatchedEndpoint>> {
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

// ---------------------------------------------------------------------------------------------
// Built-in topics

/// The DDS built-in discovery topics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BuiltinTopic {
    /// DCPSParticipant: participants.
    Participant,
    /// DCPSPublication: writers.
    Publication,
    /// DCPSSubscription: readers.
    Subscription,
}

/// A participant as the DCPSParticipant topic describes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParticipantInfo {
    /// The participant's GUID.
    pub guid: Guid,
    /// `false` once the participant is gone (then `user_data` is empty).
    pub alive: bool,
    /// Its USER_DATA (for ROS 2: `enclave=…;`).
    pub user_data: Vec<u8>,
}

/// A writer or reader as DCPSPublication/DCPSSubscription describe it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EndpointInfo {
    /// The endpoint's GUID.
    pub guid: Guid,
    /// Its participant's GUID (zero when `alive` is false).
    pub participant_guid: Guid,
    /// `false` once the endpoint is gone (then only `guid` is meaningful).
    pub alive: bool,
    /// Topic name.
    pub topic_name: String,
    /// Type name.
    pub type_name: String,
    /// Its QoS (the subset this crate models); `None` when not alive.
    pub qos: Option<EndpointQos>,
    /// Its USER_DATA (for ROS 2: `typehash=RIHS01_…;`).
    pub user_data: Vec<u8>,
}

/// One sample of a built-in topic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BuiltinSample {
    /// From DCPSParticipant.
    Participant(ParticipantInfo),
    /// From DCPSPublication.
    Publication(EndpointInfo),
    /// From DCPSSubscription.
    Subscription(EndpointInfo),
}

/// Samples loaned by Cyclone, returned (`dds_return_loan`) on drop.
struct Loan<'a> {
    reader: &'a Handle,
    buf: Vec<*mut c_void>,
    n: i32,
}

impl Drop for Loan<'_> {
    fn drop(&mut self) {
        if self.n > 0 {
            // SAFETY: `buf[..n]` is exactly the loan dds_take gave us for this live reader;
            // it is returned once.
            unsafe { c::dds_return_loan(self.reader.id, self.buf.as_mut_ptr(), self.n) };
        }
    }
}

/// A reader of one built-in topic (see [`Participant::builtin_reader`]).
#[derive(Debug)]
pub struct BuiltinReader {
    handle: Arc<Handle>,
    topic: BuiltinTopic,
}

const BATCH: usize = 32;

impl BuiltinReader {
    /// The reader as an [`Entity`].
    pub fn entity(&self) -> Entity {
        Entity(self.handle.clone())
    }

    /// Which built-in topic this reads.
    pub fn topic(&self) -> BuiltinTopic {
        self.topic
    }

    /// Takes everything available now (never blocks), as owned values.
    pub fn take(&self) -> Result<Vec<BuiltinSample>> {
        let mut out = Vec::new();
        loop {
            let mut loan = Loan {
                reader: &self.handle,
                buf: vec![std::ptr::null_mut(); BATCH],
                n: 0,
            };
            let mut si: Vec<c::dds_sample_info_t> =
                (0..BATCH).map(|_| zeroed_sample_info()).collect();
            // SAFETY: live reader; `buf[0] == NULL` asks Cyclone to loan the sample memory
            // (returned by Loan::drop); `buf` and `si` each have room for BATCH entries.
            let n = check("dds_take(builtin)", unsafe {
                c::dds_take(
                    self.handle.id,
                    loan.buf.as_mut_ptr(),
                    si.as_mut_ptr(),
                    BATCH,
                    BATCH as u32,
                )
            })?;
            loan.n = n;
            if n == 0 {
                return Ok(out);
            }
            for (ptr, info) in loan.buf.iter().zip(&si).take(n as usize) {
                let alive = info.instance_state == c::dds_instance_state_DDS_IST_ALIVE;
                let valid = info.valid_data;
                // SAFETY: the loaned samples of a built-in reader are dds_builtintopic_*
                // structs matching the topic, valid until the loan is returned (after this
                // loop); for invalid samples only the key is filled in, so nothing else is
                // read then. Strings and QoS are copied out by the helpers.
                let sample = unsafe {
                    match self.topic {
                        BuiltinTopic::Participant => {
                            let p = &*(*ptr as *const c::dds_builtintopic_participant_t);
                            BuiltinSample::Participant(ParticipantInfo {
                                guid: Guid(p.key.v),
                                alive,
                                user_data: if valid {
                                    qos_user_data(p.qos)
                                } else {
                                    Vec::new()
                                },
                            })
                        }
                        BuiltinTopic::Publication | BuiltinTopic::Subscription => {
                            let e = &*(*ptr as *const c::dds_builtintopic_endpoint_t);
                            let info = EndpointInfo {
                                guid: Guid(e.key.v),
                                participant_guid: Guid(if valid {
                                    e.participant_key.v
                                } else {
                                    [0; 16]
                                }),
                                alive,
                                topic_name: if valid {
                                    owned_string(e.topic_name)
                                } else {
                                    String::new()
                                },
                                type_name: if valid {
                                    owned_string(e.type_name)
                                } else {
                                    String::new()
                                },
                                qos: if valid { qos_endpoint(e.qos) } else { None },
                                user_data: if valid {
                                    qos_user_data(e.qos)
                                } else {
                                    Vec::new()
                                },
                            };
                            if self.topic == BuiltinTopic::Publication {
                                BuiltinSample::Publication(info)
                            } else {
                                BuiltinSample::Subscription(info)
                            }
                        }
                    }
                };
                out.push(sample);
            }
            if (n as usize) < BATCH {
                return Ok(out);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Waiting

/// A guard condition: set from any thread to wake a [`Waiter`] it is attached to. Cheap to
/// clone (all clones are the same condition).
#[derive(Debug, Clone)]
pub struct GuardCondition {
    handle: Arc<Handle>,
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
enum Attached {
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
    handle: Arc<Handle>,
    // What is attached, by token: kept alive while attached (read conditions are owned here),
    // except entities watched for their status, which may be deleted while attached.
    attached: std::sync::Mutex<Vec<(usize, Attached)>>,
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

    fn attached(&self) -> std::sync::MutexGuard<'_, Vec<(usize, Attached)>> {
        self.attached.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn attach(&self, h: Arc<Handle>, token: usize) -> Result<()> {
        // SAFETY: both handles live (we keep `h` alive while attached); the token is an opaque
        // integer Cyclone hands back from dds_waitset_wait.
        check("dds_waitset_attach", unsafe {
            c::dds_waitset_attach(self.handle.id, h.id, token as c::dds_attach_t)
        })?;
        self.attached().push((token, Attached::Owned(h)));
        Ok(())
    }

    fn read_condition(&self, reader: &Arc<Handle>, token: usize) -> Result<()> {
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
