//! The daemon: a background `horus-ros` process that keeps one participant and its live graph,
//! so that the query verbs answer completely at once instead of discovering the graph each time
//! (ros2cli's daemon, `ros2cli/daemon/__init__.py` and `ros2cli/node/daemon.py`, Jazzy).
//!
//! One daemon serves one graph: a user (uid), a domain, a backend and the discovery settings
//! that change what is discovered (`ROS_AUTOMATIC_DISCOVERY_RANGE`, `ROS_STATIC_PEERS`,
//! `ROS_LOCALHOST_ONLY` as rcl resolves them, and `CYCLONEDDS_URI` on the Cyclone backend): all
//! of them make its [`DaemonKey`], which names its socket. ros2cli keys its daemon on the domain
//! alone (localhost TCP port 11511 + domain id) and asserts the RMW implementation at start.
//!
//! The socket is a Unix stream socket in the abstract namespace (no file, gone with the
//! process), which is scoped to the network namespace exactly as ros2cli's localhost port is.
//! The protocol is [`protocol`]; the daemon's side [`server`], the verbs' side [`client`].

pub mod client;
pub mod protocol;
pub mod server;
pub mod spawn;

use std::collections::BTreeMap;
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::SocketAddr;
use std::time::Duration;

use horus_ros_rmw::context::env::{read_environment, DomainId, DomainIdError};
use horus_ros_rmw::Backend;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::Global;

/// How long the daemon lives without a graph request (ros2cli `daemon/__init__.py`: `serve`'s
/// `timeout`, `--timeout` default `2 * 60 * 60` seconds).
pub const DEFAULT_IDLE_TIMEOUT: Duration = Duration::from_secs(2 * 60 * 60);

/// How long `daemon start` waits for the daemon to be ready, and `daemon stop` for it to be
/// gone (ros2cli `verb/daemon/start.py`, `stop.py`: `timeout=10.0`).
pub const START_STOP_TIMEOUT: Duration = Duration::from_secs(10);

/// Why the daemon key of a command could not be made: its environment is invalid.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DaemonKeyError {
    /// `ROS_DOMAIN_ID` or `--domain-id` is out of range or malformed.
    #[error(transparent)]
    Domain(#[from] DomainIdError),
    /// The backend the environment asks for is unknown or unsupported.
    #[error(transparent)]
    Backend(#[from] horus_ros_rmw::BackendError),
}

/// Everything that decides which graph a daemon sees: the daemon answers only requests with the
/// same key, and its socket is named after it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DaemonKey {
    /// The DDS domain.
    pub domain_id: u16,
    /// The backend (`rustdds` | `cyclone`).
    pub backend: String,
    /// The automatic discovery range as rcl resolves it (`ROS_LOCALHOST_ONLY` included).
    pub discovery_range: String,
    /// The static peers as rcl keeps them.
    pub static_peers: Vec<String>,
    /// The backend's own configuration variables that are set, by name
    /// ([`Backend::configuration_env`]: `CYCLONEDDS_URI` on Cyclone DDS, none on rustdds).
    pub backend_environment: BTreeMap<String, String>,
}

impl DaemonKey {
    /// The key of the graph a command with these options joins, read from the environment as
    /// [`Context::builder`](horus_ros_rmw::Context::builder) reads it.
    pub fn of(global: &Global) -> Result<Self, DaemonKeyError> {
        Self::with_env(global, |k| std::env::var(k).ok())
    }

    /// [`of`](Self::of) with the environment looked up through `get`.
    fn with_env(
        global: &Global,
        get: impl Fn(&str) -> Option<String>,
    ) -> Result<Self, DaemonKeyError> {
        let environment = read_environment(&get)?;
        let domain = match global.domain_id {
            Some(d) => DomainId::new(d)?,
            None => environment.domain_id,
        };
        // As the context chooses: --backend, else HORUS_ROS_BACKEND, else RMW_IMPLEMENTATION.
        let backend: Backend = match global.backend() {
            Some(b) => b,
            None => Backend::from_env_with(&get)?,
        };
        Ok(Self {
            domain_id: domain.get(),
            backend: backend.name().to_owned(),
            discovery_range: environment.discovery.range.to_string(),
            static_peers: environment.discovery.static_peers,
            backend_environment: backend
                .configuration_env()
                .iter()
                .filter_map(|&name| Some((name.to_owned(), get(name)?)))
                .collect(),
        })
    }

    /// The name of the daemon's socket in the abstract namespace:
    /// `horus-ros-daemon/<uid>/<domain>/<backend>/<digest>`, the digest (SHA-256, 16 hex
    /// digits) covering the whole key.
    pub fn socket_name(&self) -> String {
        let json = serde_json::to_vec(self).unwrap_or_default();
        let digest = Sha256::digest(&json);
        let hex: String = digest[..8].iter().map(|b| format!("{b:02x}")).collect();
        format!(
            "horus-ros-daemon/{}/{}/{}/{hex}",
            nix::unistd::getuid(),
            self.domain_id,
            self.backend
        )
    }

    /// The socket's address.
    pub fn address(&self) -> std::io::Result<SocketAddr> {
        SocketAddr::from_abstract_name(self.socket_name().as_bytes())
    }
}

/// The daemon's hidden node name: `_horus_ros_daemon_<domain>_<32 hex digits>`, random, as
/// ros2cli's `_ros2cli_daemon_<domain>_<uuid4 hex>` (`daemon/__init__.py`, `serve`).
pub fn node_name(domain_id: u16) -> String {
    let mut bytes = [0u8; 16];
    let random = std::fs::File::open("/dev/urandom")
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut bytes));
    if random.is_err() {
        // No randomness to be had: the process id and the time keep it unique on this host.
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap_or_default()
            .as_nanos();
        bytes[..4].copy_from_slice(&std::process::id().to_be_bytes());
        bytes[4..].copy_from_slice(&now.to_be_bytes()[4..]);
    }
    let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    format!("_horus_ros_daemon_{domain_id}_{hex}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BackendArg;
    use std::collections::HashMap;

    fn global(domain_id: Option<u32>, backend: BackendArg) -> Global {
        Global {
            domain_id,
            spin_time: 0.5,
            no_daemon: false,
            json: false,
            backend: Some(crate::BackendChoice(Some(backend))),
        }
    }

    fn key(global: &Global, env: &[(&str, &str)]) -> DaemonKey {
        let env: HashMap<String, String> = env
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        DaemonKey::with_env(global, |k| env.get(k).cloned()).expect("key")
    }

    #[test]
    fn settings_that_change_the_graph_change_the_socket() {
        let rustdds = global(Some(7), BackendArg::Rustdds);
        let base = key(&rustdds, &[]);
        assert_eq!(base.domain_id, 7);
        assert_eq!(base.discovery_range, "SUBNET");
        let name = base.socket_name();
        assert!(name.starts_with("horus-ros-daemon/"), "{name}");
        assert!(name.contains("/7/rustdds/"), "{name}");
        for env in [
            &[("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")][..],
            &[("ROS_STATIC_PEERS", "192.168.0.2")][..],
            &[("ROS_LOCALHOST_ONLY", "1")][..],
        ] {
            assert_ne!(key(&rustdds, env).socket_name(), name, "{env:?}");
        }
        assert_ne!(
            key(&global(Some(8), BackendArg::Rustdds), &[]).socket_name(),
            name
        );
        assert_ne!(
            key(&global(Some(7), BackendArg::Cyclone), &[]).socket_name(),
            name
        );
        // The domain from the environment when --domain-id is not given.
        assert_eq!(
            key(
                &global(None, BackendArg::Rustdds),
                &[("ROS_DOMAIN_ID", "7")]
            ),
            base
        );
    }

    #[test]
    fn cyclonedds_uri_counts_on_cyclone_only() {
        let uri = [("CYCLONEDDS_URI", "<CycloneDDS/>")];
        let rustdds = global(Some(3), BackendArg::Rustdds);
        assert_eq!(key(&rustdds, &uri), key(&rustdds, &[]));
        let cyclone = global(Some(3), BackendArg::Cyclone);
        assert_eq!(
            key(&cyclone, &uri)
                .backend_environment
                .get("CYCLONEDDS_URI")
                .map(String::as_str),
            Some("<CycloneDDS/>")
        );
        assert_ne!(
            key(&cyclone, &uri).socket_name(),
            key(&cyclone, &[]).socket_name()
        );
    }

    #[test]
    fn rcl_resolution_not_raw_values() {
        // ROS_LOCALHOST_ONLY=1 overrides the range and drops the peers, as rcl does: the same
        // graph as LOCALHOST without peers.
        let g = global(Some(1), BackendArg::Rustdds);
        assert_eq!(
            key(
                &g,
                &[
                    ("ROS_LOCALHOST_ONLY", "1"),
                    ("ROS_STATIC_PEERS", "10.0.0.1")
                ]
            ),
            key(&g, &[("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")])
        );
    }

    #[test]
    fn bad_domain_is_an_error() {
        let g = global(None, BackendArg::Rustdds);
        let env: HashMap<String, String> = [("ROS_DOMAIN_ID".to_owned(), "x".to_owned())].into();
        assert!(DaemonKey::with_env(&g, |k| env.get(k).cloned()).is_err());
    }

    #[test]
    fn daemon_node_names_are_hidden_and_unique() {
        let a = node_name(4);
        assert!(a.starts_with("_horus_ros_daemon_4_"), "{a}");
        assert_eq!(a.len(), "_horus_ros_daemon_4_".len() + 32);
        assert_ne!(a, node_name(4));
    }
}
