//! Helpers shared by the integration tests. Every test uses its own domain id (141-149) and a
//! Cyclone configuration restricted to the loopback interface; run them inside
//! `scripts/isolated` (a private network namespace).
#![allow(dead_code)]

use std::time::{Duration, Instant};

use horus_ros_rmw_cyclone::config::{domain_config, DiscoveryRange};
use horus_ros_rmw_cyclone::{BuiltinReader, Domain, Participant, StatusMask, Waiter, Writer};

/// Cyclone configuration: loopback only, with multicast (appended after our discovery
/// fragment, the place where rmw_cyclonedds puts `CYCLONEDDS_URI`).
pub const LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

/// Upper bound for anything discovery-related in these tests.
pub const DISCOVERY: Duration = Duration::from_secs(10);

/// The configuration every in-process participant of a test uses.
pub fn config() -> String {
    domain_config(
        DiscoveryRange::Subnet,
        &[],
        std::process::id(),
        Some(LOOPBACK),
    )
}

/// A participant on `domain` (loopback configuration) with `user_data`.
pub fn participant(domain: u32, user_data: &str) -> Participant {
    let d = Domain::acquire(domain, &config()).expect("create domain");
    Participant::new(d, user_data.as_bytes()).expect("create participant")
}

/// Checks `f` at once and after each wake-up of `waiter` (attached to what `f` looks at: a
/// reader's data, an entity's status), until it gives `Some` or `timeout` passes.
pub fn until<T>(timeout: Duration, waiter: &Waiter, mut f: impl FnMut() -> Option<T>) -> Option<T> {
    let end = Instant::now() + timeout;
    loop {
        if let Some(v) = f() {
            return Some(v);
        }
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return None;
        }
        waiter.wait(left).expect("wait");
    }
}

/// A waiter woken by data on each of `readers`.
pub fn builtin_waiter(readers: &[&BuiltinReader]) -> Waiter {
    let waiter = Waiter::new().expect("waiter");
    for (token, reader) in readers.iter().enumerate() {
        waiter.attach_builtin(reader, token + 1).expect("attach");
    }
    waiter
}

/// Blocks, at most `limit`, until `w` matched at least one reader, through a status condition.
pub fn wait_matched(w: &Writer, limit: Duration) {
    let waiter = Waiter::new().expect("waiter");
    waiter
        .attach_status(&w.entity(), StatusMask::PUBLICATION_MATCHED, 1)
        .expect("attach");
    let matched = until(limit, &waiter, || {
        (w.publication_matched().expect("status").0 > 0).then_some(())
    });
    assert!(matched.is_some(), "writer never matched a reader");
}

/// CDR (little endian) of `builtin_interfaces/msg/Time { sec, nanosec }` with its header.
pub fn time_cdr(sec: i32, nanosec: u32) -> Vec<u8> {
    let mut v = vec![0x00, 0x01, 0x00, 0x00];
    v.extend_from_slice(&sec.to_le_bytes());
    v.extend_from_slice(&nanosec.to_le_bytes());
    v
}

/// The inverse of [`time_cdr`] (little-endian encapsulation only).
pub fn parse_time(cdr: &[u8]) -> (i32, u32) {
    assert_eq!(&cdr[..2], &[0x00, 0x01], "CDR_LE encapsulation expected");
    let sec = i32::from_le_bytes(cdr[4..8].try_into().expect("4 bytes"));
    let nanosec = u32::from_le_bytes(cdr[8..12].try_into().expect("4 bytes"));
    (sec, nanosec)
}

/// The type hash USER_DATA rmw_cyclonedds gives an endpoint of `builtin_interfaces/msg/Time`.
pub const TIME_USER_DATA: &str =
    "typehash=RIHS01_b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197;";
/// DDS type name of `builtin_interfaces/msg/Time`.
pub const TIME_TYPE: &str = "builtin_interfaces::msg::dds_::Time_";
