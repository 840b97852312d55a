use crate::names::{DemangledTopic, ServiceName, TopicName};

// Prefixes and suffixes of rmw_fastrtps_shared_cpp (jazzy) namespace_prefix.cpp
// and rmw_cyclonedds_cpp rmw_node.cpp make_fqtopic; demangling as
// rmw_fastrtps_shared_cpp demangle.cpp.
#[test]
fn topic_mangling_round_trips() {
    for name in [
        "/chatter",
        "/ns/_hidden/x",
        "/parameter_events",
        "/fooRequest",
    ] {
        let topic = TopicName::new(name).expect("valid");
        let dds = topic.to_dds_topic_name(false);
        assert_eq!(dds, format!("rt{name}"));
        assert_eq!(
            DemangledTopic::from_dds_topic_name(&dds),
            DemangledTopic::Topic(topic.clone())
        );
        assert_eq!(topic.to_dds_topic_name(true), name);
    }
}

#[test]
fn service_mangling_round_trips() {
    for name in [
        "/add_two_ints",
        "/talker/get_parameters",
        "/Request",
        "/a/Reply",
    ] {
        let service = ServiceName::new(name).expect("valid");
        let request = service.to_dds_request_topic_name(false);
        let reply = service.to_dds_reply_topic_name(false);
        assert_eq!(request, format!("rq{name}Request"));
        assert_eq!(reply, format!("rr{name}Reply"));
        assert_eq!(
            DemangledTopic::from_dds_topic_name(&request),
            DemangledTopic::ServiceRequest(service.clone())
        );
        assert_eq!(
            DemangledTopic::from_dds_topic_name(&reply),
            DemangledTopic::ServiceReply(service.clone())
        );
        // avoid_ros_namespace_conventions drops the prefix, keeps the suffix
        assert_eq!(
            service.to_dds_request_topic_name(true),
            format!("{name}Request")
        );
        assert_eq!(
            service.to_dds_reply_topic_name(true),
            format!("{name}Reply")
        );
    }
}

#[test]
fn demangle_non_ros_topics() {
    let not_ros = [
        "ros_discovery_info",
        "chatter",
        "rt",
        "rtchatter",
        "rt/",
        "rt/with space",
        "rq/add_two_ints",
        "rq/add_two_intsRequestX",
        "rq/add_two_intsReply",
        "rr/add_two_intsRequest",
        "rr/Reply",
        "xx/chatter",
        "",
    ];
    for dds in not_ros {
        assert_eq!(
            DemangledTopic::from_dds_topic_name(dds),
            DemangledTopic::NotRos,
            "{dds:?}"
        );
    }
    let reply = DemangledTopic::from_dds_topic_name("rr/add_two_intsReply");
    assert_eq!(
        reply.service_name().map(ServiceName::as_str),
        Some("/add_two_ints")
    );
    assert_eq!(reply.topic_name(), None);
}
