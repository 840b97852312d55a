//! The built-in topics: DCPSParticipant / DCPSPublication / DCPSSubscription, read as owned
//! samples.

use std::ffi::c_void;
use std::sync::Arc;

use cyclors as c;

use super::*;
use crate::qos::EndpointQos;
use crate::Guid;

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
pub(super) struct Loan<'a> {
    pub(super) reader: &'a Handle,
    pub(super) buf: Vec<*mut c_void>,
    pub(super) n: i32,
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
    pub(super) handle: Arc<Handle>,
    pub(super) topic: BuiltinTopic,
}

pub(super) const BATCH: usize = 32;

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
