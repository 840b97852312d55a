//! Watches a robot's telemetry and changes its mode, with the types generated from the
//! example's own package `horus_demo_msgs` (see build.rs): subscribes to `telemetry`
//! (`horus_demo_msgs/msg/Telemetry`) and calls `set_mode` (`horus_demo_msgs/srv/SetMode`) of
//! `telemetry_node`.
//!
//! Usage: `telemetry_monitor [--count N] [--set MODE REASON]...`: prints the first N telemetry
//! messages (default 1), then makes each SetMode call in order, printing its answer and, once a
//! mode was accepted, the first telemetry that reports it. It prints one JSON object a line:
//! `{"telemetry": …}`, `{"set_mode": {"request": …, "response": …}}`, `{"set_mode_failed":
//! {"request": …, "error": "…"}}` (e.g. a `reason` over its bound of 48 bytes cannot be
//! encoded: the call fails at once, nothing is sent), `{"telemetry_after": …}`. Exits 0, or 1 if
//! the telemetry or the service did not show up within 30 s.

use std::time::Instant;

use horus_ros_example_interfaces::horus_demo_msgs::msg::Telemetry;
use horus_ros_example_interfaces::horus_demo_msgs::srv::{SetMode, SetModeRequest};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Subscription;
use horus_ros_services::prelude::*;
use serde_json::json;

/// How long to wait for the telemetry node.
const WAIT: Duration = Duration::from_secs(30);

const USAGE: &str = "Usage: telemetry_monitor [--count N] [--set MODE REASON]...
  --count N            print the first N telemetry messages (default: 1)
  --set MODE REASON    call set_mode (MODE: 0 idle, 1 active, 2 docked); repeatable";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (count, calls) = parse(std::env::args().skip(1)).unwrap_or_else(|message| {
        eprintln!("{message}\n\n{USAGE}");
        std::process::exit(2);
    });

    let context = Context::from_env()?;
    let node = context.create_node("telemetry_monitor", "/")?;
    let mut telemetry =
        node.create_subscription::<Telemetry>("telemetry", &Qos::default_profile())?;
    for _ in 0..count {
        let Some(message) = next(&mut telemetry, |_| true)? else {
            fail("no telemetry on /telemetry");
        };
        println!("{}", json!({ "telemetry": message }));
    }

    let mut client = ServiceClient::<SetMode>::builder()
        .node(&node)
        .name("set_mode")
        .build()?;
    if !calls.is_empty() && !client.wait_for_service(WAIT) {
        fail("no server of /set_mode");
    }
    for request in calls {
        match client.call(request.clone(), Duration::from_secs(5)) {
            Ok(response) => {
                println!(
                    "{}",
                    json!({"set_mode": {"request": request, "response": response}})
                );
                if response.accepted {
                    let Some(after) = next(&mut telemetry, |t| t.mode == request.mode)? else {
                        fail("the telemetry never reported the new mode");
                    };
                    println!("{}", json!({ "telemetry_after": after }));
                }
            }
            // Not `request` itself: a value over its bounds does not serialize, as JSON either.
            Err(error) => println!(
                "{}",
                json!({"set_mode_failed": {
                    "request": {"mode": request.mode, "reason": request.reason},
                    "error": error.to_string(),
                }})
            ),
        }
    }
    Ok(())
}

/// The next telemetry for which `wanted` holds, within [`WAIT`].
fn next(
    subscription: &mut Subscription<Telemetry>,
    wanted: impl Fn(&Telemetry) -> bool,
) -> Result<Option<Telemetry>, horus_ros_rmw::TakeError> {
    let deadline = Instant::now() + WAIT;
    loop {
        while let Some(message) = subscription.try_take()? {
            if wanted(&message) {
                return Ok(Some(message));
            }
        }
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Ok(None);
        }
        subscription.wait(left);
    }
}

fn fail(message: &str) -> ! {
    eprintln!(
        "[ERROR] [telemetry_monitor]: {message} within {} s",
        WAIT.as_secs()
    );
    std::process::exit(1);
}

/// `--count N` and the `--set MODE REASON` calls.
fn parse(mut args: impl Iterator<Item = String>) -> Result<(usize, Vec<SetModeRequest>), String> {
    let mut count = 1;
    let mut calls = Vec::new();
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "-h" | "--help" => {
                println!("{USAGE}");
                std::process::exit(0);
            }
            "--count" => {
                let n = args.next().ok_or("--count needs a number")?;
                count = n.parse().map_err(|_| format!("not a count: {n}"))?;
            }
            "--set" => {
                let mode = args.next().ok_or("--set needs a mode")?;
                let mode = mode.parse().map_err(|_| format!("not a mode: {mode}"))?;
                let reason = args.next().ok_or("--set needs a reason")?;
                calls.push(SetModeRequest { mode, reason });
            }
            other => return Err(format!("unexpected argument: {other}")),
        }
    }
    Ok((count, calls))
}
