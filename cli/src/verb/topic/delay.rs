//! `horus-ros topic delay` (ros2topic jazzy 0.32 `verb/delay.py`): the delay between the
//! `header.stamp` of a topic's messages and their arrival.
//!
//! As ros2cli: waits for the topic to appear, subscribes with the `sensor_data` QoS; the first
//! message only starts the count, each later one adds `now - header.stamp` (ns) to a window of
//! `--window`; every second, when there are delays, prints
//! `average delay: %.3f\n\tmin: %.3fs max: %.3fs std dev: %.5fs window: %s`, or
//! `no new messages` when none came since the last report. A type without `header` is refused
//! (ros2cli: `msg does not have header`) when the verb starts rather than at the first message.
//! With the global `--json`, each report is one JSON object on one line.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use serde_json::json;

use super::subscribe::{
    expand, now_ns, positive_int, print_report, resolve_type, select, stats, subscribe,
    wait_for_type, Part,
};
use crate::dynamic::{cdr, Value};
use crate::session::Session;
use crate::{CliError, Global};
use horus_ros_rmw::qos::Qos;

/// ros2topic delay `DEFAULT_WINDOW_SIZE`.
const DEFAULT_WINDOW_SIZE: usize = 10000;

/// Arguments of `topic delay`.
#[derive(Debug, clap::Args)]
pub struct DelayArgs {
    /// Topic name to calculate the delay for
    pub topic: String,
    /// window size, in # of messages, for calculating rate, string to (default: 10000)
    #[arg(short = 'w', long, default_value_t = DEFAULT_WINDOW_SIZE, value_parser = positive_int)]
    pub window: usize,
}

/// `header.stamp` in nanoseconds (rclpy `Time.from_msg`), if the message has one.
fn stamp(schema: &crate::dynamic::Schema, type_name: &str, v: &Value) -> Option<i64> {
    let path = ["header".to_owned(), "stamp".to_owned()];
    let stamp = select(schema, type_name, v, &path).ok()?;
    let int = |name: &str| match stamp.attr(schema, name).ok()? {
        Part::Field(_, Value::Int(i)) => i64::try_from(*i).ok(),
        _ => None,
    };
    Some(int("sec")? * 1_000_000_000 + int("nanosec")?)
}

/// Runs `topic delay`.
pub fn run(global: &Global, args: &DelayArgs) -> Result<(), CliError> {
    let session = Session::open(global)?;
    let topic = expand(&session, &args.topic)?;
    let type_name = wait_for_type(&session, &args.topic, &topic)?;
    let t = resolve_type(&session, &type_name)?;
    let has_header = t
        .schema
        .get(&t.name)
        .is_ok_and(|s| s.members.iter().any(|m| m.name == "header"));
    if !has_header {
        return Err(CliError::new("msg does not have header"));
    }
    let mut reader = subscribe(&session, &topic, &type_name, t.hash, Qos::sensor_data())?;
    let mut msg_t0: i64 = -1;
    let mut msg_tn: i64 = 0;
    let mut last_msg_tn: i64 = 0;
    let mut delays: VecDeque<i64> = VecDeque::new();
    let mut tick = Instant::now() + Duration::from_secs(1);
    loop {
        let left = tick.saturating_duration_since(Instant::now());
        if !left.is_zero() {
            reader.wait(left);
        }
        loop {
            let sample = match reader.take() {
                Ok(Some(s)) => s,
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!("dropped a message: {e}");
                    continue;
                }
            };
            let value = match cdr::decode(&t.schema, &t.name, &sample.body, sample.big_endian) {
                Ok(v) => v,
                Err(e) => {
                    tracing::warn!("could not decode a message: {e}");
                    continue;
                }
            };
            // delay.py `callback_delay`.
            let curr = now_ns();
            if curr == 0 {
                if !delays.is_empty() {
                    println!("time has reset, resetting counters");
                    delays.clear();
                }
                continue;
            }
            if msg_t0 < 0 || msg_t0 > curr {
                msg_t0 = curr;
                msg_tn = curr;
                delays.clear();
            } else {
                let Some(s) = stamp(&t.schema, &t.name, &value) else {
                    return Err(CliError::new("msg does not have header"));
                };
                delays.push_back(curr - s);
                msg_tn = curr;
            }
            if delays.len() > args.window {
                delays.pop_front();
            }
        }
        if Instant::now() < tick {
            continue;
        }
        tick += Duration::from_secs(1);
        // delay.py `print_delay`.
        if delays.is_empty() {
            continue;
        }
        let text = if msg_tn == last_msg_tn {
            if global.json {
                json!({ "topic": args.topic, "new_messages": false }).to_string()
            } else {
                "no new messages".to_owned()
            }
        } else {
            let Some((mean, min, max, std_dev)) = stats(&delays) else {
                continue;
            };
            last_msg_tn = msg_tn;
            let (delay, min, max, std_dev) = (
                mean * 1e-9,
                min as f64 * 1e-9,
                max as f64 * 1e-9,
                std_dev * 1e-9,
            );
            let window = delays.len();
            if global.json {
                json!({
                    "topic": args.topic,
                    "average_delay": delay,
                    "min": min,
                    "max": max,
                    "std_dev": std_dev,
                    "window": window,
                })
                .to_string()
            } else {
                format!(
                    "average delay: {delay:.3}\n\tmin: {min:.3}s max: {max:.3}s std dev: \
                     {std_dev:.5}s window: {window}"
                )
            }
        };
        if !print_report(&text) {
            return Ok(());
        }
    }
}
