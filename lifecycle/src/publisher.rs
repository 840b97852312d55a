//! [`LifecyclePublisher`]: rclcpp_lifecycle's `LifecyclePublisher`
//! (`rclcpp_lifecycle/include/rclcpp_lifecycle/lifecycle_publisher.hpp`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use horus_ros_msgs::Message;
use horus_ros_rmw::names::TopicName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Gid, PublishError, Publisher};

/// A publisher of a [`LifecycleNode`](crate::LifecycleNode) that publishes only while its node
/// is activating or active. Made by [`LifecycleNode::create_publisher`](crate::LifecycleNode::create_publisher).
///
/// While inactive, [`publish`](Self::publish) drops the message and warns once, until the next
/// activation (rclcpp's "Trying to publish message on the topic '…', but the publisher is not
/// activated").
pub struct LifecyclePublisher<M: Message> {
    publisher: Publisher<M>,
    active: Arc<AtomicBool>,
    warned: AtomicBool,
}

impl<M: Message> std::fmt::Debug for LifecyclePublisher<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LifecyclePublisher")
            .field("topic", &self.publisher.topic_name().to_string())
            .field("activated", &self.is_activated())
            .finish()
    }
}

impl<M: Message> LifecyclePublisher<M> {
    pub(crate) fn new(publisher: Publisher<M>, active: Arc<AtomicBool>) -> Self {
        Self {
            publisher,
            active,
            warned: AtomicBool::new(false),
        }
    }

    /// Whether the publisher publishes now (rclcpp's `is_activated`).
    pub fn is_activated(&self) -> bool {
        self.active.load(Ordering::Acquire)
    }

    /// Publishes `message` if activated; returns whether it was published.
    pub fn publish(&self, message: M) -> Result<bool, PublishError> {
        if !self.is_activated() {
            if !self.warned.swap(true, Ordering::Relaxed) {
                tracing::warn!(
                    "Trying to publish message on the topic '{}', but the publisher is not activated",
                    self.publisher.topic_name()
                );
            }
            return Ok(false);
        }
        self.warned.store(false, Ordering::Relaxed);
        self.publisher.publish(message)?;
        Ok(true)
    }

    /// The publisher's GID.
    pub fn gid(&self) -> Gid {
        self.publisher.gid()
    }

    /// The fully qualified topic name.
    pub fn topic_name(&self) -> &TopicName {
        self.publisher.topic_name()
    }

    /// The publisher's QoS.
    pub fn qos(&self) -> &Qos {
        self.publisher.qos()
    }
}
