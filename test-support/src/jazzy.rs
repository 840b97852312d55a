//! Where the tests find ROS 2 Jazzy: the wheels and the real peers that `scripts/setup` installs
//! (rclpy on each of the three RMWs, ros2cli, rmw_zenohd, the demo nodes), and which RMW a test
//! run's peers use.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The workspace's `target/jazzy-env`, where `scripts/setup` writes `run` and `python`.
fn jazzy_env() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/jazzy-env")
}

/// The Python interpreter that has the ROS 2 wheels, run in the real peers' environment (so
/// rclpy loads the RMW that `RMW_IMPLEMENTATION` or [`PEER_RMW_VAR`] names):
/// `HORUS_ROS_JAZZY_PYTHON`, else `target/jazzy-env/python` (made by `scripts/setup`), else
/// `HORUS_ROS_INTEROP_PYTHON` or the workspace's venv (`target/interop-venv`) as they are, else
/// `python3`.
pub fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("HORUS_ROS_JAZZY_PYTHON") {
        return PathBuf::from(p);
    }
    let wrapped = jazzy_env().join("python");
    if wrapped.exists() {
        return wrapped;
    }
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

/// A command `program args…` run in the real peers' environment (`target/jazzy-env/run`):
/// `ros2`, `rmw_zenohd`, the demo nodes. Panics, saying what to run, when `scripts/setup` has
/// not made it.
pub fn command(program: &str) -> Command {
    let run = jazzy_env().join("run");
    assert!(
        run.exists(),
        "{} is missing: scripts/setup installs the real ROS 2 Jazzy peers",
        run.display()
    );
    let mut command = Command::new(run);
    command.arg(program);
    command
}

/// The environment variable that names the RMW of every Jazzy peer that does not choose its own
/// (`scripts/test` sets it per run); unset means rmw_fastrtps_cpp, Jazzy's default.
pub const PEER_RMW_VAR: &str = "HORUS_ROS_PEER_RMW";

/// An RMW implementation a real Jazzy peer runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rmw {
    /// rmw_fastrtps_cpp 8.4.3 on Fast DDS 2.14.5 (the wheels), Jazzy's default.
    FastRtps,
    /// rmw_cyclonedds_cpp 2.2.2 on Cyclone DDS 0.10.2.
    CycloneDds,
    /// rmw_zenoh_cpp 0.2.10, through a router (`rmw_zenohd`).
    Zenoh,
}

impl Rmw {
    /// All three, in Jazzy's order of precedence.
    pub const ALL: [Rmw; 3] = [Rmw::FastRtps, Rmw::CycloneDds, Rmw::Zenoh];

    /// Its `RMW_IMPLEMENTATION` name.
    pub fn name(self) -> &'static str {
        match self {
            Rmw::FastRtps => "rmw_fastrtps_cpp",
            Rmw::CycloneDds => "rmw_cyclonedds_cpp",
            Rmw::Zenoh => "rmw_zenoh_cpp",
        }
    }

    /// The RMW of a name as `RMW_IMPLEMENTATION` spells it.
    pub fn from_name(name: &str) -> Option<Rmw> {
        Rmw::ALL.into_iter().find(|r| r.name() == name)
    }

    /// The RMW of this run's peers: [`PEER_RMW_VAR`], else rmw_fastrtps_cpp. Panics on a name
    /// that is not one of the three.
    pub fn of_peers() -> Rmw {
        match std::env::var(PEER_RMW_VAR) {
            Ok(name) if !name.is_empty() => Rmw::from_name(&name)
                .unwrap_or_else(|| panic!("{PEER_RMW_VAR}={name}: not one of the three RMWs")),
            _ => Rmw::FastRtps,
        }
    }

    /// Whether it is a DDS implementation (the graph on `ros_discovery_info`).
    pub fn is_dds(self) -> bool {
        self != Rmw::Zenoh
    }

    /// Whether its services correlate a reply with its request through the DDS
    /// `related_sample_identity` (rmw_fastrtps' convention), which the Cyclone backend can
    /// neither send nor read: calls between its nodes and ours on the Cyclone backend are
    /// refused. rmw_cyclonedds carries the request id in the payload (a header our Cyclone
    /// backend speaks), rmw_zenoh in the query's attachment.
    pub fn needs_sample_identity(self) -> bool {
        self == Rmw::FastRtps
    }

    /// The DDS vendor id its participants announce (RTPS `VendorId_t`, the first two bytes of
    /// their GUID prefix): Fast DDS 1.15, Cyclone DDS 1.16; none for Zenoh.
    pub fn dds_vendor_id(self) -> Option<[u8; 2]> {
        match self {
            Rmw::FastRtps => Some([0x01, 0x0f]),
            Rmw::CycloneDds => Some([0x01, 0x10]),
            Rmw::Zenoh => None,
        }
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
