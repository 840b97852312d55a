//! The Fibonacci actions compiled into this crate (`src/interfaces/<package>.rs`, for the
//! examples, tests and benchmarks) are horus-ros-codegen's output for `interfaces/<package>/`:
//! regenerated here and compared byte for byte. `HORUS_ROS_REGENERATE=1` writes them instead.

use std::path::Path;

use horus_ros_codegen::Builder;

#[test]
fn compiled_fibonacci_actions_are_the_generators_output() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!(
        "horus-ros-actions-interfaces-{}",
        std::process::id()
    ));
    let generated = Builder::new()
        .ament_prefix_path(false)
        .comments(false)
        .package_dir(root.join("interfaces/test_msgs"))
        .package_dir(root.join("interfaces/action_tutorials_interfaces"))
        .out_dir(&out)
        .generate()
        .unwrap_or_else(|e| panic!("{e}"));
    let regenerate = std::env::var_os("HORUS_ROS_REGENERATE").is_some();
    let mut stale = Vec::new();
    for (package, file) in &generated.packages {
        let fresh = std::fs::read_to_string(file).expect("generated file");
        let committed = root.join(format!("src/interfaces/{package}.rs"));
        if regenerate {
            std::fs::write(&committed, &fresh).expect("write");
        } else if std::fs::read_to_string(&committed).ok().as_deref() != Some(fresh.as_str()) {
            stale.push(committed.display().to_string());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        stale.is_empty(),
        "stale (HORUS_ROS_REGENERATE=1 cargo test -p horus-ros-actions --test interfaces): {stale:?}"
    );
}
