//! Exercises the Cyclone DDS backend of horus-ros-rmw end to end and tears everything down; run
//! under valgrind by `tests/cyclone_leakcheck.rs`. Per round: a context on `Backend::Cyclone`
//! (participant, `ros_discovery_info` writer), a node, a typed publisher and subscription, a raw
//! writer and reader, a discovery feed (built-in topics, `ros_discovery_info`, matches); it waits
//! for both matches, exchanges a few samples each way, then drops everything. Two rounds, so a
//! context torn down and created again is covered too.
//!
//! Domain 149, loopback only (`CYCLONEDDS_URI` is set to a loopback configuration when unset):
//! run inside `scripts/isolated`, e.g.
//! `cargo build -p horus-ros-rmw --features cyclone --example cyclone_leakcheck &&
//! scripts/isolated target/debug/examples/cyclone_leakcheck`.

use std::time::{Duration, Instant};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::{Message, TypeHash};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Backend, Context, DiscoveryEvent, Gid, RawEndpointSpec};

const DOMAIN: u32 = 149;
const ROUNDS: usize = 2;
const SAMPLES: usize = 5;
/// Cyclone DDS on loopback, with multicast (the private namespace has no other interface).
const LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

type Error = Box<dyn std::error::Error>;

fn main() -> Result<(), Error> {
    // Before any thread exists.
    if std::env::var_os("CYCLONEDDS_URI").is_none() {
        std::env::set_var("CYCLONEDDS_URI", LOOPBACK);
    }
    for round in 0..ROUNDS {
        run(round)?;
    }
    println!("cyclone_leakcheck: ok");
    Ok(())
}

fn run(round: usize) -> Result<(), Error> {
    let deadline = Instant::now() + Duration::from_secs(90);
    let context = Context::builder()
        .domain_id(DOMAIN)
        .backend(Backend::Cyclone)
        .enclave("/leakcheck")
        .build()?;
    assert_eq!(context.backend(), Some(Backend::Cyclone));
    let node = context.create_node("leakcheck", "/")?;
    let mut feed = context.discovery_feed()?;

    let qos = Qos::default();
    let publisher = node.create_publisher::<Time>("leakcheck_time", &qos)?;
    let mut subscription = node.create_subscription::<Time>("leakcheck_time", &qos)?;
    let spec = RawEndpointSpec {
        dds_topic_name: "rt/leakcheck_raw".to_owned(),
        dds_type_name: Time::dds_type_name(),
        type_hash: TypeHash::ZERO,
        qos: Qos::services_default(),
        service_id: None,
    };
    let writer = node.create_raw_writer(&spec)?;
    let mut reader = node.create_raw_reader(&spec)?;

    // Both writers matched with their readers, as the feed reports it (events of the built-in
    // topics and ros_discovery_info are taken along the way).
    let mut wanted: Vec<(Gid, Gid)> = vec![
        (publisher.gid(), subscription.gid()),
        (writer.gid(), reader.gid()),
    ];
    let mut events = 0usize;
    while !wanted.is_empty() {
        if Instant::now() > deadline {
            return Err(format!("no match within the deadline: {wanted:?} missing").into());
        }
        if let Some(event) = feed.next_timeout(Duration::from_millis(200)) {
            events += 1;
            if let DiscoveryEvent::Matched { local, remote } = event {
                wanted.retain(|&pair| pair != (local, remote));
            }
        }
    }

    let mut typed = 0usize;
    let mut raw = 0usize;
    for i in 0..SAMPLES {
        publisher.publish(Time {
            sec: i as i32,
            nanosec: 7,
        })?;
        // The CDR body of a Time (after the encapsulation header), little-endian.
        let mut body = (i as i32).to_le_bytes().to_vec();
        body.extend_from_slice(&7u32.to_le_bytes());
        writer.write(body, None, None)?;
    }
    while typed < SAMPLES || raw < SAMPLES {
        if Instant::now() > deadline {
            return Err(format!("only {typed} typed and {raw} raw samples").into());
        }
        reader.wait(Duration::from_millis(50));
        while let Some(time) = subscription.try_take()? {
            assert_eq!(time.nanosec, 7);
            typed += 1;
        }
        while let Some(sample) = reader.take()? {
            assert_eq!(sample.body.len(), 8);
            assert_eq!(sample.id.writer, writer.gid());
            raw += 1;
        }
        while feed.try_next().is_some() {
            events += 1;
        }
    }
    println!(
        "cyclone_leakcheck: round {round}: {typed} typed and {raw} raw samples, {events} \
         discovery events"
    );

    // Endpoints first, then the feed, the node and the context.
    drop(reader);
    drop(writer);
    drop(subscription);
    drop(publisher);
    while feed.try_next().is_some() {}
    drop(feed);
    drop(node);
    drop(context);
    Ok(())
}
