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

use super::subscribe::{
    announced_hash, decode, drain, expand, now_ns, print_report, resolve_type, subscribe,
    wait_for_type, Filter, Interrupt, Part,
};
use super::window::Window;
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
          value_parser = crate::args::positive_int)]
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

/// ros2topic hz `ROSTopicHz` for one topic: the intervals between arrivals, and the arrival
/// last reported on.
struct Hz {
    times: Window,
    last_printed_tn: i64,
}

impl Hz {
    /// `callback_hz` at time `curr` (ns).
    fn message(&mut self, curr: i64) {
        let _ = self
            .times
            .message(curr, |last| Ok::<_, std::convert::Infallible>(curr - last));
    }

    /// `get_hz` + `print_hz`: the report, once a second of messages has passed since the last
    /// one (the first time only marks where counting starts).
    fn report(&mut self, json: bool, topic: &str) -> Option<String> {
        if self.times.is_empty() {
            return None;
        }
        let msg_tn = self.times.last();
        if self.last_printed_tn == 0 {
            self.last_printed_tn = msg_tn;
            return None;
        }
        if (msg_tn as f64) < self.last_printed_tn as f64 + 1e9 {
            return None;
        }
        let text = self.times.report(json, topic, "rate", |mean| {
            if mean > 0.0 {
                1e9 / mean
            } else {
                0.0
            }
        })?;
        self.last_printed_tn = msg_tn;
        Some(text)
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
        Some(_) => Some(resolve_type(
            &session,
            &type_name,
            &format!("The message type '{type_name}' is invalid"),
        )?),
        None => None,
    };
    let hash = match &message_type {
        Some(t) => t.hash,
        None => announced_hash(&session, &topic, &type_name),
    };
    let mut reader = subscribe(&session, &topic, &type_name, hash, Qos::sensor_data())?;
    let mut hz = Hz {
        times: Window::new(args.window_size),
        last_printed_tn: 0,
    };
    let interrupt = Interrupt::watch(&reader);
    loop {
        reader.wait(None);
        interrupt.check()?;
        for sample in drain(&mut reader) {
            let now = now_ns();
            if let (Some(f), Some(t)) = (&filter, &message_type) {
                let Some(value) = decode(&t.schema, &t.name, &sample) else {
                    continue;
                };
                let pass = f
                    .matches(&t.schema, Part::Message(&t.name, &value))
                    .map_err(|e| CliError::new(format!("The --filter expression failed: {e}")))?;
                if !pass {
                    continue;
                }
            }
            hz.message(now);
            if let Some(text) = hz.report(global.json, &args.topic_name) {
                if !print_report(&text) {
                    return Ok(());
                }
            }
        }
    }
}
