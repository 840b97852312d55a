//! Shared by the tests that run the crate's examples as the programs they are.

use std::path::PathBuf;

/// The built example `name` (`cargo test` builds every example of the crate beside the tests).
pub fn example_path(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("current exe");
    let dir = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>");
    let path = dir.join("examples").join(name);
    assert!(path.exists(), "{} not built", path.display());
    path
}
