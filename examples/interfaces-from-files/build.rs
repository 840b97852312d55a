//! Generates the Rust types of the example's interface packages with horus-ros-codegen:
//!
//! - `horus_demo_msgs` (`interfaces/horus_demo_msgs/`), the example's own package: its
//!   `std_msgs/Header` is the type compiled into horus-ros-msgs;
//! - `test_msgs`, which the ROS 2 Jazzy wheels ship, so that the example can talk to an rclpy
//!   node (rclpy only loads the interfaces built for it). It comes from an install prefix: those
//!   of `AMENT_PREFIX_PATH` (a sourced ROS 2 install), else the virtual environment of
//!   `HORUS_ROS_INTEROP_PYTHON` (`<venv>/bin/python`, where `scripts/setup` installs the wheels).
//!
//! Without test_msgs anywhere, only `horus_demo_msgs` is generated (the workspace builds before
//! the wheels are installed) and the cfg `no_test_msgs` is set: the binary that needs test_msgs
//! then exits saying how to get it.

use std::path::{Path, PathBuf};

/// The package from the wheels that the rclpy binary uses.
const WHEEL_PACKAGE: &str = "test_msgs";

fn main() {
    println!("cargo::rustc-check-cfg=cfg(no_test_msgs)");
    println!("cargo:rerun-if-env-changed=AMENT_PREFIX_PATH");
    println!("cargo:rerun-if-env-changed=HORUS_ROS_INTEROP_PYTHON");
    println!("cargo:rerun-if-changed=build.rs");

    let mut builder = horus_ros_codegen::Builder::new().package_dir("interfaces/horus_demo_msgs");
    match wheels_prefix() {
        Some(prefix) => {
            // AMENT_PREFIX_PATH is searched by the builder itself; the venv is added here.
            builder = builder.prefix(prefix).prefix_package(WHEEL_PACKAGE);
        }
        None => {
            println!(
                "cargo:warning=no {WHEEL_PACKAGE} in AMENT_PREFIX_PATH nor in the venv of \
                 HORUS_ROS_INTEROP_PYTHON: only horus_demo_msgs is generated"
            );
            println!("cargo:rustc-cfg=no_test_msgs");
        }
    }
    if let Err(e) = builder.generate() {
        // A build script reports with a panic: cargo shows the message.
        panic!("generating the interfaces: {e}");
    }
}

/// The install prefix that has the wheel package: the first of `AMENT_PREFIX_PATH`, else the
/// venv of `HORUS_ROS_INTEROP_PYTHON`.
fn wheels_prefix() -> Option<PathBuf> {
    let has_package = |prefix: &Path| prefix.join("share").join(WHEEL_PACKAGE).is_dir();
    if let Some(paths) = std::env::var_os("AMENT_PREFIX_PATH") {
        if let Some(prefix) = std::env::split_paths(&paths).find(|p| has_package(p)) {
            return Some(prefix);
        }
    }
    let python = PathBuf::from(std::env::var_os("HORUS_ROS_INTEROP_PYTHON")?);
    let venv = python.parent()?.parent()?.to_owned();
    has_package(&venv).then_some(venv)
}
