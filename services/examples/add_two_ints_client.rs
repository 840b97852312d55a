//! A horus-ros port of ROS 2's `demo_nodes_cpp` `add_two_ints_client`.
//!
//! Node `add_two_ints_client` waits for the service `add_two_ints` (resolved to
//! `/add_two_ints`), logging `service not available, waiting again...` each second, calls it once
//! and logs the sum. It talks to any ROS 2 Jazzy `example_interfaces/srv/AddTwoInts` server, on
//! either RMW:
//!
//! ```text
//! ros2 run demo_nodes_cpp add_two_ints_server          # or our add_two_ints_server example
//! cargo run -p horus-ros-services --example add_two_ints_client -- 40 2
//! ```
//!
//! Usage: `add_two_ints_client [-s SERVICE] [--introspection STATE] [A B]` (default 2 3, as in
//! the ROS demo). Exits 0 with the result, 1 if no server showed up within 30 s or the call
//! failed. The domain comes from `ROS_DOMAIN_ID`. `--introspection metadata|contents` publishes
//! the call's service events on `/add_two_ints/_service_event` as Jazzy's `demo_nodes_cpp`
//! `introspection_client` does with `client_configure_introspection` set.

use std::time::{Instant, SystemTime, UNIX_EPOCH};

use horus_ros_rmw::qos::Qos;
use horus_ros_services::prelude::*;

/// How long to wait for a server before giving up (rclcpp's demo waits forever).
const SERVICE_WAIT_LIMIT: Duration = Duration::from_secs(30);

/// How long the call may take once a server is there.
const CALL_TIMEOUT: Duration = Duration::from_secs(10);

/// With introspection on, how long the node stays after the call so that its events (sent
/// reliably) reach subscribers before the participant leaves.
const EVENT_LINGER: Duration = Duration::from_millis(500);

fn main() -> horus_ros_services::Result<()> {
    let options = match Options::parse(std::env::args().skip(1)) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("{message}\n\n{USAGE}");
            std::process::exit(2);
        }
    };

    let context = Context::from_env()?;
    let node = context.create_node("add_two_ints_client", "/")?;
    // As every rclcpp node: parameter services and ~/get_type_description.
    let _node_services = horus_ros_services::NodeServices::start(&node)?;
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name(options.service.as_str())
        .introspection(options.introspection, Qos::system_default())
        .build()?;

    let request = AddTwoIntsRequest {
        a: options.a,
        b: options.b,
    };

    // rclcpp: `while (!client->wait_for_service(1s)) { RCLCPP_INFO(..., "service not available, waiting again..."); }`
    let started = Instant::now();
    while !client.wait_for_service(Duration::from_secs(1)) {
        if started.elapsed() >= SERVICE_WAIT_LIMIT {
            log(
                "ERROR",
                &node,
                &format!(
                    "service {} not available after {} s. Exiting.",
                    client.name().as_str(),
                    SERVICE_WAIT_LIMIT.as_secs()
                ),
            );
            std::process::exit(1);
        }
        log("INFO", &node, "service not available, waiting again...");
    }

    let result = client.call(request, CALL_TIMEOUT);
    if options.introspection != IntrospectionState::Off {
        std::thread::sleep(EVENT_LINGER);
    }
    match result {
        Ok(response) => {
            log(
                "INFO",
                &node,
                &format!("Result of add_two_ints: {}", response.sum),
            );
            Ok(())
        }
        Err(error) => {
            log(
                "ERROR",
                &node,
                &format!("call to {} failed: {error}", client.name().as_str()),
            );
            std::process::exit(1);
        }
    }
}

const USAGE: &str = "Usage: add_two_ints_client [-s SERVICE] [--introspection STATE] [A B]
  -s SERVICE               the service name (default: add_two_ints)
  --introspection STATE    off (default), metadata or contents: publish service events
  A B                      the two integers to add (default: 2 3)";

/// The command line.
struct Options {
    service: String,
    introspection: IntrospectionState,
    a: i64,
    b: i64,
}

impl Options {
    fn parse(mut args: impl Iterator<Item = String>) -> Result<Self, String> {
        let mut service = "add_two_ints".to_owned();
        let mut introspection = IntrospectionState::Off;
        let mut numbers = Vec::new();
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "-h" | "--help" => {
                    println!("{USAGE}");
                    std::process::exit(0);
                }
                "-s" => service = args.next().ok_or("-s needs a service name")?,
                "--introspection" => {
                    let state = args.next().ok_or("--introspection needs a state")?;
                    introspection = state.parse()?;
                }
                "--" => {}
                number => numbers.push(
                    number
                        .parse::<i64>()
                        .map_err(|_| format!("not an integer: {number}"))?,
                ),
            }
        }
        let (a, b) = match numbers[..] {
            [] => (2, 3),
            [a, b] => (a, b),
            _ => return Err("give two integers A B, or none".to_owned()),
        };
        Ok(Self {
            service,
            introspection,
            a,
            b,
        })
    }
}

/// Logs as rclcpp's default console format does: `[SEVERITY] [seconds.nanoseconds] [node]: message`
/// (errors to stderr).
fn log(severity: &str, node: &Node, message: &str) {
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    let line = format!(
        "[{severity}] [{}.{:09}] [{}]: {message}",
        now.as_secs(),
        now.subsec_nanos(),
        node.name().as_str()
    );
    if severity == "ERROR" {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
}
