//! What `topic hz | delay | bw` share: the window of the last values ros2topic hz and delay
//! keep ([`Window`]: hz.py `callback_hz`, delay.py `callback_delay`), the report they print
//! from it ([`Window::report`]), and the once-a-second clock of delay and bw ([`Ticker`]).

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use horus_ros_rmw::RawReader;
use serde_json::json;

/// The last values (nanoseconds) of a topic's messages, at most `size`: intervals between
/// arrivals (hz) or delays from the header stamp (delay).
pub struct Window {
    size: usize,
    /// The arrival of the first message of the count (-1 before one); `msg_t0`.
    first: i64,
    /// The arrival of the last message; `msg_tn`.
    last: i64,
    values: VecDeque<i64>,
}

impl Window {
    /// An empty window of at most `size` values.
    pub fn new(size: usize) -> Self {
        Self {
            size,
            first: -1,
            last: 0,
            values: VecDeque::new(),
        }
    }

    /// A message arrived at `curr` (ns): as ros2topic's callbacks, a clock at 0 clears the values
    /// (saying `time has reset, resetting counters` if there were some), the first message (or
    /// one from before the first) only starts the count, any later one adds `value(last)`
    /// (`last`: the previous arrival), and the oldest values go beyond the size.
    pub fn message<E>(
        &mut self,
        curr: i64,
        value: impl FnOnce(i64) -> Result<i64, E>,
    ) -> Result<(), E> {
        if curr == 0 {
            if !self.values.is_empty() {
                println!("time has reset, resetting counters");
                self.values.clear();
            }
            return Ok(());
        }
        if self.first < 0 || self.first > curr {
            self.first = curr;
            self.last = curr;
            self.values.clear();
        } else {
            self.values.push_back(value(self.last)?);
            self.last = curr;
        }
        if self.values.len() > self.size {
            self.values.pop_front();
        }
        Ok(())
    }

    /// The arrival of the last message counted (ns); 0 before any.
    pub fn last(&self) -> i64 {
        self.last
    }

    /// Whether no value is held.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Mean, min, max and population standard deviation of the values; `None` when empty.
    fn stats(&self) -> Option<(f64, i64, i64, f64)> {
        let n = self.values.len() as f64;
        let min = *self.values.iter().min()?;
        let max = *self.values.iter().max()?;
        let mean = self.values.iter().map(|v| *v as f64).sum::<f64>() / n;
        let var = self
            .values
            .iter()
            .map(|v| (*v as f64 - mean).powi(2))
            .sum::<f64>()
            / n;
        Some((mean, min, max, var.sqrt()))
    }

    /// The report of `topic` (as given) that hz.py `get_hz` / delay.py `get_delay` compute
    /// and print: `average {what}: %.3f\n\tmin: %.3fs max: %.3fs std dev: %.5fs window: %s`
    /// (hz: `what` = `rate`, the average `1e9 / mean`; delay: `delay`, `mean * 1e-9`), or with
    /// `json` (the global `--json`) one object (`average_{what}`, `min`, `max`, `std_dev`, `window`; see
    /// docs/cli-json.md); `None` when empty.
    pub fn report(
        &self,
        json: bool,
        topic: &str,
        what: &str,
        average: impl FnOnce(f64) -> f64,
    ) -> Option<String> {
        let (mean, min, max, std_dev) = self.stats()?;
        let (average, min, max, std_dev) = (
            average(mean),
            min as f64 * 1e-9,
            max as f64 * 1e-9,
            std_dev * 1e-9,
        );
        let window = self.values.len();
        Some(if json {
            let mut j = json!({
                "topic": topic,
                "min": min,
                "max": max,
                "std_dev": std_dev,
                "window": window,
            });
            j[format!("average_{what}")] = json!(average);
            j.to_string()
        } else {
            format!(
                "average {what}: {average:.3}\n\tmin: {min:.3}s max: {max:.3}s std dev: \
                 {std_dev:.5}s window: {window}"
            )
        })
    }
}

/// The once-a-second report clock of ros2topic delay and bw (their `create_timer(1, …)`).
pub struct Ticker(Instant);

impl Ticker {
    /// The first report is due a second from now.
    pub fn start() -> Self {
        Self(Instant::now() + Duration::from_secs(1))
    }

    /// Waits on `reader` until data comes or the report is due.
    pub fn wait(&self, reader: &mut RawReader) {
        let left = self.0.saturating_duration_since(Instant::now());
        if !left.is_zero() {
            reader.wait(left);
        }
    }

    /// Whether the report is due; if so, the next is due a second later.
    pub fn due(&mut self) -> bool {
        if Instant::now() < self.0 {
            return false;
        }
        self.0 += Duration::from_secs(1);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_counts_from_the_second_message_and_keeps_the_last_values() {
        let mut w = Window::new(2);
        for t in [100, 300, 600, 1000] {
            w.message(t, |last| Ok::<_, ()>(t - last)).expect("counted");
        }
        // 200 dropped: the window keeps 300 and 400.
        let text = w
            .report(false, "/t", "delay", |m| m * 1e-9)
            .expect("a report");
        assert_eq!(
            text,
            "average delay: 0.000\n\tmin: 0.000s max: 0.000s std dev: 0.00000s window: 2"
        );
        let j: serde_json::Value =
            serde_json::from_str(&w.report(true, "/t", "rate", |m| 1e9 / m).expect("a report"))
                .expect("json");
        assert_eq!(j["average_rate"], json!(1e9 / 350.0));
        assert_eq!(j["window"], json!(2));
        assert_eq!(j["min"], json!(300.0 * 1e-9));
        assert!(Window::new(3).report(false, "/t", "rate", |m| m).is_none());
    }
}
