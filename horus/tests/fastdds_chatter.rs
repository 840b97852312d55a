//! HORUS talker and listener against eProsima Fast DDS 2.9 (the DDS of `rmw_fastrtps_cpp`,
//! Jazzy's default RMW): the C++ peer `interop-tests/peers/fastdds/ros_participant.cpp` acting as
//! demo_nodes_cpp's listener and talker on `/chatter` (std_msgs/String, rclcpp's default QoS,
//! typehash USER_DATA, its node announced on `ros_discovery_info`), both directions, inside the
//! test network namespace. Each test has its own domain.

use std::collections::HashSet;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use horus::prelude::*;
use horus::ros::{Arguments, Context};
use interop_tests::fastdds::{self, ChatterCreated, FastDdsPeer};

const LIMIT: Duration = Duration::from_secs(30);

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .arguments(Arguments::default())
        .build()
        .expect("context")
}

/// The peer's endpoint is the one rmw_fastrtps_cpp would create for demo_nodes' chatter.
fn assert_chatter_endpoint(created: &ChatterCreated, mode: &str) {
    assert_eq!(created.vendor, "010f", "{created:?}");
    assert_eq!(created.mode, mode, "{created:?}");
    assert_eq!(created.topic, "rt/chatter", "{created:?}");
    assert_eq!(
        created.type_name, "std_msgs::msg::dds_::String_",
        "{created:?}"
    );
    let qos = &created.json["qos"];
    assert_eq!(qos["reliability"], "RELIABLE", "{created:?}");
    assert_eq!(qos["durability"], "VOLATILE", "{created:?}");
    assert_eq!(qos["history"], "KEEP_LAST", "{created:?}");
    assert_eq!(qos["depth"], 10, "{created:?}");
}

struct Talker {
    chatter: Topic<StringMsg>,
    count: u64,
}

impl Node for Talker {
    fn name(&self) -> &str {
        "talker"
    }
    fn tick(&mut self) {
        self.count += 1;
        self.chatter.send(StringMsg {
            data: format!("Hello World: {}", self.count),
        });
    }
}

#[test]
fn a_horus_talker_is_heard_by_a_fast_dds_listener() {
    let domain = 193;
    let mut peer =
        FastDdsPeer::start_listener(domain, "/", "listener", "/chatter", LIMIT, 3).expect("peer");
    let created = peer.chatter_created(LIMIT).expect("listener created");
    assert_chatter_endpoint(&created, "listen");
    let mut sched = Scheduler::new()
        .context(context(domain))
        .tick_rate(20_u64.hz())
        .print_report(false);
    sched
        .add(Talker {
            chatter: Topic::new("chatter").expect("topic"),
            count: 0,
        })
        .build()
        .expect("talker");
    let stop = sched.stop_handle();
    let runner = std::thread::spawn(move || sched.run().map_err(|e| e.to_string()));
    let deadline = Instant::now() + LIMIT;
    let mut heard = Vec::new();
    while heard.len() < 3 {
        match peer.next_heard(deadline.saturating_duration_since(Instant::now())) {
            Some(h) => heard.push(h),
            None => panic!(
                "the Fast DDS listener heard only {heard:?}: {}",
                peer.output()
            ),
        }
    }
    let (code, _) = peer.finish(LIMIT).expect("peer exit");
    stop.stop();
    assert_eq!(runner.join().expect("scheduler"), Ok(()));
    assert_eq!(code, Some(0), "{}", peer.output());
    // Consecutive messages of the one HORUS writer, in order (RELIABLE, KEEP_LAST 10).
    let numbers: Vec<u64> = heard
        .iter()
        .map(|h| {
            h.data
                .strip_prefix("Hello World: ")
                .and_then(|n| n.parse().ok())
                .unwrap_or_else(|| panic!("unexpected message {h:?}"))
        })
        .collect();
    assert!(numbers.windows(2).all(|w| w[1] == w[0] + 1), "{numbers:?}");
    assert!(
        heard.iter().all(|h| h.writer == heard[0].writer),
        "{heard:?}"
    );
}

struct Listener {
    chatter: Topic<StringMsg>,
    heard: mpsc::Sender<String>,
}

impl Node for Listener {
    fn name(&self) -> &str {
        "listener"
    }
    fn init(&mut self) -> Result<()> {
        self.chatter.connect_subscriber()?;
        Ok(())
    }
    fn tick(&mut self) {
        while let Some(m) = self.chatter.try_recv() {
            let _ = self.heard.send(m.data);
        }
    }
}

#[test]
fn a_horus_listener_hears_a_fast_dds_talker() {
    let domain = 194;
    let (tx, heard) = mpsc::channel();
    let mut sched = Scheduler::new()
        .context(context(domain))
        .tick_rate(100_u64.hz())
        .print_report(false);
    sched
        .add(Listener {
            chatter: Topic::new("chatter").expect("topic"),
            heard: tx,
        })
        .build()
        .expect("listener");
    let stop = sched.stop_handle();
    let runner = std::thread::spawn(move || {
        let outcome = sched.run().map_err(|e| e.to_string());
        (outcome, sched.get_node_metrics("listener"))
    });
    let mut peer =
        FastDdsPeer::start_talker(domain, "/", "talker", "/chatter", LIMIT, 0).expect("peer");
    let created = peer.chatter_created(LIMIT).expect("talker created");
    assert_chatter_endpoint(&created, "talk");
    let deadline = Instant::now() + LIMIT;
    let mut got = Vec::new();
    while got.len() < 3 {
        match heard.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(m) => got.push(m),
            Err(_) => panic!("heard only {got:?}"),
        }
    }
    peer.leave().expect("SIGTERM to the talker");
    let (code, rest) = peer.finish(LIMIT).expect("peer exit");
    stop.stop();
    let (outcome, metrics) = runner.join().expect("scheduler");
    assert_eq!(outcome, Ok(()));
    assert_eq!(code, Some(0), "{}", peer.output());
    // Everything heard is what the Fast DDS talker published.
    let published: HashSet<String> = rest.iter().filter_map(|l| fastdds::published(l)).collect();
    assert!(
        got.iter()
            .all(|m| m.starts_with("Hello World: ") && published.contains(m)),
        "heard {got:?}, published {published:?}"
    );
    assert!(metrics.expect("metrics").messages_received >= 3);
}
