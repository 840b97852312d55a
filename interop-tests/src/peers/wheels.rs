//! What the ROS 2 wheels install beside each interface: `<prefix>/share/<pkg>/{msg,srv,action}/`
//! holds its `.msg`/`.srv`/`.action`, `.idl` and a `.json` with Jazzy's type description
//! (`type_description_msg`, rosidl_generator_type_description's output) and the RIHS01 hash of
//! every type it defines (`type_hashes`).

use std::path::{Path, PathBuf};

use serde_json::Value;

/// `<prefix>/share` of the test environment's interpreter ([`crate::python`]).
pub fn share_dir() -> Result<PathBuf, String> {
    horus_ros_test_support::jazzy::share_dir()
}

/// The `.json` file of the interface defining `type_name` (`pkg/srv/Name`, or a type the
/// interface adds: `pkg/srv/Name_Request`, `pkg/action/Name_SendGoal_Event`, …).
pub fn interface_file(type_name: &str) -> Result<PathBuf, String> {
    let mut parts = type_name.splitn(3, '/');
    let (Some(package), Some(kind), Some(leaf)) = (parts.next(), parts.next(), parts.next()) else {
        return Err(format!("not a ROS type name: {type_name}"));
    };
    // Interface names have no `_`: what follows one is a type the interface adds.
    let interface = leaf.split('_').next().unwrap_or(leaf);
    Ok(share_dir()?
        .join(package)
        .join(kind)
        .join(format!("{interface}.json")))
}

/// The parsed `.json` file at `path`.
pub fn read_json(path: &Path) -> Result<Value, String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("parsing {}: {e}", path.display()))
}

/// The RIHS01 hash the wheels give `type_name` (`RIHS01_…`).
pub fn wheel_hash(type_name: &str) -> Result<String, String> {
    let path = interface_file(type_name)?;
    read_json(&path)?["type_hashes"]
        .as_array()
        .and_then(|hashes| {
            hashes
                .iter()
                .find(|h| h["type_name"] == type_name)
                .and_then(|h| h["hash_string"].as_str())
        })
        .map(str::to_owned)
        .ok_or_else(|| format!("no hash of {type_name} in {}", path.display()))
}

/// Every interface `.json` of every package, sorted by path.
pub fn interface_files() -> Result<Vec<PathBuf>, String> {
    let share = share_dir()?;
    let mut files = Vec::new();
    let packages =
        std::fs::read_dir(&share).map_err(|e| format!("reading {}: {e}", share.display()))?;
    for package in packages.filter_map(Result::ok) {
        for kind in ["msg", "srv", "action"] {
            let Ok(entries) = std::fs::read_dir(package.path().join(kind)) else {
                continue;
            };
            files.extend(
                entries
                    .filter_map(Result::ok)
                    .map(|e| e.path())
                    .filter(|p| p.extension().is_some_and(|x| x == "json")),
            );
        }
    }
    files.sort();
    Ok(files)
}
