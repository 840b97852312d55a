//! The global `--backend` option: `--backend cyclone` joins with Cyclone DDS and sees the graph,
//! an unknown value is a clap usage error, and `--help` shows it with its environment variable.
//!
//! Domain 136. Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test backend_option`.

mod common;

use std::process::Command;
use std::time::Duration;

use common::{cyclone_config, expect};
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_rmw::{Backend, Context};
use horus_ros_services::{ServiceClient, ServiceServerBuilder};

const D: u32 = 136;

/// Runs `horus-ros args…` with `HORUS_ROS_BACKEND` set to `env_backend` (or removed), without
/// joining any domain when clap refuses the arguments.
fn horus_with_env(args: &[&str], env_backend: Option<&str>) -> std::process::Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command.args(args).env_remove("ROS_DOMAIN_ID");
    match env_backend {
        Some(b) => command.env("HORUS_ROS_BACKEND", b),
        None => command.env_remove("HORUS_ROS_BACKEND"),
    };
    command.output().expect("run horus-ros")
}

#[test]
fn backend_cyclone_lists_services() {
    // Cyclone DDS's configuration for this process and the CLI it starts: loopback only.
    std::env::set_var("CYCLONEDDS_URI", cyclone_config());
    let context = Context::builder()
        .domain_id(D)
        .backend(Backend::Cyclone)
        .build()
        .expect("Cyclone DDS context");
    let node = context.create_node("backend_test", "/").expect("node");
    let _server = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&node)
        .name("/backend_add")
        .on_request(|r| {
            Ok(horus_ros_msgs::example_interfaces::srv::AddTwoIntsResponse { sum: r.a + r.b })
        })
        .build()
        .expect("server");
    let client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/backend_add")
        .build()
        .expect("client");
    assert!(client.wait_for_service(Duration::from_secs(8)));

    expect(
        D,
        &["--backend", "cyclone", "service", "list"],
        "/backend_add\n",
    );
    // The option's value wins over HORUS_ROS_BACKEND; the rustdds backend sees it as well.
    expect(
        D,
        &["--backend", "rustdds", "service", "list"],
        "/backend_add\n",
    );
    // Case-insensitive, as HORUS_ROS_BACKEND.
    expect(D, &["--backend", "Cyclone", "service", "list", "-c"], "1\n");
}

#[test]
fn unknown_backend_is_a_usage_error() {
    let out = horus_with_env(&["--backend", "fastdds", "service", "list"], None);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(out.stdout.is_empty());
    assert!(
        stderr.contains("invalid value 'fastdds' for '--backend <BACKEND>'")
            && stderr.contains("[possible values: rustdds, cyclone]"),
        "{stderr}"
    );
    // The same from the environment variable it defaults to.
    let out = horus_with_env(&["service", "list"], Some("fastdds"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("invalid value 'fastdds' for '--backend <BACKEND>'"),
        "{stderr}"
    );
}

#[test]
fn help_shows_the_backend_option() {
    let out = horus_with_env(&["--help"], None);
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{help}");
    assert!(help.contains("--backend <BACKEND>"), "{help}");
    assert!(help.contains("[env: HORUS_ROS_BACKEND"), "{help}");
    assert!(help.contains("[default: rustdds]"), "{help}");
    assert!(
        help.contains("rustdds") && help.contains("cyclone"),
        "{help}"
    );
}
