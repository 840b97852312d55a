//! The backends are crates behind the contract: what `cargo tree` shows of the workspace.
//!
//! - Each backend crate depends on the contract (and, for the DDS ones, the shared DDS layer),
//!   never on another backend nor on the layers above.
//! - The contract and the shared DDS layer depend on no middleware.
//! - A program built on the top crate with only the Zenoh backend links no rustdds and no
//!   Cyclone DDS.

use std::collections::BTreeSet;
use std::process::Command;

/// The packages (names) in the normal dependency tree of `package` with `features` only.
fn tree(package: &str, features: Option<&str>) -> BTreeSet<String> {
    let mut command = Command::new(env!("CARGO"));
    command.args([
        "tree",
        "--offline",
        "--locked",
        "--edges",
        "normal",
        "--prefix",
        "none",
        "--format",
        "{p}",
        "--package",
        package,
    ]);
    if let Some(features) = features {
        command.args(["--no-default-features", "--features", features]);
    }
    let output = command
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run cargo tree");
    assert!(
        output.status.success(),
        "cargo tree -p {package}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .map(str::to_owned)
        .collect()
}

const BACKENDS: [&str; 3] = [
    "horus-ros-rmw-rustdds",
    "horus-ros-rmw-cyclone",
    "horus-ros-rmw-zenoh",
];
const MIDDLEWARE: [&str; 3] = ["rustdds", "cyclors", "zenoh"];

#[test]
fn each_backend_depends_on_the_contract_and_on_no_other_backend() {
    for backend in BACKENDS {
        let deps = tree(backend, None);
        assert!(
            deps.contains("horus-ros-rmw-contract"),
            "{backend}: {deps:?}"
        );
        for other in BACKENDS.iter().filter(|b| **b != backend) {
            assert!(!deps.contains(*other), "{backend} depends on {other}");
        }
        for above in ["horus-ros-rmw", "horus-ros-rmw-implementation"] {
            assert!(!deps.contains(above), "{backend} depends on {above}");
        }
    }
}

#[test]
fn the_contract_and_the_shared_dds_layer_depend_on_no_middleware() {
    for package in ["horus-ros-rmw-contract", "horus-ros-dds-common"] {
        let deps = tree(package, None);
        for middleware in MIDDLEWARE.iter().chain(&BACKENDS) {
            assert!(
                !deps.contains(*middleware),
                "{package} depends on {middleware}"
            );
        }
    }
}

#[test]
fn a_program_with_only_the_zenoh_backend_links_no_dds() {
    let deps = tree("horus-ros-nodes", Some("zenoh"));
    assert!(deps.contains("horus-ros-rmw-zenoh"), "{deps:?}");
    assert!(deps.contains("zenoh"), "{deps:?}");
    for dds in [
        "rustdds",
        "cyclors",
        "horus-ros-rmw-rustdds",
        "horus-ros-rmw-cyclone",
    ] {
        assert!(!deps.contains(dds), "{dds} in a Zenoh-only build: {deps:?}");
    }
}
