//! Hidden names, as ros2cli filters them.

/// Prefix marking a hidden name token (rclpy `topic_or_service_is_hidden.py`
/// `HIDDEN_TOPIC_PREFIX`; ros2cli `ros2node/api` `HIDDEN_NODE_PREFIX`).
pub const HIDDEN_PREFIX: char = '_';

/// Whether a topic or service name is hidden: any `/`-separated token starts
/// with `_` (rclpy `topic_or_service_is_hidden`, jazzy). Works on any string.
pub fn is_hidden_name(name: &str) -> bool {
    name.split('/')
        .any(|token| token.starts_with(HIDDEN_PREFIX))
}
