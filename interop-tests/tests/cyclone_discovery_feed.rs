//! Our discovery feed against a Cyclone DDS peer that joins the graph as a ROS 2 participant:
//! we see its participant (vendor Cyclone), its endpoints with their topic, type and the type hash
//! from USER_DATA, its `ros_discovery_info` message, and its endpoints leaving with it.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::EndpointKind;
use horus_ros_rmw::{Context, DiscoveryEvent, VendorId};
use interop_tests::{cyclone_config, peer_script, python};
use serde_json::Value;

const DOMAIN: u32 = 51;

#[test]
fn feed_reports_a_cyclone_ros_participant() {
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("feed");
    assert!(context.discovery_feed().is_err(), "one feed per context");
    let hash = Time::type_hash().to_string();

    let mut child = Command::new(python())
        .arg(peer_script("cyclone_ros_participant.py"))
        .args([&DOMAIN.to_string(), "/peer_ns", "cyclone_node", &hash, "3"])
        .env("CYCLONEDDS_URI", cyclone_config())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start the Cyclone DDS peer");
    let mut line = String::new();
    let stdout = child.stdout.take().expect("piped stdout");
    BufReader::new(stdout)
        .read_line(&mut line)
        .expect("peer prints what it created");
    let created: Value = serde_json::from_str(line.trim()).expect("JSON line");
    let (participant, writer, reader) = (
        created["participant"]
            .as_str()
            .unwrap_or_default()
            .to_owned(),
        created["writer"].as_str().unwrap_or_default().to_owned(),
        created["reader"].as_str().unwrap_or_default().to_owned(),
    );

    let mut saw_participant = false;
    let mut saw_writer = false;
    let mut saw_reader = false;
    let mut saw_info = false;
    let mut saw_lost = false;
    let deadline = Instant::now() + Duration::from_secs(20);
    while !(saw_participant && saw_writer && saw_reader && saw_info && saw_lost) {
        assert!(
            Instant::now() < deadline,
            "not everything seen within 20 s: participant={saw_participant} writer={saw_writer} \
             reader={saw_reader} ros_discovery_info={saw_info} lost={saw_lost}"
        );
        // Woken by the next discovery event (or at the deadline).
        let Some(event) = feed.next_timeout(deadline.saturating_duration_since(Instant::now()))
        else {
            continue;
        };
        match event {
            DiscoveryEvent::ParticipantDiscovered(p) if p.gid.to_string() == participant => {
                assert_eq!(p.vendor_id, VendorId::CYCLONE_DDS);
                saw_participant = true;
            }
            DiscoveryEvent::EndpointDiscovered(e) if e.gid.to_string() == writer => {
                assert_eq!(e.kind, EndpointKind::Writer);
                assert_eq!(e.dds_topic_name, "rt/peer_ns/chatter");
                assert_eq!(e.dds_type_name, "builtin_interfaces::msg::dds_::Time_");
                assert_eq!(e.user_data, format!("typehash={hash};").into_bytes());
                assert_eq!(e.type_hash.to_string(), hash);
                assert_eq!(e.participant_gid.to_string(), participant);
                saw_writer = true;
            }
            DiscoveryEvent::EndpointDiscovered(e) if e.gid.to_string() == reader => {
                assert_eq!(e.kind, EndpointKind::Reader);
                assert_eq!(e.dds_topic_name, "rt/peer_ns/echo");
                assert_eq!(e.type_hash.to_string(), hash);
                saw_reader = true;
            }
            DiscoveryEvent::ParticipantEntities(info) if info.gid.to_string() == participant => {
                let node = &info.node_entities_info_seq[0];
                assert_eq!(
                    (node.node_namespace.as_str(), node.node_name.as_str()),
                    ("/peer_ns", "cyclone_node")
                );
                let writers: Vec<String> = node
                    .writer_gid_seq
                    .iter()
                    .map(ToString::to_string)
                    .collect();
                let readers: Vec<String> = node
                    .reader_gid_seq
                    .iter()
                    .map(ToString::to_string)
                    .collect();
                assert_eq!(writers, vec![writer.clone()]);
                assert_eq!(readers, vec![reader.clone()]);
                saw_info = true;
            }
            // The peer exits cleanly after 3 s: its writer must be reported lost.
            DiscoveryEvent::EndpointLost { gid, .. } if gid.to_string() == writer => {
                saw_lost = true
            }
            DiscoveryEvent::ParticipantLost { gid } if gid.to_string() == participant => {
                saw_lost = true
            }
            _ => {}
        }
    }
    let _ = child.wait();
}
