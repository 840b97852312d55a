use crate::names::{is_hidden_name, NodeName, ServiceName, TopicName};

// Semantics of rclpy (jazzy) rclpy/topic_or_service_is_hidden.py and ros2cli
// ros2node/api `get_node_names` (node names hidden by a leading '_').
#[test]
fn hidden_names() {
    let cases = [
        ("/chatter", false),
        ("/_hidden", true),
        ("/ns/_private/thing", true),
        ("/_ns/thing", true),
        ("/ns/thing_", false),
        ("/ns/th_ing", false),
    ];
    for (name, hidden) in cases {
        assert_eq!(is_hidden_name(name), hidden, "{name}");
        assert_eq!(
            TopicName::new(name).expect("valid").is_hidden(),
            hidden,
            "{name}"
        );
        assert_eq!(
            ServiceName::new(name).expect("valid").is_hidden(),
            hidden,
            "{name}"
        );
    }
    assert!(NodeName::new("_ros2cli_123").expect("valid").is_hidden());
    assert!(!NodeName::new("talker_").expect("valid").is_hidden());
}
