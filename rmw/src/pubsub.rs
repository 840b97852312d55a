//! Typed topic endpoints created through a [`Node`]: [`Publisher`] and [`Subscription`].
//!
//! The DDS topic is the mangled name (`rt/<fully-qualified name>` unless the QoS avoids ROS
//! namespace conventions), the DDS type is the message's `pkg::msg::dds_::Name_`, samples are
//! XCDR1 little-endian. Each endpoint is listed under its node in `ros_discovery_info` from its
//! creation until it is dropped.

use std::marker::PhantomData;

use horus_ros_msgs::cdr::CdrError;
use horus_ros_msgs::Message;

use crate::dds_error::DdsError;
use crate::names::{ExpandError, TopicName};
use crate::node::Node;
use crate::qos::{EndpointKind, Qos, QosError};
use crate::raw::{RawEndpointSpec, RawReader, RawReaderWaker, RawWriter};
use crate::Gid;

/// Why an endpoint could not be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EndpointError {
    /// The topic name does not expand to a valid ROS name.
    #[error("invalid topic name '{name}': {cause}")]
    InvalidName {
        /// The name given.
        name: String,
        /// Why it is invalid.
        cause: ExpandError,
    },
    /// The QoS profile cannot be expressed in DDS.
    #[error("invalid QoS for '{name}': {cause}")]
    InvalidQos {
        /// The topic name given.
        name: String,
        /// Why.
        cause: QosError,
    },
    /// The DDS layer refused to create the reader or writer.
    #[error("could not create the DDS {kind} for '{topic}': {cause}")]
    Dds {
        /// `reader` or `writer`.
        kind: &'static str,
        /// The DDS topic name.
        topic: String,
        /// What the DDS layer said.
        cause: DdsError,
    },
}

/// What went wrong with one sample: its CDR, or the DDS layer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SampleError {
    /// The message could not be encoded as CDR, or the sample taken does not decode as the
    /// subscription's message type (e.g. a malformed sample from the wire; it is consumed).
    #[error(transparent)]
    Cdr(CdrError),
    /// The DDS layer refused or failed.
    #[error(transparent)]
    Dds(DdsError),
}

impl From<CdrError> for SampleError {
    fn from(e: CdrError) -> Self {
        Self::Cdr(e)
    }
}

impl From<DdsError> for SampleError {
    fn from(e: DdsError) -> Self {
        Self::Dds(e)
    }
}

/// Why a sample could not be published.
#[derive(Debug, thiserror::Error)]
#[error("could not publish on '{topic}': {cause}")]
pub struct PublishError {
    /// The ROS topic name ([`Publisher`]), or the DDS topic name ([`RawWriter`]).
    pub topic: String,
    /// What went wrong: the message's encoding, or the DDS layer.
    pub cause: SampleError,
}

/// Why a sample could not be taken.
#[derive(Debug, thiserror::Error)]
#[error("could not take a sample from '{topic}': {cause}")]
pub struct TakeError {
    /// The ROS topic name ([`Subscription`]), or the DDS topic name ([`RawReader`]).
    pub topic: String,
    /// What went wrong (e.g. a malformed sample from the wire).
    pub cause: SampleError,
}

/// Resolves `name` for `node` (remapped as rcl does) and checks that `qos` maps to DDS; returns
/// the topic and what its raw endpoint is.
fn resolve_topic<M: Message>(
    node: &Node,
    name: &str,
    qos: &Qos,
    kind: EndpointKind,
) -> Result<(TopicName, RawEndpointSpec), EndpointError> {
    qos.to_dds(kind)
        .map_err(|source| EndpointError::InvalidQos {
            name: name.to_owned(),
            cause: source,
        })?;
    let mut topic_name =
        TopicName::expand(name, node.name(), node.namespace()).map_err(|source| {
            EndpointError::InvalidName {
                name: name.to_owned(),
                cause: source,
            }
        })?;
    // `-r from:=to` (rcl_remap_topic_name), unless the QoS avoids ROS conventions.
    if !qos.avoid_ros_namespace_conventions {
        let arguments = node.context().arguments();
        if let Some(remapped) =
            arguments.remap_topic(topic_name.as_str(), node.name(), node.namespace())
        {
            topic_name =
                TopicName::new(&remapped).map_err(|source| EndpointError::InvalidName {
                    name: name.to_owned(),
                    cause: ExpandError::InvalidExpansion {
                        expanded: remapped.clone(),
                        cause: source,
                    },
                })?;
        }
    }
    let spec = RawEndpointSpec {
        dds_topic_name: topic_name.to_dds_topic_name(qos.avoid_ros_namespace_conventions),
        dds_type_name: M::dds_type_name(),
        type_hash: M::type_hash(),
        qos: *qos,
        service_id: None,
    };
    Ok((topic_name, spec))
}

/// Publishes messages of type `M` on one topic (a raw writer of their CDR).
pub struct Publisher<M: Message> {
    writer: RawWriter,
    topic: TopicName,
    qos: Qos,
    message: PhantomData<fn(M)>,
}

/// Receives messages of type `M` from one topic (a raw reader of their CDR).
pub struct Subscription<M: Message> {
    reader: RawReader,
    topic: TopicName,
    qos: Qos,
    message: PhantomData<fn() -> M>,
}

impl Node {
    /// Creates a publisher on `topic` (relative names, `~` and substitutions expand as in rcl).
    pub fn create_publisher<M: Message>(
        &self,
        topic: &str,
        qos: &Qos,
    ) -> Result<Publisher<M>, EndpointError> {
        let (topic, spec) = resolve_topic::<M>(self, topic, qos, EndpointKind::Writer)?;
        Ok(Publisher {
            writer: self.create_raw_writer(&spec)?,
            topic,
            qos: *qos,
            message: PhantomData,
        })
    }

    /// Creates a subscription on `topic` (relative names, `~` and substitutions expand as in rcl).
    pub fn create_subscription<M: Message>(
        &self,
        topic: &str,
        qos: &Qos,
    ) -> Result<Subscription<M>, EndpointError> {
        let (topic, spec) = resolve_topic::<M>(self, topic, qos, EndpointKind::Reader)?;
        Ok(Subscription {
            reader: self.create_raw_reader(&spec)?,
            topic,
            qos: *qos,
            message: PhantomData,
        })
    }
}

impl<M: Message> Publisher<M> {
    /// Publishes one message.
    pub fn publish(&self, message: M) -> Result<(), PublishError> {
        let fail = |source: SampleError| PublishError {
            topic: self.topic.to_string(),
            cause: source,
        };
        let body = horus_ros_msgs::cdr::to_cdr_body(&message).map_err(|e| fail(e.into()))?;
        self.writer
            .write(body, None, None)
            .map(|_| ())
            .map_err(|e| fail(e.cause))
    }

    /// Waits until every matched reliable reader acknowledged what was published, at most
    /// `timeout`; returns whether they all did. On the Cyclone backend it returns at once:
    /// Cyclone DDS delivers unacknowledged samples of a deleted writer itself (its writer
    /// linger duration).
    pub fn wait_for_acknowledgments(&self, timeout: std::time::Duration) -> bool {
        self.writer.wait_for_acknowledgments(timeout)
    }

    /// The writer's GID.
    pub fn gid(&self) -> Gid {
        self.writer.gid()
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
    /// Takes the next message, if one has arrived (non-blocking). A sample that does not decode
    /// as `M` is consumed and reported as an error.
    pub fn try_take(&mut self) -> Result<Option<M>, TakeError> {
        let fail = |source: SampleError| TakeError {
            topic: self.topic.to_string(),
            cause: source,
        };
        let Some(sample) = self.reader.take().map_err(|e| fail(e.cause))? else {
            return Ok(None);
        };
        let decoded = if sample.big_endian {
            horus_ros_msgs::cdr::from_cdr_body::<M, byteorder::BigEndian>(&sample.body)
        } else {
            horus_ros_msgs::cdr::from_cdr_body::<M, byteorder::LittleEndian>(&sample.body)
        };
        decoded.map(Some).map_err(|e| fail(e.into()))
    }

    /// A handle that makes this subscription's current or next [`wait`](Self::wait) return,
    /// from any thread (e.g. to stop the thread waiting on it).
    pub fn waker(&self) -> RawReaderWaker {
        self.reader.waker()
    }

    /// Waits until a message may have arrived or the [`waker`](Self::waker) was woken, at most
    /// `timeout` (a `Duration`, or `None` for no limit); returns whether something was
    /// signalled. Take until `None` after it: wake-ups are edge-triggered.
    pub fn wait(&mut self, timeout: impl Into<Option<std::time::Duration>>) -> bool {
        self.reader.wait(timeout)
    }

    /// The reader's GID.
    pub fn gid(&self) -> Gid {
        self.reader.gid()
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
