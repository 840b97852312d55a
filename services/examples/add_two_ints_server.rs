//! A horus-ros port of ROS 2's `demo_nodes_cpp` `add_two_ints_server`.
//!
//! Node `add_two_ints_server` serves `example_interfaces/srv/AddTwoInts` on `add_two_ints`
//! (resolved to `/add_two_ints`) and logs each request as the ROS demo does. Any ROS 2 Jazzy
//! client can call it, on either RMW:
//!
//! ```text
//! cargo run -p horus-ros-services --example add_two_ints_server
//! ros2 run demo_nodes_cpp add_two_ints_client          # or our add_two_ints_client example
//! ros2 service call /add_two_ints example_interfaces/srv/AddTwoInts "{a: 2, b: 3}"
//! ```
//!
//! Usage: `add_two_ints_server [-s SERVICE] [--count N] [--introspection STATE]`. It serves until
//! SIGINT (Ctrl+C) or SIGTERM shuts its context down, then leaves the graph and exits with 0 (as
//! rclcpp's demo does after `rclcpp::spin` returns), or, with `--count N`, until it has answered
//! N requests. The domain comes from
//! `ROS_DOMAIN_ID`. `--introspection metadata|contents` publishes service events on
//! `/add_two_ints/_service_event` as Jazzy's `demo_nodes_cpp` `introspection_service` does with
//! `service_configure_introspection` set (same states, system-default QoS); watch them with
//! `horus-ros service echo /add_two_ints` or `ros2 service echo /add_two_ints`.

use std::sync::mpsc;
use std::time::{SystemTime, UNIX_EPOCH};

use horus_ros_rmw::qos::Qos;
use horus_ros_services::prelude::*;

/// How long the server stays up after its last request with `--count` (so the reply, sent
/// reliably, is surely delivered before the participant leaves).
const LINGER: Duration = Duration::from_millis(500);

fn main() -> horus_ros_services::Result<()> {
    let options = match Options::parse(std::env::args().skip(1)) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("{message}\n\n{USAGE}");
            std::process::exit(2);
        }
    };

    let context = Context::from_env()?;
    let node = context.create_node("add_two_ints_server", "/")?;
    // As every rclcpp node: parameter services and ~/get_type_description.
    let node_services = horus_ros_services::NodeServices::start(&node)?;
    // Described by ~/get_type_description, as rcl does for the types a node uses.
    node_services.register_service::<AddTwoInts>();

    let (served, requests_served) = mpsc::channel::<()>();
    let log_node = node.clone();
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name(options.service.as_str())
        .introspection(options.introspection, Qos::system_default())
        .on_request(move |request| {
            info(
                &log_node,
                &format!("Incoming request\na: {} b: {}", request.a, request.b),
            );
            let _ = served.send(());
            Ok(AddTwoIntsResponse {
                // ROS's demo adds with C++ int64 wrap-around; so do we (no panic on overflow).
                sum: request.a.wrapping_add(request.b),
            })
        })
        .build()?;

    match options.count {
        // Like `rclcpp::spin`: serve until SIGINT or SIGTERM shuts the context down; the
        // participant leaves every peer's graph as `context` and the rest are dropped below.
        None => {
            context.wait_for_shutdown(None);
        }
        Some(count) => {
            for _ in 0..count {
                if requests_served.recv().is_err() {
                    break;
                }
            }
            std::thread::sleep(LINGER);
        }
    }
    Ok(())
}

const USAGE: &str = "Usage: add_two_ints_server [-s SERVICE] [--count N] [--introspection STATE]
  -s SERVICE               the service name (default: add_two_ints)
  --count N                exit after answering N requests (default: serve until Ctrl+C)
  --introspection STATE    off (default), metadata or contents: publish service events";

/// The command line.
struct Options {
    service: String,
    count: Option<u64>,
    introspection: IntrospectionState,
}

impl Options {
    fn parse(mut args: impl Iterator<Item = String>) -> Result<Self, String> {
        let mut options = Options {
            service: "add_two_ints".to_owned(),
            count: None,
            introspection: IntrospectionState::Off,
        };
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "-h" | "--help" => {
                    println!("{USAGE}");
                    std::process::exit(0);
                }
                "-s" => options.service = args.next().ok_or("-s needs a service name")?,
                "--count" => {
                    let n = args.next().ok_or("--count needs a number")?;
                    let n = n.parse().map_err(|_| format!("not a count: {n}"))?;
                    options.count = Some(n);
                }
                "--introspection" => {
                    let state = args.next().ok_or("--introspection needs a state")?;
                    options.introspection = state.parse()?;
                }
                other => return Err(format!("unexpected argument: {other}")),
            }
        }
        Ok(options)
    }
}

/// Logs as rclcpp's default console format does: `[INFO] [seconds.nanoseconds] [node]: message`.
fn info(node: &Node, message: &str) {
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    println!(
        "[INFO] [{}.{:09}] [{}]: {message}",
        now.as_secs(),
        now.subsec_nanos(),
        node.name().as_str()
    );
}
