//! Runs `examples/leakcheck.rs` under valgrind: no definite or indirect leak and no memory
//! error may be reported. Valgrind is required (scripts/setup installs it): without it this
//! test fails rather than skips. Domain 147; run inside `scripts/isolated`.
use std::time::Duration;

use horus_ros_test_support::{built_example, valgrind};

#[test]
fn no_leaks_under_valgrind() {
    // Bounded: valgrind slows Cyclone down a lot, but not this much.
    valgrind::assert_no_leaks(
        &built_example("leakcheck"),
        &[],
        "leakcheck: ok",
        Duration::from_secs(240),
    );
}
