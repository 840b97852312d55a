//! Joins the graph with one node and reports whether another node shows up on
//! `ros_discovery_info`. The discovery-range tests (`tests/discovery_range.rs`) run two of these,
//! one per process, since a process configures each DDS domain once.
//!
//! usage: `discovery_probe <own node> <node to look for> <seconds>` — prints `seen` as soon as the
//! other node is announced, or `unseen` when `<seconds>` have passed; it keeps its own node on the
//! graph until then, or for one more second after `seen`, so that the other probe can see it. The context comes from the
//! environment (`HORUS_ROS_BACKEND`, `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE`,
//! `ROS_STATIC_PEERS`, `CYCLONEDDS_URI`). Run it inside a private network namespace.

use std::time::{Duration, Instant};

use horus_ros_rmw::{Context, DiscoveryEvent};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, own, wanted, seconds] = args.as_slice() else {
        return Err("usage: discovery_probe <own node> <node to look for> <seconds>".into());
    };
    let end = Instant::now() + Duration::from_secs_f64(seconds.parse()?);
    let context = Context::from_env()?;
    let _node = context.create_node(own, "/")?;
    let mut feed = context.discovery_feed()?;
    let mut seen = false;
    while !seen {
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        if let Some(DiscoveryEvent::ParticipantEntities(info)) = feed.next_timeout(left) {
            seen = info.gid != context.gid()
                && info
                    .node_entities_info_seq
                    .iter()
                    .any(|n| &n.node_name == wanted);
        }
    }
    println!("{}", if seen { "seen" } else { "unseen" });
    // Stay on the graph a little longer, for the other probe.
    let linger = end.min(Instant::now() + Duration::from_secs(1));
    std::thread::sleep(linger.saturating_duration_since(Instant::now()));
    Ok(())
}
