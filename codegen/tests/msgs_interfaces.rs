//! The ROS packages compiled into horus-ros-msgs (`msgs/src/interfaces/<package>.rs`) are this
//! generator's output for the Jazzy wheels' interface files, without their comments: regenerated
//! here and compared byte for byte. `HORUS_ROS_REGENERATE=1` writes them instead (after a change
//! to the generator; review the diff).

use std::path::{Path, PathBuf};

use horus_ros_codegen::Builder;
use horus_ros_test_support::jazzy::share_dir;

/// The packages horus-ros-msgs compiles in (closed under their dependencies).
const PACKAGES: &[&str] = &[
    "action_msgs",
    "builtin_interfaces",
    "geometry_msgs",
    "lifecycle_msgs",
    "rcl_interfaces",
    "rosgraph_msgs",
    "sensor_msgs",
    "service_msgs",
    "std_msgs",
    "std_srvs",
    "type_description_interfaces",
    "unique_identifier_msgs",
];

fn committed_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../msgs/src/interfaces")
}

#[test]
fn msgs_interfaces_are_this_generators_output() {
    let share = share_dir().unwrap_or_else(|e| panic!("{e}"));
    let out =
        std::env::temp_dir().join(format!("horus-ros-msgs-interfaces-{}", std::process::id()));
    let mut builder = Builder::new()
        .ament_prefix_path(false)
        .compiled_types(false)
        .comments(false)
        .prefix(share.parent().expect("a prefix"))
        .out_dir(&out);
    for p in PACKAGES {
        builder = builder.prefix_package(p);
    }
    let generated = builder.generate().unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = generated.packages.keys().map(String::as_str).collect();
    assert_eq!(
        names, PACKAGES,
        "the packages must be closed under their dependencies"
    );
    let regenerate = std::env::var_os("HORUS_ROS_REGENERATE").is_some();
    let mut stale = Vec::new();
    for (package, file) in &generated.packages {
        let fresh = std::fs::read_to_string(file).expect("generated file");
        let committed = committed_dir().join(format!("{package}.rs"));
        if regenerate {
            std::fs::create_dir_all(committed_dir()).expect("msgs/src/interfaces");
            std::fs::write(&committed, &fresh).expect("write");
        } else if std::fs::read_to_string(&committed).ok().as_deref() != Some(fresh.as_str()) {
            stale.push(committed.display().to_string());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        stale.is_empty(),
        "not this generator's output (HORUS_ROS_REGENERATE=1 cargo test -p horus-ros-codegen \
         --test msgs_interfaces rewrites them): {stale:?}"
    );
    println!(
        "{} packages, {} interfaces: as generated",
        PACKAGES.len(),
        generated.interfaces
    );
}
