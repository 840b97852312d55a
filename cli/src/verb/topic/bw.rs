//! `horus-ros topic bw` (ros2topic jazzy 0.32 `verb/bw.py`): the bandwidth a topic uses.
//!
//! As ros2cli: waits for the topic to appear, subscribes with the `sensor_data` QoS to the raw
//! (serialized) messages, prints `Subscribed to [<topic>]`, keeps the receive time and size
//! (the serialized length, encapsulation header included) of the last `--window` messages and,
//! every second once it has two, prints
//! `<bw>/s from <n> messages\n\tMessage size mean: <mean> min: <min> max: <max>` in B, KB or MB
//! (by the rate: below 1000, below 1000000, else; powers of 1000). Messages are never decoded.
//! With the global `--json`, each report is one JSON object on one line (sizes in bytes).

use std::collections::VecDeque;

use serde_json::json;

use super::subscribe::{
    announced_hash, drain, expand, now_ns, print_report, subscribe, wait_for_type, Interrupt,
};
use super::window::Ticker;
use crate::session::Session;
use crate::{CliError, Global};
use horus_ros_rmw::qos::Qos;

/// ros2topic bw `DEFAULT_WINDOW_SIZE`.
const DEFAULT_WINDOW_SIZE: usize = 100;

/// Arguments of `topic bw`.
#[derive(Debug, clap::Args)]
pub struct BwArgs {
    /// Topic name to monitor for bandwidth utilization
    pub topic: String,
    /// maximum window size, in # of messages, for calculating rate (default: 100)
    #[arg(short = 'w', long, value_name = "WINDOW", default_value_t = DEFAULT_WINDOW_SIZE,
          value_parser = crate::args::positive_int)]
    pub window: usize,
}

/// bw.py `str_bytes`, `str_kilobytes`, `str_megabytes`, chosen by the rate.
fn unit(bytes_per_s: f64) -> fn(f64) -> String {
    if bytes_per_s < 1000.0 {
        |b| format!("{b:.0} B")
    } else if bytes_per_s < 1_000_000.0 {
        |b| format!("{:.2} KB", b / 1000.0)
    } else {
        |b| format!("{:.2} MB", b / 1000.0 / 1000.0)
    }
}

/// Runs `topic bw`.
pub fn run(global: &Global, args: &BwArgs) -> Result<(), CliError> {
    let session = Session::open(global)?;
    let topic = expand(&session, &args.topic)?;
    let type_name = wait_for_type(&session, &args.topic, &topic)?;
    let hash = announced_hash(&session, &topic, &type_name);
    let mut reader = subscribe(&session, &topic, &type_name, hash, Qos::sensor_data())?;
    if !global.json && !print_report(&format!("Subscribed to [{}]", args.topic)) {
        return Ok(());
    }
    // (receive time in ns, serialized size)
    let mut window: VecDeque<(i64, usize)> = VecDeque::new();
    let mut ticker = Ticker::start();
    let interrupt = Interrupt::watch(&reader);
    loop {
        ticker.wait(&mut reader);
        interrupt.check()?;
        for s in drain(&mut reader) {
            // `len(data)` of the serialized message: header and body.
            window.push_back((now_ns(), 4 + s.body.len()));
            if window.len() > args.window {
                window.pop_front();
            }
        }
        if !ticker.due() {
            continue;
        }
        if window.len() < 2 {
            continue;
        }
        let n = window.len();
        let tn = now_ns();
        let t0 = window[0].0;
        if tn <= t0 {
            eprintln!("WARNING: time is reset!");
            window.clear();
            continue;
        }
        let total: usize = window.iter().map(|(_, s)| s).sum();
        let bytes_per_s = total as f64 / ((tn - t0) as f64 * 1e-9);
        let mean = total as f64 / n as f64;
        let max = window.iter().map(|(_, s)| *s).max().unwrap_or(0);
        let min = window.iter().map(|(_, s)| *s).min().unwrap_or(0);
        let text = if global.json {
            json!({
                "topic": args.topic,
                "bytes_per_s": bytes_per_s,
                "messages": n,
                "mean": mean,
                "min": min,
                "max": max,
            })
            .to_string()
        } else {
            let f = unit(bytes_per_s);
            format!(
                "{}/s from {n} messages\n\tMessage size mean: {} min: {} max: {}",
                f(bytes_per_s),
                f(mean),
                f(min as f64),
                f(max as f64)
            )
        };
        if !print_report(&text) {
            return Ok(());
        }
    }
}
