//! The endpoint QoS subset this crate sets on writers/readers and reads back from the built-in
//! topics (the policies ROS 2 profiles map to).

use std::time::Duration;

/// RELIABILITY kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reliability {
    /// Samples may be lost.
    BestEffort,
    /// Samples are retransmitted until acknowledged.
    Reliable,
}

/// DURABILITY kind (the two ROS 2 uses).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// Late joiners get nothing from before they matched.
    Volatile,
    /// The writer keeps its history for late-joining readers.
    TransientLocal,
}

/// HISTORY kind and depth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum History {
    /// Keep the last N samples.
    KeepLast(u32),
    /// Keep everything (bounded by resource limits).
    KeepAll,
}

/// LIVELINESS kind (the two ROS 2 uses).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Liveliness {
    /// Asserted by the DDS implementation.
    Automatic,
    /// Asserted by each write on the topic.
    ManualByTopic,
}

/// Writer/reader QoS. `None` durations mean infinite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EndpointQos {
    /// RELIABILITY kind.
    pub reliability: Reliability,
    /// RELIABILITY max_blocking_time (writers: how long a write may block on a full history).
    pub max_blocking_time: Duration,
    /// DURABILITY kind.
    pub durability: Durability,
    /// HISTORY kind and depth.
    pub history: History,
    /// DEADLINE period.
    pub deadline: Option<Duration>,
    /// LIFESPAN duration.
    pub lifespan: Option<Duration>,
    /// LIVELINESS kind.
    pub liveliness: Liveliness,
    /// LIVELINESS lease duration.
    pub liveliness_lease: Option<Duration>,
}

impl Default for EndpointQos {
    /// The ROS 2 default profile (reliable, volatile, keep last 10), with Cyclone's default
    /// max_blocking_time of 100 ms and infinite deadline/lifespan/lease.
    fn default() -> Self {
        Self {
            reliability: Reliability::Reliable,
            max_blocking_time: Duration::from_millis(100),
            durability: Durability::Volatile,
            history: History::KeepLast(10),
            deadline: None,
            lifespan: None,
            liveliness: Liveliness::Automatic,
            liveliness_lease: None,
        }
    }
}
