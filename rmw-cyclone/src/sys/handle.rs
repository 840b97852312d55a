//! Entity handles: every Cyclone entity owned by a [`Handle`] that deletes it on drop; [`Entity`]
//! and [`WeakEntity`]; [`StatusMask`].

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use cyclors as c;

use super::*;
use crate::Guid;

/// An owned Cyclone entity: `dds_delete`d on drop, after which the parent (if any) is released.
pub(super) struct Handle {
    pub(super) id: c::dds_entity_t,
    // Dropped after `Drop::drop` ran, so the child is always deleted before its parent.
    pub(super) _parent: Option<Arc<Handle>>,
    // What Cyclone may call into while the entity lives (a topic's filter): dropped after it.
    pub(super) _keep: Option<Box<dyn std::any::Any + Send + Sync>>,
    // Set once deleted ahead of the drop (see `delete_now`).
    pub(super) deleted: AtomicBool,
}

impl std::fmt::Debug for Handle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Handle").field("id", &self.id).finish()
    }
}

impl Handle {
    pub(super) fn new(id: c::dds_entity_t, parent: Option<&Arc<Handle>>) -> Arc<Self> {
        Self::keeping(id, parent, None)
    }

    /// A handle that also keeps `keep` alive until the entity is deleted.
    pub(super) fn keeping(
        id: c::dds_entity_t,
        parent: Option<&Arc<Handle>>,
        keep: Option<Box<dyn std::any::Any + Send + Sync>>,
    ) -> Arc<Self> {
        Arc::new(Self {
            id,
            _parent: parent.cloned(),
            _keep: keep,
            deleted: AtomicBool::new(false),
        })
    }

    /// Deletes the entity now, with its children, instead of when the last reference goes.
    /// Everything of ours that Cyclone may call into (listener arguments, filters) outlives the
    /// deletion all the more; the children's handles go stale, so calls on them fail with
    /// Cyclone's "bad parameter" and their `dds_delete` on drop does nothing.
    pub(super) fn delete_now(&self) -> Result<()> {
        if self.deleted.swap(true, Ordering::SeqCst) {
            return Ok(());
        }
        // SAFETY: as in `drop`: a handle is a table index, Cyclone checks it before use.
        check("dds_delete", unsafe { c::dds_delete(self.id) })?;
        Ok(())
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        if *self.deleted.get_mut() {
            return;
        }
        // SAFETY: `id` is an entity we created and nobody else deletes, unless an ancestor was
        // deleted early (`delete_now`, the goodbye of a process ending on a signal): parents
        // outlive their children (see `_parent`). Entity handles are table indices, not
        // pointers: Cyclone checks them, and dds_delete of a stale one fails harmlessly.
        let _ = unsafe { c::dds_delete(self.id) };
    }
}

/// A shared reference to one of our entities, for GUID/handle queries and status conditions.
#[derive(Debug, Clone)]
pub struct Entity(pub(super) Arc<Handle>);

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

    pub(super) fn set_status_mask(&self, mask: StatusMask) -> Result<()> {
        // SAFETY: live handle; any mask value is accepted or rejected with an error code.
        check("dds_set_status_mask", unsafe {
            c::dds_set_status_mask(self.0.id, mask.0)
        })?;
        Ok(())
    }
}

/// An [`Entity`] that may already be deleted.
#[derive(Debug, Clone)]
pub struct WeakEntity(pub(super) std::sync::Weak<Handle>);

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
