//! The `ros_discovery_info` topic on rustdds: its writer and readers with the QoS of
//! [`crate::dds::discovery_info`].

use rustdds::{
    no_key::DataWriter, policy, CDRSerializerAdapter, DomainParticipant, Publisher, QosPolicies,
    QosPolicyBuilder, Topic, TopicKind,
};

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;

pub(crate) use crate::dds::discovery_info::{TOPIC_NAME, TYPE_NAME};

/// The writer's QoS: RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1.
pub(crate) fn writer_qos() -> QosPolicies {
    QosPolicyBuilder::new()
        .reliability(policy::Reliability::Reliable {
            max_blocking_time: rustdds::Duration::INFINITE,
        })
        .durability(policy::Durability::TransientLocal)
        .history(policy::History::KeepLast { depth: 1 })
        .build()
}

/// The reader's QoS: RELIABLE, TRANSIENT_LOCAL, KEEP_ALL.
pub(crate) fn reader_qos() -> QosPolicies {
    QosPolicyBuilder::new()
        .reliability(policy::Reliability::Reliable {
            max_blocking_time: rustdds::Duration::INFINITE,
        })
        .durability(policy::Durability::TransientLocal)
        .history(policy::History::KeepAll)
        .build()
}

/// The topic, created (or found) on `participant`.
pub(crate) fn topic(participant: &DomainParticipant) -> Result<Topic, rustdds::dds::CreateError> {
    participant.create_topic(
        TOPIC_NAME.to_owned(),
        TYPE_NAME.to_owned(),
        &writer_qos(),
        TopicKind::NoKey,
    )
}

/// Publishes this participant's [`ParticipantEntitiesInfo`].
pub(crate) struct DiscoveryInfoWriter {
    writer: DataWriter<ParticipantEntitiesInfo, CDRSerializerAdapter<ParticipantEntitiesInfo>>,
}

impl DiscoveryInfoWriter {
    /// Creates the writer.
    pub(crate) fn new(
        publisher: &Publisher,
        topic: &Topic,
    ) -> Result<Self, rustdds::dds::CreateError> {
        let writer = publisher.create_datawriter_no_key(topic, Some(writer_qos()))?;
        Ok(Self { writer })
    }

    /// Waits at most `limit` until every matched reader acknowledged what was written; whether
    /// they all did.
    pub(crate) fn wait_for_acknowledgments(&self, limit: std::time::Duration) -> bool {
        self.writer.wait_for_acknowledgments(limit).unwrap_or(false)
    }

    /// Publishes `info`; a failure is logged, since discovery will catch up with the next change.
    pub(crate) fn publish(&self, info: ParticipantEntitiesInfo) {
        if let Err(e) = self.writer.write(info, None) {
            tracing::warn!("could not publish on {TOPIC_NAME}: {e}");
        }
    }
}
