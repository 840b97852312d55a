//! Domains: one configured Cyclone domain per process and domain id, shared (like rmw_cyclonedds'
//! `CddsDomain`).

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use cyclors as c;

use super::*;

pub(super) struct DomainSlot {
    pub(super) handle: Arc<Handle>,
    pub(super) config: String,
    pub(super) refs: usize,
}

pub(super) static DOMAINS: Mutex<Option<HashMap<u32, DomainSlot>>> = Mutex::new(None);

/// A reference to a Cyclone domain configured from an XML string, shared per domain id within
/// the process like rmw_cyclonedds' `CddsDomain`: the first reference creates the domain
/// (`dds_create_domain`), the last one deletes it; asking for a domain id that is already
/// configured differently is an error (Cyclone allows one configuration per id per process).
#[derive(Debug)]
pub struct Domain {
    pub(super) id: u32,
    pub(super) handle: Arc<Handle>,
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

    /// Deletes the domain now, with every entity in it, waiting until Cyclone has finished
    /// deleting its participants (`ddsi_stop`); the next [`acquire`](Self::acquire) of this id
    /// creates a new one.
    pub(super) fn delete_now(&self) -> Result<()> {
        if let Some(map) = lock(&DOMAINS).as_mut() {
            if map
                .get(&self.id)
                .is_some_and(|slot| Arc::ptr_eq(&slot.handle, &self.handle))
            {
                map.remove(&self.id);
            }
        }
        self.handle.delete_now()
    }
}

impl Drop for Domain {
    fn drop(&mut self) {
        let mut domains = lock(&DOMAINS);
        if let Some(map) = domains.as_mut() {
            // Not a slot of a newer domain of the same id (after `delete_now`).
            let slot = map
                .get_mut(&self.id)
                .filter(|slot| Arc::ptr_eq(&slot.handle, &self.handle));
            if let Some(slot) = slot {
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
