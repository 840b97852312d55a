//! What the CLI's benches share: the Cyclone DDS configuration they run on, their numeric
//! settings from the environment, the check that they run inside a private network namespace,
//! and milliseconds for printing.
#![allow(dead_code)]

use std::path::Path;
use std::time::Duration;

/// The Cyclone DDS configuration used when `CYCLONEDDS_URI` is unset: loopback, with multicast.
pub const CYCLONE_LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

/// The number in the environment variable `name`, else `default`.
pub fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Network interfaces other than `lo` that are up: none inside `scripts/isolated`'s namespace.
/// Without a sysfs view of the network it cannot tell, and says so (the benches then refuse).
pub fn interfaces_up() -> Vec<String> {
    let Ok(entries) = std::fs::read_dir("/sys/class/net") else {
        return vec!["(cannot read /sys/class/net)".to_owned()];
    };
    entries
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| name != "lo")
        .filter(|name| {
            let flags =
                std::fs::read_to_string(Path::new("/sys/class/net").join(name).join("flags"))
                    .unwrap_or_default();
            // IFF_UP; unreadable flags count as up.
            u32::from_str_radix(flags.trim().trim_start_matches("0x"), 16)
                .map_or(true, |f| f & 1 == 1)
        })
        .collect()
}

/// `d` in milliseconds.
pub fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}
