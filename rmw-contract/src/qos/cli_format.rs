//! A QoS profile as ros2cli prints it in `ros2 topic info -v` / `ros2 service info -v`.
//!
//! rclpy `topic_endpoint_info.py` (jazzy) `TopicEndpointInfo.__str__` prints, under
//! `QoS profile:` and indented, the policy enum names, the history depth only for KEEP_LAST,
//! and each duration as rclpy `Duration.__str__`: `Infinite` or `<n> nanoseconds`.

use std::fmt;

use super::{HistoryPolicy, Qos};

impl Qos {
    /// The `History (Depth)` value: `KEEP_LAST (<depth>)`, else the policy name alone.
    pub fn history_depth_string(&self) -> String {
        match self.history {
            HistoryPolicy::KeepLast => format!("{} ({})", self.history, self.depth),
            other => other.to_string(),
        }
    }

    /// The seven lines ros2cli prints for this profile, without indentation, in its order:
    /// `Reliability: RELIABLE`, `History (Depth): KEEP_LAST (10)`, `Durability: VOLATILE`,
    /// `Lifespan: Infinite`, `Deadline: Infinite`, `Liveliness: AUTOMATIC`,
    /// `Liveliness lease duration: Infinite`.
    pub fn info_lines(&self) -> Vec<String> {
        vec![
            format!("Reliability: {}", self.reliability),
            format!("History (Depth): {}", self.history_depth_string()),
            format!("Durability: {}", self.durability),
            format!("Lifespan: {}", self.lifespan),
            format!("Deadline: {}", self.deadline),
            format!("Liveliness: {}", self.liveliness),
            format!(
                "Liveliness lease duration: {}",
                self.liveliness_lease_duration
            ),
        ]
    }
}

/// The [`Qos::info_lines`] joined by newlines (no trailing newline).
impl fmt::Display for Qos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.info_lines().join("\n"))
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;
    use crate::qos::{EndpointKind, LivelinessPolicy};

    #[test]
    fn remote_default_endpoint_lines() {
        // What `ros2 topic info -v` shows for a discovered default-QoS publisher (Fast DDS
        // reports history UNKNOWN and DDS's infinite durations).
        let dds = Qos::default_profile()
            .to_dds(EndpointKind::Writer)
            .expect("valid profile");
        let mut remote = Qos::from_dds(&dds);
        remote.history = HistoryPolicy::Unknown;
        remote.depth = 0;
        assert_eq!(
            remote.info_lines(),
            [
                "Reliability: RELIABLE",
                "History (Depth): UNKNOWN",
                "Durability: VOLATILE",
                "Lifespan: Infinite",
                "Deadline: Infinite",
                "Liveliness: AUTOMATIC",
                "Liveliness lease duration: Infinite",
            ]
        );
    }

    #[test]
    fn local_profile_lines() {
        let q = Qos::services_default();
        assert_eq!(
            q.to_string(),
            "Reliability: RELIABLE\n\
             History (Depth): KEEP_LAST (10)\n\
             Durability: VOLATILE\n\
             Lifespan: 0 nanoseconds\n\
             Deadline: 0 nanoseconds\n\
             Liveliness: SYSTEM_DEFAULT\n\
             Liveliness lease duration: 0 nanoseconds"
        );
        let q = Qos::sensor_data()
            .keep_all()
            .transient_local()
            .with_deadline(Duration::from_millis(100))
            .with_liveliness(LivelinessPolicy::ManualByTopic);
        let lines = q.info_lines();
        assert_eq!(lines[0], "Reliability: BEST_EFFORT");
        assert_eq!(lines[1], "History (Depth): KEEP_ALL");
        assert_eq!(lines[2], "Durability: TRANSIENT_LOCAL");
        assert_eq!(lines[4], "Deadline: 100000000 nanoseconds");
        assert_eq!(lines[5], "Liveliness: MANUAL_BY_TOPIC");
        assert_eq!(
            Qos::best_available().info_lines()[0],
            "Reliability: BEST_AVAILABLE"
        );
    }
}
