//! What the benchmarks share: refusing to run where their DDS or Zenoh traffic could reach a
//! real network (only inside a private network namespace, `scripts/bench` or `scripts/isolated`,
//! where `lo` is the only interface up), their settings from the environment, the machine's
//! load, and percentiles.

use std::time::Duration;

/// The positive integer in the variable `name`, else `default`.
pub fn env_usize(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&v| v > 0)
        .unwrap_or(default)
}

/// The load averages (1, 5, 15 minutes) of `/proc/loadavg`, or `unknown`.
pub fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".to_owned())
}

/// Nearest-rank percentile `p` (0–100) of sorted samples (zero for none).
pub fn percentile(sorted: &[Duration], p: f64) -> Duration {
    if sorted.is_empty() {
        return Duration::ZERO;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// Names of interfaces other than `lo` that are up (IFF_UP in `flags`, or operstate `up`).
pub fn non_loopback_interfaces_up() -> std::io::Result<Vec<String>> {
    let mut up = Vec::new();
    for entry in std::fs::read_dir("/sys/class/net")? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == "lo" {
            continue;
        }
        let read = |file: &str| {
            std::fs::read_to_string(entry.path().join(file))
                .map(|s| s.trim().to_owned())
                .unwrap_or_default()
        };
        let flags = u32::from_str_radix(read("flags").trim_start_matches("0x"), 16).unwrap_or(0);
        if flags & 0x1 != 0 || read("operstate") == "up" {
            up.push(name);
        }
    }
    Ok(up)
}

/// Exits (status 2) with a message saying why and how to run it — `run`, the isolated
/// command line — when an interface other than `lo` is up (or the interfaces cannot be read).
pub fn refuse_outside_namespace(bench: &str, run: &str) {
    let why = match non_loopback_interfaces_up() {
        Ok(up) if up.is_empty() => return,
        Ok(up) => format!("network interface(s) up besides lo: {}", up.join(", ")),
        Err(e) => format!("cannot read /sys/class/net to check the interfaces: {e}"),
    };
    eprintln!(
        "{bench}: REFUSING TO RUN: {why}.\n\
         This benchmark opens DDS participants or Zenoh sessions, whose traffic must not leave \
         this machine.\nRun it inside a private network namespace:\n    scripts/bench\nor\n    \
         {run}"
    );
    std::process::exit(2);
}

/// A child process killed and reaped when dropped.
#[derive(Debug)]
pub struct Stopped(pub std::process::Child);

impl Drop for Stopped {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The number in the variable `name` (zero allowed), else `default`.
pub fn env_count(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// `n` processes spinning on the CPU (`yes` writing to nothing), stopped when dropped: the load
/// a benchmark runs under.
pub fn cpu_hogs(n: usize) -> Vec<Stopped> {
    (0..n)
        .map(|_| {
            Stopped(
                std::process::Command::new("yes")
                    .stdout(std::process::Stdio::null())
                    .spawn()
                    .expect("start yes"),
            )
        })
        .collect()
}
