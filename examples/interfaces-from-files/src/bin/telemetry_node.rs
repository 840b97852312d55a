//! A robot's telemetry node, with the types generated from the example's own package
//! `horus_demo_msgs` (see build.rs): publishes `horus_demo_msgs/msg/Telemetry` on `telemetry`
//! ten times a second and serves `horus_demo_msgs/srv/SetMode` on `set_mode`, whose accepted
//! requests change the mode the telemetry reports.
//!
//! ```text
//! cargo run -p horus-ros-example-interfaces --bin telemetry_node
//! cargo run -p horus-ros-example-interfaces --bin telemetry_monitor -- --set 1 "go"
//! ```
//!
//! Usage: `telemetry_node [--name NAME] [--cells N] [--serve N]`. It runs until SIGINT (Ctrl+C)
//! or SIGTERM, or with `--serve N` until it has answered N requests. The domain comes from
//! `ROS_DOMAIN_ID`. A telemetry with more battery cells than `cell_voltages` allows
//! (`float32[<=8]`, `--cells 9`) is refused when it is encoded, with the typed error
//! `CdrError::BoundExceeded`: the node says so and exits with status 3.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

use horus_ros_example_interfaces::horus_demo_msgs::msg::Telemetry;
use horus_ros_example_interfaces::horus_demo_msgs::srv::{SetMode, SetModeResponse};
use horus_ros_example_interfaces::{mode_name, telemetry};
use horus_ros_msgs::cdr::CdrError;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{PublishError, SampleError};
use horus_ros_services::prelude::*;

/// The publication period.
const PERIOD: Duration = Duration::from_millis(100);

/// How long the node stays after its last request with `--serve` (the reply, sent reliably, is
/// delivered before the participant leaves).
const LINGER: Duration = Duration::from_millis(500);

const USAGE: &str = "Usage: telemetry_node [--name NAME] [--cells N] [--serve N]
  --name NAME    the robot's name in the telemetry (default: horus; at most 32 bytes)
  --cells N      how many battery cells to report (default: 4; the message allows 8)
  --serve N      exit after answering N SetMode requests (default: run until Ctrl+C)";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let options = Options::parse(std::env::args().skip(1)).unwrap_or_else(|message| {
        eprintln!("{message}\n\n{USAGE}");
        std::process::exit(2);
    });

    let context = Context::from_env()?;
    let node = context.create_node("telemetry_node", "/")?;
    let publisher = node.create_publisher::<Telemetry>("telemetry", &Qos::default_profile())?;

    let mode = Arc::new(AtomicU8::new(Telemetry::MODE_IDLE));
    let current = Arc::clone(&mode);
    let server = ServiceServer::<SetMode>::builder()
        .node(&node)
        .name("set_mode")
        .on_request(move |request| {
            let previous = current.load(Ordering::Relaxed);
            let accepted = mode_name(request.mode) != "unknown";
            if accepted {
                current.store(request.mode, Ordering::Relaxed);
            }
            let message = if accepted {
                format!(
                    "{} -> {} ({})",
                    mode_name(previous),
                    mode_name(request.mode),
                    request.reason
                )
            } else {
                format!("no mode {}", request.mode)
            };
            println!("[INFO] [telemetry_node]: SetMode: {message}");
            Ok(SetModeResponse {
                accepted,
                previous_mode: previous,
                message,
            })
        })
        .build()?;
    println!("[INFO] [telemetry_node]: publishing on /telemetry, serving /set_mode");

    for sequence in 1.. {
        let mut message = telemetry(&options.name, sequence, options.cells);
        message.mode = mode.load(Ordering::Relaxed);
        match publisher.publish(message) {
            Ok(()) => {}
            // A bound of the message exceeded: nothing was sent; the error says which field.
            Err(PublishError {
                cause: SampleError::Cdr(CdrError::BoundExceeded(bound)),
                ..
            }) => {
                eprintln!("[ERROR] [telemetry_node]: telemetry not published: {bound}");
                std::process::exit(3);
            }
            Err(e) => return Err(e.into()),
        }
        if options.serve.is_some_and(|n| server.served_count() >= n) {
            std::thread::sleep(LINGER);
            break;
        }
        // Like a timer of rclcpp: sleeps a period, and wakes at once on SIGINT or SIGTERM.
        if context.wait_for_shutdown(PERIOD) {
            break;
        }
    }
    Ok(())
}

/// The command line.
struct Options {
    name: String,
    cells: usize,
    serve: Option<u64>,
}

impl Options {
    fn parse(mut args: impl Iterator<Item = String>) -> Result<Self, String> {
        let mut options = Options {
            name: "horus".to_owned(),
            cells: 4,
            serve: None,
        };
        while let Some(arg) = args.next() {
            let mut value = |what: &str| args.next().ok_or(format!("{arg} needs {what}"));
            match arg.as_str() {
                "-h" | "--help" => {
                    println!("{USAGE}");
                    std::process::exit(0);
                }
                "--name" => options.name = value("a name")?,
                "--cells" => {
                    let n = value("a number")?;
                    options.cells = n.parse().map_err(|_| format!("not a count: {n}"))?;
                }
                "--serve" => {
                    let n = value("a number")?;
                    options.serve = Some(n.parse().map_err(|_| format!("not a count: {n}"))?);
                }
                other => return Err(format!("unexpected argument: {other}")),
            }
        }
        Ok(options)
    }
}
