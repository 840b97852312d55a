//! `Display` of endpoint info, against rclpy's `__str__` text.

use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::Qos;

use super::fixtures::*;
use crate::{ServiceEndpointInfo, ServiceEndpointType, TopicEndpointInfo, TopicEndpointType};

const GID_A: [u8; 16] = [1, 15, 200, 182, 254, 67, 179, 68, 0, 0, 0, 0, 0, 0, 14, 4];
const GID_B: [u8; 16] = [1, 15, 200, 182, 254, 67, 179, 68, 0, 0, 0, 0, 0, 0, 15, 3];

fn add_two_ints_request_hash() -> TypeHash {
    match TypeHash::parse("RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302")
    {
        Ok(h) => h,
        Err(e) => panic!("bad test hash: {e}"),
    }
}

#[test]
fn topic_endpoint_info_like_rclpy() {
    let info = TopicEndpointInfo {
        node_name: "talker".to_owned(),
        node_namespace: "/".to_owned(),
        topic_type: "std_msgs/msg/String".to_owned(),
        topic_type_hash: TypeHash::ZERO,
        endpoint_type: TopicEndpointType::Publisher,
        endpoint_gid: crate::Gid::from_bytes(GID_A),
        qos_profile: remote_qos(),
    };
    assert_eq!(
        info.to_string(),
        "Node name: talker\n\
         Node namespace: /\n\
         Topic type: std_msgs/msg/String\n\
         Topic type hash: INVALID\n\
         Endpoint type: PUBLISHER\n\
         GID: 01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04\n\
         QoS profile:\n  \
           Reliability: RELIABLE\n  \
           History (Depth): UNKNOWN\n  \
           Durability: VOLATILE\n  \
           Lifespan: Infinite\n  \
           Deadline: Infinite\n  \
           Liveliness: AUTOMATIC\n  \
           Liveliness lease duration: Infinite"
    );
    let sub = TopicEndpointInfo {
        topic_type_hash: add_two_ints_request_hash(),
        endpoint_type: TopicEndpointType::Subscription,
        qos_profile: Qos::default_profile(),
        ..info
    };
    let text = sub.to_string();
    assert!(text.contains(
        "\nTopic type hash: RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302\n"
    ));
    assert!(text.contains("\nEndpoint type: SUBSCRIPTION\n"));
    assert!(text.contains("\n  History (Depth): KEEP_LAST (10)\n"));
}

fn server_info() -> ServiceEndpointInfo {
    let mut writer_qos = remote_qos();
    writer_qos.durability = horus_ros_rmw::qos::DurabilityPolicy::TransientLocal;
    ServiceEndpointInfo {
        node_name: "add_two_ints_server".to_owned(),
        node_namespace: "/".to_owned(),
        service_type: "example_interfaces/srv/AddTwoInts".to_owned(),
        service_type_hash: TypeHash::ZERO,
        endpoint_type: ServiceEndpointType::Server,
        endpoint_gids: vec![crate::Gid::from_bytes(GID_A), crate::Gid::from_bytes(GID_B)],
        qos_profiles: vec![remote_qos(), writer_qos],
        endpoint_type_hashes: vec![TypeHash::ZERO, TypeHash::ZERO],
    }
}

#[test]
fn server_info_like_rclpy() {
    assert_eq!(
        server_info().to_string(),
        "Node name: add_two_ints_server\n\
         Node namespace: /\n\
         Service type: example_interfaces/srv/AddTwoInts\n\
         Service type hash: INVALID\n\
         Endpoint type: SERVER\n\
         Endpoint count: 2\n\
         GIDs:\n \
         - Request Reader : 01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04\n \
         - Response Writer : 01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0f.03\n\
         QoS profiles:\n \
         - Request Reader :\n      \
               Reliability: RELIABLE\n      \
               History (Depth): UNKNOWN (0)\n      \
               Durability: VOLATILE\n      \
               Lifespan: Infinite\n      \
               Deadline: Infinite\n      \
               Liveliness: AUTOMATIC\n      \
               Liveliness lease duration: Infinite\n \
         - Response Writer :\n      \
               Reliability: RELIABLE\n      \
               History (Depth): UNKNOWN (0)\n      \
               Durability: TRANSIENT_LOCAL\n      \
               Lifespan: Infinite\n      \
               Deadline: Infinite\n      \
               Liveliness: AUTOMATIC\n      \
               Liveliness lease duration: Infinite"
    );
}

#[test]
fn client_info_prints_writer_first() {
    let client = ServiceEndpointInfo {
        endpoint_type: ServiceEndpointType::Client,
        service_type_hash: add_two_ints_request_hash(),
        ..server_info()
    };
    let text = client.to_string();
    assert!(text.contains("\nEndpoint type: CLIENT\n"));
    assert!(text.contains(
        "\nService type hash: RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302\n"
    ));
    // gids[1] is the request writer, gids[0] the response reader.
    assert!(text.contains(
        "GIDs:\n \
         - Request Writer : 01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0f.03\n \
         - Response Reader : 01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04\n\
         QoS profiles:\n \
         - Request Writer :\n      \
               Reliability: RELIABLE\n      \
               History (Depth): UNKNOWN (0)\n      \
               Durability: TRANSIENT_LOCAL\n"
    ));
    assert!(text.contains("\n - Response Reader :\n      Reliability: RELIABLE\n"));
}

#[test]
fn single_endpoint_service_info_like_rclpy() {
    let info = ServiceEndpointInfo {
        endpoint_gids: vec![crate::Gid::from_bytes(GID_A)],
        qos_profiles: vec![Qos::services_default()],
        endpoint_type_hashes: vec![TypeHash::ZERO],
        ..server_info()
    };
    assert!(info.to_string().ends_with(
        "Endpoint count: 1\n\
         GID: 01.0f.c8.b6.fe.43.b3.44.00.00.00.00.00.00.0e.04\n\
         QoS profile:\n  \
           Reliability: RELIABLE\n  \
           History (Depth): KEEP_LAST (10)\n  \
           Durability: VOLATILE\n  \
           Lifespan: 0 nanoseconds\n  \
           Deadline: 0 nanoseconds\n  \
           Liveliness: SYSTEM_DEFAULT\n  \
           Liveliness lease duration: 0 nanoseconds"
    ));
}

#[test]
fn cache_output_prints() {
    let g = sample_graph();
    let Ok(servers) = g.servers_info_by_service("/add_two_ints", false) else {
        panic!("servers query failed");
    };
    let text = servers[0].to_string();
    assert!(text.starts_with("Node name: server\nNode namespace: /\n"));
    assert!(text.contains(" - Request Reader : "));
}
