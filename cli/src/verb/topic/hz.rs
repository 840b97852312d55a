//! `horus-ros topic hz` (ros2topic jazzy 0.32 `verb/hz.py`): the average publishing rate of a
//! topic.
//!
//! As ros2cli: waits for the topic to appear (`WARNING: topic [...] does not appear to be
//! published yet`), subscribes with the `sensor_data` QoS, takes the receive time of each
//! message (the clock's nanoseconds), keeps the last `--window` intervals, and after a message
//! that arrives a second or more after the last report prints
//! `average rate: %.3f\n\tmin: %.3fs max: %.3fs std dev: %.5fs window: %s`.
//!
//! Messages are counted as the raw samples arrive, never decoded, unless `--filter` needs them
//! (a subset of Python, see [`Filter`]). The clock is the system clock (rclpy's ROS clock
//! without `/clock`), so `--wall-time` changes nothing. With the global `--json`, each report is
//! one JSON object on one line.

use std::collections::VecDeque;

use serde_json::json;

use super::subscribe::{
    announced_hash, expand, now_ns, positive_int, print_report, resolve_type, stats, subscribe,
    wait_for_type, Filter, Part,
};
use crate::dynamic::cdr;
use crate::session::Session;
use crate::{CliError, Global};
use horus_ros_rmw::qos::Qos;

/// ros2topic hz `DEFAULT_WINDOW_SIZE`.
const DEFAULT_WINDOW_SIZE: usize = 10000;

/// Arguments of `topic hz`.
#[derive(Debug, clap::Args)]
pub struct HzArgs {
    /// Name of the ROS topic to listen to (e.g. '/chatter')
    pub topic_name: String,
    /// window size, in # of messages, for calculating rate (default: 10000)
    #[arg(short = 'w', long = "window", value_name = "WINDOW", default_value_t = DEFAULT_WINDOW_SIZE,
          value_parser = positive_int)]
    pub window_size: usize,
    /// only measure messages matching the specified Python expression (here a subset of
    /// Python: paths from m, len(), literals, comparisons, and/or/not)
    #[arg(long = "filter", value_name = "EXPR")]
    pub filter_expr: Option<String>,
    /// calculates rate using wall time which can be helpful when clock is not published during
    /// simulation
    #[arg(long = "wall-time")]
    pub use_wtime: bool,
}

/// ros2topic hz `ROSTopicHz` for one topic.
struct Hz {
    window: usize,
    msg_t0: i64,
    msg_tn: i64,
    times: VecDeque<i64>,
    last_printed_tn: i64,
}

impl Hz {
    /// `callback_hz` at time `curr` (ns).
    fn message(&mut self, curr: i64) {
        if curr == 0 {
            if !self.times.is_empty() {
                println!("time has reset, resetting counters");
                self.times.clear();
            }
            return;
        }
        if self.msg_t0 < 0 || self.msg_t0 > curr {
            self.msg_t0 = curr;
            self.msg_tn = curr;
            self.times.clear();
        } else {
            self.times.push_back(curr - self.msg_tn);
            self.msg_tn = curr;
        }
        if self.times.len() > self.window {
            self.times.pop_front();
        }
    }

    /// `get_hz`: (rate in Hz, min, max, std dev in s, window), when due.
    fn report(&mut self) -> Option<(f64, f64, f64, f64, usize)> {
        if self.times.is_empty() {
            return None;
        }
        if self.last_printed_tn == 0 {
            self.last_printed_tn = self.msg_tn;
            return None;
        }
        if (self.msg_tn as f64) < self.last_printed_tn as f64 + 1e9 {
            return None;
        }
        let (mean, min, max, std_dev) = stats(&self.times)?;
        let rate = if mean > 0.0 { 1.0 / mean } else { 0.0 };
        self.last_printed_tn = self.msg_tn;
        Some((
            rate * 1e9,
            min as f64 * 1e-9,
            max as f64 * 1e-9,
            std_dev * 1e-9,
            self.times.len(),
        ))
    }
}

/// Runs `topic hz`.
pub fn run(global: &Global, args: &HzArgs) -> Result<(), CliError> {
    let filter = args
        .filter_expr
        .as_deref()
        .map(|e| {
            Filter::parse(e).map_err(|why| {
                CliError::new(format!("Unsupported --filter expression '{e}': {why}"))
            })
        })
        .transpose()?;
    let session = Session::open(global)?;
    let topic = expand(&session, &args.topic_name)?;
    let type_name = wait_for_type(&session, &args.topic_name, &topic)?;
    let message_type = match filter {
        Some(_) => Some(resolve_type(&session, &type_name)?),
        None => None,
    };
    let hash = match &message_type {
        Some(t) => t.hash,
        None => announced_hash(&session, &topic, &type_name),
    };
    let mut reader = subscribe(&session, &topic, &type_name, hash, Qos::sensor_data())?;
    let mut hz = Hz {
        window: args.window_size,
        msg_t0: -1,
        msg_tn: 0,
        times: VecDeque::new(),
        last_printed_tn: 0,
    };
    loop {
        reader.wait(None);
        loop {
            let sample = match reader.take() {
                Ok(Some(s)) => s,
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!("dropped a message: {e}");
                    continue;
                }
            };
            let now = now_ns();
            if let (Some(f), Some(t)) = (&filter, &message_type) {
                let value = match cdr::decode(&t.schema, &t.name, &sample.body, sample.big_endian) {
                    Ok(v) => v,
                    Err(e) => {
                        tracing::warn!("could not decode a message: {e}");
                        continue;
                    }
                };
                let pass = f
                    .matches(&t.schema, Part::Message(&t.name, &value))
                    .map_err(|e| CliError::new(format!("The --filter expression failed: {e}")))?;
                if !pass {
                    continue;
                }
            }
            hz.message(now);
            if let Some((rate, min, max, std_dev, window)) = hz.report() {
                let text = if global.json {
                    json!({
                        "topic": args.topic_name,
                        "average_rate": rate,
                        "min": min,
                        "max": max,
                        "std_dev": std_dev,
                        "window": window,
                    })
                    .to_string()
                } else {
                    format!(
                        "average rate: {rate:.3}\n\tmin: {min:.3}s max: {max:.3}s std dev: \
                         {std_dev:.5}s window: {window}"
                    )
                };
                if !print_report(&text) {
                    return Ok(());
                }
            }
        }
    }
}
