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

use serde_json::json;

use super::subscribe::{
    decode, drain, expand, now_ns, print_report, resolve_type, select, subscribe, wait_for_type,
    Interrupt, Part,
};
use super::window::{Ticker, Window};
use crate::dynamic::Value;
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
    #[arg(short = 'w', long, default_value_t = DEFAULT_WINDOW_SIZE, value_parser = crate::args::positive_int)]
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
    let t = resolve_type(
        &session,
        &type_name,
        &format!("The message type '{type_name}' is invalid"),
    )?;
    let has_header = t
        .schema
        .get(&t.name)
        .is_ok_and(|s| s.members.iter().any(|m| m.name == "header"));
    if !has_header {
        return Err(CliError::new("msg does not have header"));
    }
    let mut reader = subscribe(&session, &topic, &type_name, t.hash, Qos::sensor_data())?;
    let mut delays = Window::new(args.window);
    let mut last_msg_tn: i64 = 0;
    let mut ticker = Ticker::start();
    let interrupt = Interrupt::watch(&reader);
    loop {
        ticker.wait(&mut reader);
        interrupt.check()?;
        for sample in drain(&mut reader) {
            let Some(value) = decode(&t.schema, &t.name, &sample) else {
                continue;
            };
            // delay.py `callback_delay`.
            let curr = now_ns();
            delays.message(curr, |_| match stamp(&t.schema, &t.name, &value) {
                Some(s) => Ok(curr - s),
                None => Err(CliError::new("msg does not have header")),
            })?;
        }
        if !ticker.due() {
            continue;
        }
        // delay.py `print_delay`.
        if delays.is_empty() {
            continue;
        }
        let text = if delays.last() == last_msg_tn {
            if global.json {
                json!({ "topic": args.topic, "new_messages": false }).to_string()
            } else {
                "no new messages".to_owned()
            }
        } else {
            let Some(text) = delays.report(global.json, &args.topic, "delay", |mean| mean * 1e-9)
            else {
                continue;
            };
            last_msg_tn = delays.last();
            text
        };
        if !print_report(&text) {
            return Ok(());
        }
    }
}
