//! A participant survives signals: rustdds' threads stop on an interrupted wait (EINTR), so a
//! SIGCHLD from a child process that exits while `Command::spawn` has signals blocked must not
//! reach them (the context starts them with asynchronous signals blocked). On the Cyclone backend
//! (whose threads retry interrupted waits) the participant must survive all the same.

use std::process::Command;
use std::time::{Duration, Instant};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Backend, Context, DiscoveryEvent};

const DOMAIN: u32 = 39;

/// How many threads of this process rustdds runs (they are named "RustDDS …").
fn rustdds_threads() -> usize {
    std::fs::read_dir("/proc/self/task")
        .map(|tasks| {
            tasks
                .filter_map(Result::ok)
                .filter(|t| {
                    std::fs::read_to_string(t.path().join("comm"))
                        .is_ok_and(|c| c.starts_with("RustDDS"))
                })
                .count()
        })
        .unwrap_or(0)
}

#[test]
fn fast_exiting_children_do_not_take_the_participant_off_the_graph() {
    let a = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context a");
    let node = a.create_node("survivor", "/").expect("node");
    let publisher = node
        .create_publisher::<Time>("alive", &Qos::default())
        .expect("publisher");
    let on_rustdds = a.backend() == Some(Backend::RustDds);
    let dds_threads = rustdds_threads();
    assert_eq!(
        dds_threads > 0,
        on_rustdds,
        "rustdds' threads (named 'RustDDS…') run exactly when the backend is rustdds"
    );
    // Children that exit at once: their SIGCHLD is often pending while the spawning thread still
    // blocks signals, and then goes to any other thread. Several spawning threads widen the window.
    let spawners: Vec<_> = (0..4)
        .map(|_| {
            std::thread::spawn(|| {
                for _ in 0..150 {
                    Command::new("true").status().expect("run `true`");
                }
            })
        })
        .collect();
    for s in spawners {
        s.join().expect("spawner");
    }
    assert_eq!(
        rustdds_threads(),
        dds_threads,
        "a rustdds thread ended: a signal interrupted its wait"
    );
    let b = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context b");
    let mut feed = b.discovery_feed().expect("feed");
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        assert!(
            Instant::now() < deadline,
            "a's writer was never discovered: its DDS threads are gone"
        );
        if let Some(DiscoveryEvent::EndpointDiscovered(e)) =
            feed.next_timeout(Duration::from_millis(100))
        {
            if e.gid == publisher.gid() {
                break;
            }
        }
    }
}
