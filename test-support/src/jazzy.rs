//! Where the tests find ROS 2 Jazzy: the wheels `scripts/setup` installs.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The Python interpreter that has the ROS 2 wheels: `HORUS_ROS_INTEROP_PYTHON`, else the
/// workspace's venv (`target/interop-venv`, made by `scripts/setup`) if it exists, else `python3`.
pub fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("HORUS_ROS_INTEROP_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/interop-venv/bin/python");
    if venv.exists() {
        venv
    } else {
        PathBuf::from("python3")
    }
}

/// `<prefix>/share` of [`python`]'s environment: each package's interface files (`.msg`,
/// `.srv`, `.action`, `.idl`) and Jazzy's own type descriptions and hashes (`.json`).
pub fn share_dir() -> Result<PathBuf, String> {
    static SHARE: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    SHARE
        .get_or_init(|| {
            let out = Command::new(python())
                .args(["-c", "import sys; print(sys.prefix)"])
                .output()
                .map_err(|e| format!("running {}: {e}", python().display()))?;
            let prefix = String::from_utf8_lossy(&out.stdout).trim().to_owned();
            let share = Path::new(&prefix).join("share");
            if out.status.success() && share.join("rclpy").is_dir() {
                Ok(share)
            } else {
                Err(format!(
                    "{} has no ROS 2 wheels under {} (scripts/setup installs them; \
                     HORUS_ROS_INTEROP_PYTHON names the interpreter)",
                    python().display(),
                    share.display()
                ))
            }
        })
        .clone()
}
