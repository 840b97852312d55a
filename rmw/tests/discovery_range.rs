//! The Cyclone backend configures discovery as rmw_cyclonedds does: `ROS_AUTOMATIC_DISCOVERY_RANGE`
//! and `ROS_STATIC_PEERS`, then `CYCLONEDDS_URI`. Two probe processes (examples/discovery_probe)
//! must find each other, or must not. Run inside `scripts/isolated`. (Static peers are not
//! observable on one host: without multicast, Cyclone contacts localhost by itself. The XML
//! they give is checked byte for byte in horus-ros-rmw-cyclone's `config` tests.)

use std::path::PathBuf;
use std::process::{Command, Stdio};

/// target/<profile>/examples/discovery_probe (`cargo test` builds the examples with the tests).
fn probe() -> PathBuf {
    horus_ros_test_support::built_example("discovery_probe")
}

/// Runs two probes (`a` looking for `b` and back) for `seconds` with `env` on top of a clean
/// ROS environment; returns what each printed.
fn pair(domain: u32, env: &[(&str, &str)], seconds: f64) -> (String, String) {
    pair_with(domain, env, env, seconds)
}

/// [`pair`] with each probe's own environment.
fn pair_with(
    domain: u32,
    env_a: &[(&str, &str)],
    env_b: &[(&str, &str)],
    seconds: f64,
) -> (String, String) {
    let spawn = |own: &str, other: &str, env: &[(&str, &str)]| {
        let mut c = Command::new(probe());
        c.args([own, other, &seconds.to_string()])
            .env("HORUS_ROS_BACKEND", "cyclone")
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env_remove("ROS_AUTOMATIC_DISCOVERY_RANGE")
            .env_remove("ROS_STATIC_PEERS")
            .env_remove("ROS_LOCALHOST_ONLY")
            .env_remove("CYCLONEDDS_URI")
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit());
        for (k, v) in env {
            c.env(k, v);
        }
        c.spawn().expect("start a probe")
    };
    let a = spawn("probe_a", "probe_b", env_a);
    let b = spawn("probe_b", "probe_a", env_b);
    let out = |c: std::process::Child| {
        let o = c.wait_with_output().expect("probe output");
        assert!(o.status.success(), "probe failed: {o:?}");
        String::from_utf8_lossy(&o.stdout).trim().to_owned()
    };
    (out(a), out(b))
}

fn both(s: &str) -> (String, String) {
    (s.to_owned(), s.to_owned())
}

/// A user's Cyclone configuration giving the domain a discovery tag: participants with
/// different tags ignore each other.
fn tagged(tag: &str) -> String {
    format!("<CycloneDDS><Domain><Discovery><Tag>{tag}</Tag></Discovery></Domain></CycloneDDS>")
}

#[test]
fn off_discovers_nothing() {
    assert_eq!(
        pair(43, &[("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF")], 3.0),
        both("unseen")
    );
}

#[test]
fn localhost_discovers_this_host_without_multicast() {
    assert_eq!(
        pair(44, &[("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")], 10.0),
        both("seen")
    );
}

#[test]
fn cyclonedds_uri_is_applied_after_the_ros_settings() {
    let (x, y) = (tagged("horus_x"), tagged("horus_y"));
    assert_eq!(
        pair(45, &[("CYCLONEDDS_URI", x.as_str())], 10.0),
        both("seen")
    );
    assert_eq!(
        pair_with(
            46,
            &[("CYCLONEDDS_URI", x.as_str())],
            &[("CYCLONEDDS_URI", y.as_str())],
            3.0
        ),
        both("unseen")
    );
}
