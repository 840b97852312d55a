//! Runs `examples/cyclone_leakcheck.rs` (the Cyclone DDS backend: context, node, typed and raw
//! endpoints, discovery feed, samples, teardown) under valgrind: no definite or indirect leak
//! and no memory error may be reported. Valgrind is required (scripts/setup installs it):
//! without it this test fails rather than skips. Needs the feature `cyclone`. Domain 149; run
//! inside `scripts/isolated`.
use std::time::Duration;

use horus_ros_test_support::{built_example, valgrind};

/// Cyclone DDS on loopback, with multicast (the private namespace has no other interface).
const LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

#[test]
fn no_leaks_under_valgrind() {
    // Bounded: valgrind slows Cyclone down a lot, but not this much.
    valgrind::assert_no_leaks(
        &built_example("cyclone_leakcheck"),
        &[("CYCLONEDDS_URI", LOOPBACK)],
        "cyclone_leakcheck: ok",
        Duration::from_secs(300),
    );
}
