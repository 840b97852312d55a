//! Typed topic endpoints created through a [`Node`]: [`Publisher`] and [`Subscription`].
//!
//! The DDS topic is the mangled name (`rt/<fully-qualified name>` unless the QoS avoids ROS
//! namespace conventions), the DDS type is the message's `pkg::msg::dds_::Name_`, samples are
//! XCDR1 little-endian. Each endpoint is listed under its node in `ros_discovery_info` from its
//! creation until it is dropped.

use horus_ros_msgs::Message;
use rustdds::{no_key, CDRDeserializerAdapter, CDRSerializerAdapter, RTPSEntity, TopicKind};

use crate::context::Dds;
use crate::dds::{gid_from_guid, RustddsParticipant};
use crate::discovery::DiscoveredEndpoint;
use crate::entities::EndpointSide;
use crate::names::{ExpandError, TopicName};
use crate::node::{Node, Registration};
use crate::qos::{DdsQos, EndpointKind, Qos, QosError};
use crate::Gid;

/// Why an endpoint could not be created.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EndpointError {
    /// The topic name does not expand to a valid ROS name.
    #[error("invalid topic name '{name}': {source}")]
    InvalidName {
        /// The name given.
        name: String,
        /// Why it is invalid.
        source: ExpandError,
    },
    /// The QoS profile cannot be expressed in DDS.
    #[error("invalid QoS for '{name}': {source}")]
    InvalidQos {
        /// The topic name given.
        name: String,
        /// Why.
        source: QosError,
    },
    /// The DDS layer refused to create the reader or writer.
    #[error("could not create the DDS {kind} for '{topic}': {reason}")]
    Dds {
        /// `reader` or `writer`.
        kind: &'static str,
        /// The DDS topic name.
        topic: String,
        /// What the DDS layer said.
        reason: String,
    },
}

/// Why a sample could not be published.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("could not publish on '{topic}': {reason}")]
pub struct PublishError {
    /// The ROS topic name.
    pub topic: String,
    /// What the DDS layer said.
    pub reason: String,
}

/// Why a sample could not be taken.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("could not take a sample from '{topic}': {reason}")]
pub struct TakeError {
    /// The ROS topic name.
    pub topic: String,
    /// What went wrong (e.g. a malformed sample from the wire).
    pub reason: String,
}

/// Resolves `name` for `node` and maps `qos` to DDS policies.
fn resolve_topic(
    node: &Node,
    name: &str,
    qos: &Qos,
    kind: EndpointKind,
) -> Result<(TopicName, DdsQos), EndpointError> {
    let dds_qos = qos
        .to_dds(kind)
        .map_err(|source| EndpointError::InvalidQos {
            name: name.to_owned(),
            source,
        })?;
    let topic_name = TopicName::expand(name, node.name(), node.namespace()).map_err(|source| {
        EndpointError::InvalidName {
            name: name.to_owned(),
            source,
        }
    })?;
    // `-r from:=to` (rcl_remap_topic_name), unless the QoS avoids ROS conventions.
    if !qos.avoid_ros_namespace_conventions {
        let arguments = node.context().arguments();
        if let Some(remapped) =
            arguments.remap_topic(topic_name.as_str(), node.name(), node.namespace())
        {
            let remapped =
                TopicName::new(&remapped).map_err(|source| EndpointError::InvalidName {
                    name: name.to_owned(),
                    source: ExpandError::InvalidExpansion {
                        expanded: remapped.clone(),
                        source,
                    },
                })?;
            return Ok((remapped, dds_qos));
        }
    }
    Ok((topic_name, dds_qos))
}

/// Creates the rustdds topic `dds_name` for message type `M`.
fn rustdds_topic<M: Message>(
    participant: &RustddsParticipant,
    dds_name: &str,
    dds_qos: &rustdds::QosPolicies,
) -> Result<rustdds::Topic, EndpointError> {
    participant
        .participant
        .create_topic(
            dds_name.to_owned(),
            M::dds_type_name(),
            dds_qos,
            TopicKind::NoKey,
        )
        .map_err(|e| EndpointError::Dds {
            kind: "topic",
            topic: dds_name.to_owned(),
            reason: e.to_string(),
        })
}

/// How one of our own endpoints is reported to the discovery feed.
fn local_endpoint<M: Message>(
    node: &Node,
    gid: Gid,
    kind: EndpointKind,
    topic: &TopicName,
    qos: &Qos,
) -> DiscoveredEndpoint {
    DiscoveredEndpoint {
        gid,
        participant_gid: node.context().gid(),
        kind,
        dds_topic_name: topic.to_dds_topic_name(qos.avoid_ros_namespace_conventions),
        dds_type_name: M::dds_type_name(),
        qos: qos.effective(kind),
        type_hash: M::type_hash(),
        // What the backend announces for us (rustdds cannot send endpoint USER_DATA).
        user_data: if node.context().backend().announces_user_data() {
            M::type_hash().to_user_data().into_bytes()
        } else {
            Vec::new()
        },
    }
}

/// Publishes messages of type `M` on one topic.
pub struct Publisher<M: Message> {
    // Dropped first: withdrawn from ros_discovery_info before the DDS writer is deleted.
    registration: Registration,
    topic: TopicName,
    qos: Qos,
    writer: TypedWriter<M>,
}

// One per entity, used in place: boxing the larger variant would buy nothing.
#[allow(clippy::large_enum_variant)]
enum TypedWriter<M: Message> {
    RustDds(no_key::DataWriter<M, CDRSerializerAdapter<M>>),
    #[cfg(feature = "cyclone")]
    Cyclone(crate::cyclone::endpoints::RawWriter),
}

/// Receives messages of type `M` from one topic.
pub struct Subscription<M: Message> {
    // Dropped first: withdrawn from ros_discovery_info before the DDS reader is deleted.
    registration: Registration,
    topic: TopicName,
    qos: Qos,
    reader: TypedReader<M>,
    waker: crate::RawReaderWaker,
}

// One per entity, used in place: boxing the larger variant would buy nothing.
#[allow(clippy::large_enum_variant)]
enum TypedReader<M: Message> {
    RustDds {
        /// Woken when data arrives (rustdds' mio 1 source, drained by take).
        poll: rustdds::mio1::Poll,
        reader: no_key::DataReader<M, CDRDeserializerAdapter<M>>,
    },
    #[cfg(feature = "cyclone")]
    Cyclone(crate::cyclone::endpoints::RawReader),
}

impl Node {
    /// Creates a publisher on `topic` (relative names, `~` and substitutions expand as in rcl).
    pub fn create_publisher<M: Message>(
        &self,
        topic: &str,
        qos: &Qos,
    ) -> Result<Publisher<M>, EndpointError> {
        let (topic_name, dds_qos) = resolve_topic(self, topic, qos, EndpointKind::Writer)?;
        let dds_name = topic_name.to_dds_topic_name(qos.avoid_ros_namespace_conventions);
        let fail = |reason: String| EndpointError::Dds {
            kind: "writer",
            topic: topic_name.to_string(),
            reason,
        };
        let (writer, gid) = match &self.context().inner().dds {
            Dds::RustDds(p) => {
                let policies = crate::dds::qos::to_rustdds(&dds_qos);
                let dds_topic = rustdds_topic::<M>(p, &dds_name, &policies)?;
                let writer = p
                    .publisher
                    .create_datawriter_no_key::<M, CDRSerializerAdapter<M>>(
                        &dds_topic,
                        Some(policies),
                    )
                    .map_err(|e| fail(e.to_string()))?;
                let gid = gid_from_guid(writer.guid());
                (TypedWriter::RustDds(writer), gid)
            }
            #[cfg(feature = "cyclone")]
            Dds::Cyclone(p) => {
                let (writer, gid) = crate::cyclone::endpoints::RawWriter::create(
                    p,
                    &dds_name,
                    &M::dds_type_name(),
                    &dds_qos,
                    M::type_hash().to_user_data().as_bytes(),
                )
                .map_err(fail)?;
                (TypedWriter::Cyclone(writer), gid)
            }
        };
        Ok(Publisher {
            registration: Registration::new(
                self,
                EndpointSide::Writer,
                local_endpoint::<M>(self, gid, EndpointKind::Writer, &topic_name, qos),
            ),
            topic: topic_name,
            qos: *qos,
            writer,
        })
    }

    /// Creates a subscription on `topic` (relative names, `~` and substitutions expand as in rcl).
    pub fn create_subscription<M: Message>(
        &self,
        topic: &str,
        qos: &Qos,
    ) -> Result<Subscription<M>, EndpointError> {
        let (topic_name, dds_qos) = resolve_topic(self, topic, qos, EndpointKind::Reader)?;
        let dds_name = topic_name.to_dds_topic_name(qos.avoid_ros_namespace_conventions);
        let fail = |reason: String| EndpointError::Dds {
            kind: "reader",
            topic: topic_name.to_string(),
            reason,
        };
        let (reader, gid, waker) = match &self.context().inner().dds {
            Dds::RustDds(p) => {
                let policies = crate::dds::qos::to_rustdds(&dds_qos);
                let dds_topic = rustdds_topic::<M>(p, &dds_name, &policies)?;
                let mut reader = p
                    .subscriber
                    .create_datareader_no_key::<M, CDRDeserializerAdapter<M>>(
                        &dds_topic,
                        Some(policies),
                    )
                    .map_err(|e| fail(e.to_string()))?;
                let gid = gid_from_guid(reader.guid());
                let poll = rustdds::mio1::Poll::new().map_err(|e| fail(e.to_string()))?;
                // As for raw readers: rustdds' mio 1 source is drained by take, so
                // edge-triggered waking works.
                poll.registry()
                    .register(
                        &mut reader,
                        rustdds::mio1::Token(0),
                        rustdds::mio1::Interest::READABLE,
                    )
                    .map_err(|e| fail(e.to_string()))?;
                let waker = rustdds::mio1::Waker::new(poll.registry(), rustdds::mio1::Token(1))
                    .map_err(|e| fail(e.to_string()))?;
                let waker = crate::RawReaderWaker::rustdds(waker);
                (TypedReader::RustDds { poll, reader }, gid, waker)
            }
            #[cfg(feature = "cyclone")]
            Dds::Cyclone(p) => {
                let (reader, gid) = crate::cyclone::endpoints::RawReader::create(
                    p,
                    &dds_name,
                    &M::dds_type_name(),
                    &dds_qos,
                    M::type_hash().to_user_data().as_bytes(),
                    None,
                )
                .map_err(fail)?;
                let waker = crate::RawReaderWaker::cyclone(reader.guard());
                (TypedReader::Cyclone(reader), gid, waker)
            }
        };
        Ok(Subscription {
            registration: Registration::new(
                self,
                EndpointSide::Reader,
                local_endpoint::<M>(self, gid, EndpointKind::Reader, &topic_name, qos),
            ),
            topic: topic_name,
            qos: *qos,
            reader,
            waker,
        })
    }
}

impl<M: Message> Publisher<M> {
    /// Publishes one message.
    pub fn publish(&self, message: M) -> Result<(), PublishError> {
        let fail = |reason: String| PublishError {
            topic: self.topic.to_string(),
            reason,
        };
        match &self.writer {
            TypedWriter::RustDds(writer) => {
                writer.write(message, None).map_err(|e| fail(e.to_string()))
            }
            #[cfg(feature = "cyclone")]
            TypedWriter::Cyclone(writer) => {
                let body =
                    horus_ros_msgs::cdr::to_cdr_body(&message).map_err(|e| fail(e.to_string()))?;
                writer.write(&body).map(|_| ()).map_err(fail)
            }
        }
    }

    /// Waits until every matched reliable reader acknowledged what was published, at most
    /// `timeout`; returns whether they all did. On the Cyclone backend it returns at once:
    /// Cyclone DDS delivers unacknowledged samples of a deleted writer itself (its writer
    /// linger duration).
    pub fn wait_for_acknowledgments(&self, timeout: std::time::Duration) -> bool {
        match &self.writer {
            TypedWriter::RustDds(writer) => {
                writer.wait_for_acknowledgments(timeout).unwrap_or(false)
            }
            #[cfg(feature = "cyclone")]
            TypedWriter::Cyclone(_) => true,
        }
    }

    /// The writer's GID.
    pub fn gid(&self) -> Gid {
        self.registration.gid()
    }

    /// The fully-qualified topic name.
    pub fn topic_name(&self) -> &TopicName {
        &self.topic
    }

    /// The QoS asked for.
    pub fn qos(&self) -> &Qos {
        &self.qos
    }
}

impl<M: Message> Subscription<M> {
    /// Takes the next message, if one has arrived (non-blocking).
    pub fn try_take(&mut self) -> Result<Option<M>, TakeError> {
        let fail = |reason: String| TakeError {
            topic: self.topic.to_string(),
            reason,
        };
        match &mut self.reader {
            TypedReader::RustDds { reader, .. } => match reader.take_next_sample() {
                Ok(sample) => Ok(sample.map(|s| s.into_value())),
                Err(e) => Err(fail(e.to_string())),
            },
            #[cfg(feature = "cyclone")]
            TypedReader::Cyclone(reader) => {
                let Some(sample) = reader.take().map_err(fail)? else {
                    return Ok(None);
                };
                let decoded = if sample.big_endian {
                    horus_ros_msgs::cdr::from_cdr_body::<M, byteorder::BigEndian>(&sample.body)
                } else {
                    horus_ros_msgs::cdr::from_cdr_body::<M, byteorder::LittleEndian>(&sample.body)
                };
                decoded.map(Some).map_err(|e| fail(e.to_string()))
            }
        }
    }

    /// A handle that makes this subscription's current or next [`wait`](Self::wait) return,
    /// from any thread (e.g. to stop the thread waiting on it).
    pub fn waker(&self) -> crate::RawReaderWaker {
        self.waker.clone()
    }

    /// Waits until a message may have arrived or the [`waker`](Self::waker) was woken, at most
    /// `timeout` (a `Duration`, or `None` for no limit); returns whether something was
    /// signalled. Take until `None` after it: wake-ups are edge-triggered.
    pub fn wait(&mut self, timeout: impl Into<Option<std::time::Duration>>) -> bool {
        let timeout = timeout.into();
        match &mut self.reader {
            TypedReader::RustDds { poll, .. } => crate::raw::wait_on(poll, timeout),
            #[cfg(feature = "cyclone")]
            TypedReader::Cyclone(reader) => reader.wait(timeout),
        }
    }

    /// The reader's GID.
    pub fn gid(&self) -> Gid {
        self.registration.gid()
    }

    /// The fully-qualified topic name.
    pub fn topic_name(&self) -> &TopicName {
        &self.topic
    }

    /// The QoS asked for.
    pub fn qos(&self) -> &Qos {
        &self.qos
    }
}
