//! `horus-ros topic hz | bw | delay` against real rclpy publishers (rmw_fastrtps_cpp, the
//! suite's Jazzy wheels): the report lines have ros2topic's formats; the measured rate is
//! checked with a wide tolerance only (the tests run on loaded machines).
//!
//! Joins DDS domains 217-219: run inside the private network namespace
//! (`scripts/isolated cargo test -p horus-ros-cli --test topic_hz`), on each backend
//! (`HORUS_ROS_BACKEND`).

mod common;
mod topic_support;

use topic_support::{publisher, Ament, Cli};

/// The value after `prefix` up to the next space, as a number.
fn number_after(line: &str, prefix: &str) -> f64 {
    let rest = line
        .split(prefix)
        .nth(1)
        .unwrap_or_else(|| panic!("no {prefix:?} in {line:?}"));
    let word = rest.split_whitespace().next().unwrap_or_default();
    word.trim_end_matches('s')
        .parse()
        .unwrap_or_else(|_| panic!("not a number after {prefix:?} in {line:?}"))
}

#[test]
fn hz_measures_a_10_hz_publisher() {
    let domain = 217;
    let _peer = publisher(
        domain,
        "talker",
        "/chatter",
        "std_msgs/msg/String",
        10.0,
        r#"[["data", "hello world"]]"#,
        false,
    );
    let cli = Cli::start(domain, &["topic", "hz", "/chatter"], Ament::Inherit);
    // The first report comes from few intervals: take the third.
    let mut rate = 0.0;
    for _ in 0..3 {
        let first = cli.line();
        assert!(first.starts_with("average rate: "), "{first}");
        rate = number_after(&first, "average rate: ");
        let second = cli.line();
        assert!(second.starts_with("\tmin: "), "{second}");
        for key in ["\tmin: ", " max: ", " std dev: ", " window: "] {
            number_after(&second, key);
        }
    }
    assert!((7.0..=13.0).contains(&rate), "rate {rate}");
    drop(cli);

    let cli = Cli::start(
        domain,
        &["--json", "topic", "hz", "/chatter", "--window", "20"],
        Ament::Inherit,
    );
    let mut report = serde_json::Value::Null;
    for _ in 0..3 {
        report = serde_json::from_str(&cli.line()).expect("a JSON report");
    }
    let rate = report["average_rate"].as_f64().expect("average_rate");
    assert!((7.0..=13.0).contains(&rate), "{report}");
    assert!(
        report["window"].as_u64().is_some_and(|w| w <= 20),
        "{report}"
    );

    // A filter nothing passes: no report; one that all pass: reports.
    let cli = Cli::start(
        domain,
        &[
            "topic",
            "hz",
            "/chatter",
            "--filter",
            "m.data == 'hello world'",
        ],
        Ament::Inherit,
    );
    assert!(cli.line().starts_with("average rate: "));
}

#[test]
fn bw_reports_the_serialized_sizes() {
    let domain = 218;
    let _peer = publisher(
        domain,
        "talker",
        "/chatter",
        "std_msgs/msg/String",
        10.0,
        r#"[["data", "hello world"]]"#,
        false,
    );
    let cli = Cli::start(domain, &["topic", "bw", "/chatter"], Ament::Inherit);
    assert_eq!(cli.line(), "Subscribed to [/chatter]");
    let first = cli.line();
    assert!(
        first.contains("/s from ") && first.ends_with(" messages"),
        "{first}"
    );
    // 4-byte CDR header + 4-byte length + "hello world\0": 20 bytes; ~200 B/s is below 1000.
    assert!(first.contains(" B/s from "), "{first}");
    assert_eq!(cli.line(), "\tMessage size mean: 20 B min: 20 B max: 20 B");
}

#[test]
fn delay_reports_header_stamp_delays() {
    let domain = 219;
    let _peer = publisher(
        domain,
        "imu",
        "/imu",
        "sensor_msgs/msg/Imu",
        10.0,
        "[]",
        true,
    );
    let cli = Cli::start(domain, &["topic", "delay", "/imu"], Ament::Inherit);
    let first = cli.line();
    assert!(first.starts_with("average delay: "), "{first}");
    let delay = number_after(&first, "average delay: ");
    // Same machine, same clock: well under a second either way.
    assert!(delay.abs() < 1.0, "{first}");
    let second = cli.line();
    assert!(second.starts_with("\tmin: "), "{second}");
    for key in ["\tmin: ", " max: ", " std dev: ", " window: "] {
        number_after(&second, key);
    }

    // A type without a header is refused.
    let _strings = publisher(
        domain,
        "talker",
        "/chatter",
        "std_msgs/msg/String",
        10.0,
        "[]",
        false,
    );
    let (out, code) = Cli::start(domain, &["topic", "delay", "/chatter"], Ament::Inherit)
        .finish(std::time::Duration::from_secs(60));
    assert_eq!((out.as_str(), code), ("", Some(1)));
}
