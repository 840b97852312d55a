//! The global `--backend` option: `--backend cyclone` joins with Cyclone DDS and sees the graph,
//! an unknown value is a clap usage error, and `--help` shows it with its environment variable.
//! Without it (and without HORUS_ROS_BACKEND), RMW_IMPLEMENTATION chooses, as it does for rcl.
//!
//! Domains 136, 141 and 142. Run inside the private network namespace:
//! `scripts/isolated cargo test -p horus-ros-cli --test backend_option`.

mod common;

use std::collections::HashMap;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{cyclone_config, expect, RUN_LIMIT};
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_rmw::{Backend, Context, DiscoveryEvent, VendorId};
use horus_ros_services::{EndpointBuilder, ServiceClient, ServiceServer};
use horus_ros_test_support::{wait_with_output, Output};

const D: u32 = 136;
/// The domain of the overrides of an unsupported RMW_IMPLEMENTATION.
const D_OVERRIDE: u32 = 141;
/// The domain where RMW_IMPLEMENTATION chooses the backend.
const D_RMW: u32 = 142;

/// `horus-ros args…` with `HORUS_ROS_BACKEND` set to `env_backend` (or removed) and
/// `RMW_IMPLEMENTATION` set to `rmw` (or removed): the suite's own HORUS_ROS_BACKEND would
/// otherwise win over RMW_IMPLEMENTATION.
fn horus_command(args: &[&str], env_backend: Option<&str>, rmw: Option<&str>) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command
        .args(args)
        .env_remove("ROS_DOMAIN_ID")
        .env("RUST_LOG", "error")
        .env("CYCLONEDDS_URI", cyclone_config());
    match env_backend {
        Some(b) => command.env("HORUS_ROS_BACKEND", b),
        None => command.env_remove("HORUS_ROS_BACKEND"),
    };
    match rmw {
        Some(r) => command.env("RMW_IMPLEMENTATION", r),
        None => command.env_remove("RMW_IMPLEMENTATION"),
    };
    command
}

/// Runs `horus-ros args…` with `HORUS_ROS_BACKEND` set to `env_backend` (or removed) and no
/// RMW_IMPLEMENTATION, without joining any domain when clap refuses the arguments.
fn horus_with_env(args: &[&str], env_backend: Option<&str>) -> Output {
    output(horus_command(args, env_backend, None))
}

/// Runs `command` with its output piped, at most [`RUN_LIMIT`].
fn output(mut command: Command) -> Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start horus-ros");
    wait_with_output(&mut child, RUN_LIMIT).expect("horus-ros output")
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
    let _server = ServiceServer::<AddTwoInts>::builder()
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
    let stderr = &out.stderr;
    assert_eq!(out.code(), Some(2), "{stderr}");
    assert!(out.stdout.is_empty());
    assert!(
        stderr.contains("invalid value 'fastdds' for '--backend <BACKEND>'")
            && stderr.contains("[possible values: rustdds, cyclone, zenoh]"),
        "{stderr}"
    );
    // The same from the environment variable it defaults to.
    let out = horus_with_env(&["service", "list"], Some("fastdds"));
    let stderr = &out.stderr;
    assert_eq!(out.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("invalid value 'fastdds' for '--backend <BACKEND>'"),
        "{stderr}"
    );
}

#[test]
fn help_shows_the_backend_option() {
    let out = horus_with_env(&["--help"], None);
    let help = &out.stdout;
    assert_eq!(out.code(), Some(0), "{help}");
    assert!(help.contains("--backend <BACKEND>"), "{help}");
    assert!(help.contains("[env: HORUS_ROS_BACKEND"), "{help}");
    // No default of its own: unset, the environment chooses (HORUS_ROS_BACKEND, RMW_IMPLEMENTATION).
    assert!(!help.contains("[default: rustdds]"), "{help}");
    assert!(
        help.contains(
            "DDS implementation to join with (default: HORUS_ROS_BACKEND, else as \
             RMW_IMPLEMENTATION says)"
        ),
        "{help}"
    );
    assert!(help.contains("rmw_cyclonedds_cpp means cyclone"), "{help}");
    assert!(
        help.contains("rustdds") && help.contains("cyclone"),
        "{help}"
    );
}

/// The message of an unsupported RMW_IMPLEMENTATION, as the CLI prints it.
fn unsupported_rmw_message(value: &str) -> String {
    format!(
        "RMW_IMPLEMENTATION='{value}' is not supported by horus-ros: it speaks rmw_fastrtps_cpp \
         (rustdds), rmw_fastrtps_dynamic_cpp (rustdds), rmw_cyclonedds_cpp (cyclone), \
         rmw_zenoh_cpp (zenoh) or, when unset or empty, rmw_fastrtps_cpp (rustdds); set \
         HORUS_ROS_BACKEND to rustdds, cyclone or zenoh to override it (or pass --backend)\n"
    )
}

#[test]
fn unsupported_rmw_implementation_is_a_clear_error() {
    for rmw in [
        "rmw_zenoh",
        "rmw_connextdds",
        "rmw_gurumdds_cpp",
        "rmw_cyclonedds",
        "RMW_FASTRTPS_CPP",
    ] {
        let out = output(horus_command(&["node", "list"], None, Some(rmw)));
        let stderr = &out.stderr;
        assert_eq!(out.code(), Some(1), "{rmw}: {stderr}");
        assert!(out.stdout.is_empty(), "{rmw}");
        assert_eq!(out.stderr, unsupported_rmw_message(rmw), "{rmw}");
    }
    // An empty HORUS_ROS_BACKEND is unset: RMW_IMPLEMENTATION still decides.
    let out = output(horus_command(
        &["node", "list"],
        Some(""),
        Some("rmw_connextdds"),
    ));
    assert_eq!(out.code(), Some(1));
    assert_eq!(out.stderr, unsupported_rmw_message("rmw_connextdds"));
    // HORUS_ROS_BACKEND and --backend override it: the command joins the domain and lists
    // its own hidden node.
    for (args, env_backend) in [
        (&["node", "list", "-a"][..], Some("rustdds")),
        (&["node", "list", "-a"][..], Some("cyclone")),
        (&["--backend", "rustdds", "node", "list", "-a"][..], None),
        (&["--backend", "cyclone", "node", "list", "-a"][..], None),
    ] {
        let mut command = horus_command(args, env_backend, Some("rmw_connextdds"));
        command.args([
            "--domain-id",
            &D_OVERRIDE.to_string(),
            "--spin-time",
            "0.2",
            "--no-daemon",
        ]);
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start horus-ros");
        let pid = child.id();
        let out = wait_with_output(&mut child, RUN_LIMIT).expect("horus-ros output");
        let stdout = &out.stdout;
        assert_eq!(
            out.code(),
            Some(0),
            "{args:?} {env_backend:?}: {}",
            out.stderr
        );
        assert!(
            stdout.lines().any(|l| l == format!("/_horus_ros_{pid}")),
            "{args:?} {env_backend:?}: {stdout}"
        );
    }
}

/// With HORUS_ROS_BACKEND removed and no `--backend`, RMW_IMPLEMENTATION chooses the DDS the
/// CLI joins with: seen from outside, through the vendor id of the participant whose
/// `ros_discovery_info` lists the CLI's node `_horus_ros_<pid>` (Cyclone DDS 0x0110, RustDDS
/// 0x0112).
#[test]
fn rmw_implementation_chooses_the_backend() {
    std::env::set_var("CYCLONEDDS_URI", cyclone_config());
    // This process's own participant runs on the suite's backend: both can read vendor ids.
    let context = Context::builder()
        .domain_id(D_RMW)
        .build()
        .expect("context");
    let mut feed = context.discovery_feed().expect("discovery feed");
    let mut vendors: HashMap<String, VendorId> = HashMap::new();
    for (rmw, want) in [
        (Some("rmw_cyclonedds_cpp"), VendorId::CYCLONE_DDS),
        (Some("rmw_fastrtps_cpp"), VendorId::RUSTDDS),
        (Some("rmw_fastrtps_dynamic_cpp"), VendorId::RUSTDDS),
        (Some(""), VendorId::RUSTDDS),
        (None, VendorId::RUSTDDS),
    ] {
        // `graph --watch` stays on the graph until it is stopped, however long discovery takes.
        let mut child = horus_command(
            &["--domain-id", &D_RMW.to_string(), "graph", "--watch"],
            None,
            rmw,
        )
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start horus-ros graph --watch");
        let node = format!("_horus_ros_{}", child.id());
        let deadline = Instant::now() + Duration::from_secs(10);
        let seen = loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match feed.next_timeout(left) {
                Some(DiscoveryEvent::ParticipantDiscovered(p)) => {
                    vendors.insert(p.gid.to_string(), p.vendor_id);
                }
                Some(DiscoveryEvent::ParticipantEntities(info))
                    if info
                        .node_entities_info_seq
                        .iter()
                        .any(|n| n.node_name == node) =>
                {
                    break vendors.get(&info.gid.to_string()).copied();
                }
                Some(_) => {}
                None => break None,
            }
        };
        let _ = child.kill();
        let _ = child.wait();
        assert_eq!(seen, Some(want), "RMW_IMPLEMENTATION={rmw:?}: node {node}");
    }
}
