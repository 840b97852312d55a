//! Typed topic endpoints created through a [`Node`]: [`Publisher`] and [`Subscription`].
//!
//! The DDS topic is the mangled name (`rt/<fully-qualified name>` unless the QoS avoids ROS
//! namespace conventions), the DDS type is the message's `pkg::msg::dds_::Name_`, samples are
//! XCDR1 little-endian. Each endpoint is listed under its node in `ros_discovery_info` from its
//! creation until it is dropped.

use horus_ros_msgs::Message;
use rustdds::{no_key, CDRDeserializerAdapter, CDRSerializerAdapter, RTPSEntity, TopicKind};

use crate::dds::gid_from_guid;
use crate::discovery::DiscoveredEndpoint;
use crate::entities::EndpointSide;
use crate::names::{ExpandError, TopicName};
use crate::node::{Node, Registration};
use crate::qos::{EndpointKind, Qos, QosError};
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

/// Resolves `name` for `node` and creates the DDS topic for message type `M`.
fn resolve_topic<M: Message>(
    node: &Node,
    name: &str,
    qos: &Qos,
    kind: EndpointKind,
) -> Result<(TopicName, rustdds::Topic, rustdds::QosPolicies), EndpointError> {
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
    let dds_name = topic_name.to_dds_topic_name(qos.avoid_ros_namespace_conventions);
    let participant = &node.context().inner().participant;
    let topic = participant
        .create_topic(
            dds_name.clone(),
            M::dds_type_name(),
            &dds_qos,
            TopicKind::NoKey,
        )
        .map_err(|e| EndpointError::Dds {
            kind: "topic",
            topic: dds_name,
            reason: e.to_string(),
        })?;
    Ok((topic_name, topic, dds_qos))
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
        // What rustdds announces for us: nothing (it cannot send endpoint USER_DATA).
        user_data: Vec::new(),
    }
}

/// Publishes messages of type `M` on one topic.
pub struct Publisher<M: Message> {
    // Dropped first: withdrawn from ros_discovery_info before the DDS writer is deleted.
    registration: Registration,
    topic: TopicName,
    qos: Qos,
    writer: no_key::DataWriter<M, CDRSerializerAdapter<M>>,
}

impl Node {
    /// Creates a publisher on `topic` (relative names, `~` and substitutions expand as in rcl).
    pub fn create_publisher<M: Message>(
        &self,
        topic: &str,
        qos: &Qos,
    ) -> Result<Publisher<M>, EndpointError> {
        let (topic_name, dds_topic, dds_qos) =
            resolve_topic::<M>(self, topic, qos, EndpointKind::Writer)?;
        let writer = self
            .context()
            .inner()
            .publisher
            .create_datawriter_no_key::<M, CDRSerializerAdapter<M>>(&dds_topic, Some(dds_qos))
            .map_err(|e| EndpointError::Dds {
                kind: "writer",
                topic: topic_name.to_string(),
                reason: e.to_string(),
            })?;
        Ok(Publisher {
            registration: Registration::new(
                self,
                EndpointSide::Writer,
                local_endpoint::<M>(
                    self,
                    gid_from_guid(writer.guid()),
                    EndpointKind::Writer,
                    &topic_name,
                    qos,
                ),
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
        let (topic_name, dds_topic, dds_qos) =
            resolve_topic::<M>(self, topic, qos, EndpointKind::Reader)?;
        let reader = self
            .context()
            .inner()
            .subscriber
            .create_datareader_no_key::<M, CDRDeserializerAdapter<M>>(&dds_topic, Some(dds_qos))
            .map_err(|e| EndpointError::Dds {
                kind: "reader",
                topic: topic_name.to_string(),
                reason: e.to_string(),
            })?;
        Ok(Subscription {
            registration: Registration::new(
                self,
                EndpointSide::Reader,
                local_endpoint::<M>(
                    self,
                    gid_from_guid(reader.guid()),
                    EndpointKind::Reader,
                    &topic_name,
                    qos,
                ),
            ),
            topic: topic_name,
            qos: *qos,
            reader,
        })
    }
}

impl<M: Message> Publisher<M> {
    /// Publishes one message.
    pub fn publish(&self, message: M) -> Result<(), PublishError> {
        self.writer.write(message, None).map_err(|e| PublishError {
            topic: self.topic.to_string(),
            reason: e.to_string(),
        })
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

/// Receives messages of type `M` from one topic.
pub struct Subscription<M: Message> {
    // Dropped first: withdrawn from ros_discovery_info before the DDS reader is deleted.
    registration: Registration,
    topic: TopicName,
    qos: Qos,
    reader: no_key::DataReader<M, CDRDeserializerAdapter<M>>,
}

impl<M: Message> Subscription<M> {
    /// Takes the next message, if one has arrived (non-blocking).
    pub fn try_take(&mut self) -> Result<Option<M>, TakeError> {
        match self.reader.take_next_sample() {
            Ok(sample) => Ok(sample.map(|s| s.into_value())),
            Err(e) => Err(TakeError {
                topic: self.topic.to_string(),
                reason: e.to_string(),
            }),
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
