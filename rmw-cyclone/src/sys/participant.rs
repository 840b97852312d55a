//! Participants and blob topics.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use cyclors as c;

use super::*;
use crate::qos::EndpointQos;
use crate::Guid;

/// A DDS domain participant with USER_DATA (for ROS: `enclave=/;`). Cheap to clone; the
/// participant is deleted when the last clone and the last entity created from it are dropped.
#[derive(Debug, Clone)]
pub struct Participant {
    pub(super) handle: Arc<Handle>,
    pub(super) domain: Arc<Domain>,
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

    /// Deletes the participant now, with every entity created from it, then its domain (with
    /// every other participant of this process in it), while references to them remain.
    /// Cyclone deletes a participant in the background; deleting the domain waits until that is
    /// done, so the participant's dispose is on its way when this returns and peers see it
    /// leave at once. Every later call on those entities fails; dropping them is harmless. For a
    /// process that is about to end (e.g. on SIGINT) and cannot wait for their owners to drop
    /// them.
    pub fn delete_with_domain(&self) -> Result<()> {
        self.handle.delete_now()?;
        self.domain.delete_now()
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
    /// as zenoh-plugin-ros2dds uses, with a sample form for filters: see `sys::sertype`): any
    /// topic and type name; Cyclone never interprets the bytes, it just carries them with their
    /// 4-byte encapsulation header.
    pub fn blob_topic(&self, topic_name: &str, type_name: &str) -> Result<Topic> {
        let h = sertype::create_topic(self.handle.id, topic_name, type_name)?;
        Ok(Topic {
            handle: Handle::new(h, Some(&self.handle)),
            name: topic_name.to_owned(),
            type_name: type_name.to_owned(),
        })
    }

    /// A [`blob_topic`](Self::blob_topic) whose readers store only the samples `keep` accepts,
    /// judged by their first [`HEAD_LEN`] bytes (encapsulation header included; fewer if the
    /// sample is shorter). Cyclone runs the filter as it stores a sample, in its own thread or
    /// the writer's: keep it short, and it must not call into Cyclone.
    pub fn filtered_blob_topic(
        &self,
        topic_name: &str,
        type_name: &str,
        keep: impl Fn(&[u8]) -> bool + Send + Sync + 'static,
    ) -> Result<Topic> {
        let h = sertype::create_topic(self.handle.id, topic_name, type_name)?;
        let filter = match sertype::set_filter(h, Box::new(keep)) {
            Ok(filter) => filter,
            Err(e) => {
                // Deletes the topic.
                drop(Handle::new(h, Some(&self.handle)));
                return Err(e);
            }
        };
        Ok(Topic {
            // The topic keeps its filter alive until it is deleted.
            handle: Handle::keeping(h, Some(&self.handle), Some(Box::new(filter))),
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
        let hooks = Arc::new(DataHooks::default());
        let listener = DataListener::new(&hooks)?;
        // SAFETY: as for `writer`; the listener is copied by Cyclone, its argument (`hooks`)
        // is kept alive by the reader's handle until the reader is deleted.
        let h = check("dds_create_reader", unsafe {
            c::dds_create_reader(self.handle.id, topic.handle.id, q.0, listener.0)
        })?;
        let keep: Box<dyn std::any::Any + Send + Sync> = Box::new(Arc::clone(&hooks));
        Ok(Reader {
            handle: Handle::keeping(h, Some(&topic.handle), Some(keep)),
            writers: Mutex::new(HashMap::new()),
            hooks,
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
    pub(super) handle: Arc<Handle>,
    pub(super) name: String,
    pub(super) type_name: String,
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
