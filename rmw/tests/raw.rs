//! Raw endpoints: bodies, sample identities, related_sample_identity and matching.

use std::time::{Duration, Instant};

use horus_ros_msgs::{Message, TypeHash};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Context, RawEndpointSpec, SampleId};

const DOMAIN: u32 = 38;

fn spec(topic: &str) -> RawEndpointSpec {
    RawEndpointSpec {
        dds_topic_name: topic.to_owned(),
        dds_type_name: horus_ros_msgs::builtin_interfaces::msg::Time::dds_type_name(),
        type_hash: TypeHash::ZERO,
        qos: Qos::services_default(),
    }
}

#[test]
fn raw_samples_carry_identity_and_related_identity() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("raw", "/").expect("node");
    let mut writer = node
        .create_raw_writer(&spec("rq/rawRequest"))
        .expect("writer");
    let mut reader = node
        .create_raw_reader(&spec("rq/rawRequest"))
        .expect("reader");
    assert!(
        writer.wait_for_reader(reader.gid(), Duration::from_secs(10)),
        "writer never matched the reader"
    );

    let related = SampleId {
        writer: reader.gid(),
        sequence_number: SampleId::UNKNOWN_SEQUENCE_NUMBER,
    };
    let body = vec![1, 0, 0, 0, 2, 0, 0, 0];
    let sent = writer
        .write(body.clone(), Some(related), None)
        .expect("write");
    assert_eq!(sent.writer, writer.gid());
    let second = writer
        .write(vec![9, 9, 9, 9], None, Some(reader.gid()))
        .expect("write to one reader");
    assert_eq!(second.sequence_number, sent.sequence_number + 1);

    let deadline = Instant::now() + Duration::from_secs(10);
    let mut got = Vec::new();
    while got.len() < 2 {
        assert!(Instant::now() < deadline, "samples did not arrive: {got:?}");
        match reader.take().expect("take") {
            Some(s) => got.push(s),
            None => {
                reader.wait(Duration::from_millis(100));
            }
        }
    }
    assert_eq!(got[0].body, body);
    assert!(!got[0].big_endian);
    assert_eq!(got[0].id, sent);
    assert_eq!(got[0].related, Some(related));
    assert_eq!(got[1].id, second);
    assert_eq!(got[1].related, None);
    assert!(reader.matched_writers().contains(&writer.gid()));
}
