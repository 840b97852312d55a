//! Generates, with horus-ros-codegen, every interface package of the Jazzy wheels that
//! `scripts/setup` installs (found from `HORUS_ROS_INTEROP_PYTHON`, the venv's interpreter), so
//! the tests can compare the generated types with Jazzy's own descriptions, hashes and CDR.
//! Without the wheels (a build before `scripts/setup`), nothing is generated and the tests that
//! need them fail saying so.

use std::path::{Path, PathBuf};

fn main() {
    println!("cargo::rustc-check-cfg=cfg(jazzy_interfaces)");
    println!("cargo:rerun-if-env-changed=HORUS_ROS_INTEROP_PYTHON");
    println!("cargo:rerun-if-changed=build.rs");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("jazzy");
    let Some(share) = wheels_share() else {
        println!(
            "cargo:warning=no Jazzy wheels (HORUS_ROS_INTEROP_PYTHON unset or without them): \
             the generated-type tests will fail until scripts/setup has run"
        );
        return;
    };
    let prefix = share.parent().unwrap_or(&share).to_owned();
    let mut builder = horus_ros_codegen::Builder::new()
        .ament_prefix_path(false)
        .compiled_types(false)
        .prefix(&prefix)
        .out_dir(&out);
    for package in interface_packages(&share) {
        builder = builder.prefix_package(&package);
    }
    if let Err(e) = builder.generate() {
        panic!("generating the Jazzy wheels' interfaces: {e}");
    }
    println!("cargo:rustc-cfg=jazzy_interfaces");
}

/// `<venv>/share` if `HORUS_ROS_INTEROP_PYTHON` is `<venv>/bin/python` and it has the wheels.
fn wheels_share() -> Option<PathBuf> {
    let python = PathBuf::from(std::env::var_os("HORUS_ROS_INTEROP_PYTHON")?);
    let share = python.parent()?.parent()?.join("share");
    share.join("test_msgs").is_dir().then_some(share)
}

/// Every package under `share` with interface files, sorted.
fn interface_packages(share: &Path) -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir(share)
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .filter(|e| {
            ["msg", "srv", "action"]
                .iter()
                .any(|k| e.path().join(k).is_dir())
        })
        .filter_map(|e| e.file_name().into_string().ok())
        .collect();
    out.sort();
    out
}
