//! The Zenoh configuration of a context's session and of the router, as rmw_zenoh_cpp 0.2.10
//! makes them (`src/detail/zenoh_config.cpp`, `config/DEFAULT_RMW_ZENOH_SESSION_CONFIG.json5`,
//! `config/DEFAULT_RMW_ZENOH_ROUTER_CONFIG.json5`; wire facts §1):
//!
//! - a file named by `ZENOH_SESSION_CONFIG_URI` (`ZENOH_ROUTER_CONFIG_URI` for the router)
//!   replaces the default configuration whole;
//! - `ZENOH_CONFIG_OVERRIDE='key/path=value;…'` then overrides single keys (JSON5 values);
//! - `ZENOH_ROUTER_CHECK_ATTEMPTS` says how often a session looks for a router at start (1 by
//!   default, 0 forever, negative never), one second apart, and only warns if none answers
//!   (`rmw_context_impl_s.cpp`).

use std::time::Duration;

use zenoh::Wait;

/// rmw_zenoh's variable naming a session configuration file.
pub const SESSION_CONFIG_URI_ENV: &str = "ZENOH_SESSION_CONFIG_URI";
/// rmw_zenoh's variable naming a router configuration file.
pub const ROUTER_CONFIG_URI_ENV: &str = "ZENOH_ROUTER_CONFIG_URI";
/// rmw_zenoh's variable overriding single configuration keys.
pub const CONFIG_OVERRIDE_ENV: &str = "ZENOH_CONFIG_OVERRIDE";
/// rmw_zenoh's variable: how many times (one second apart) a session looks for a router.
pub const ROUTER_CHECK_ATTEMPTS_ENV: &str = "ZENOH_ROUTER_CHECK_ATTEMPTS";

/// What both default configurations share (the two json5 files agree on these).
const COMMON: &[(&str, &str)] = &[
    // Multicast scouting is configured but disabled: no UDP at all.
    ("scouting/multicast/enabled", "false"),
    ("scouting/gossip/enabled", "true"),
    ("scouting/gossip/multihop", "false"),
    (
        "timestamping/enabled",
        r#"{ router: true, peer: true, client: true }"#,
    ),
    ("timestamping/drop_future_timestamp", "false"),
    ("queries_default_timeout", "600000"),
    ("transport/link/tx/lease", "60000"),
    ("transport/link/tx/keep_alive", "2"),
    ("transport/link/tx/batch_size", "65535"),
    ("transport/link/tx/sequence_number_resolution", r#""32bit""#),
    ("transport/shared_memory/enabled", "false"),
    ("adminspace/enabled", "true"),
    ("adminspace/permissions/read", "true"),
    ("adminspace/permissions/write", "false"),
];

/// The session's own keys (`DEFAULT_RMW_ZENOH_SESSION_CONFIG.json5`).
const SESSION: &[(&str, &str)] = &[
    ("mode", r#""peer""#),
    ("connect/endpoints", r#"["tcp/localhost:7447"]"#),
    ("listen/endpoints", r#"["tcp/localhost:0"]"#),
    (
        "scouting/gossip/target",
        r#"{ router: ["router", "peer"], peer: ["router"] }"#,
    ),
    (
        "scouting/gossip/autoconnect",
        r#"{ router: [], peer: ["router", "peer"] }"#,
    ),
    (
        "scouting/gossip/autoconnect_strategy",
        r#"{ peer: { to_router: "always", to_peer: "greater-zid" } }"#,
    ),
];

/// The router's own keys (`DEFAULT_RMW_ZENOH_ROUTER_CONFIG.json5`): `rmw_zenohd`.
const ROUTER: &[(&str, &str)] = &[
    ("mode", r#""router""#),
    ("connect/endpoints", "[]"),
    ("listen/endpoints", r#"["tcp/[::]:7447"]"#),
    (
        "scouting/gossip/target",
        r#"{ router: ["router", "peer"], peer: ["router"] }"#,
    ),
    (
        "scouting/gossip/autoconnect",
        r#"{ router: [], peer: ["router", "peer"] }"#,
    ),
];

/// Why a Zenoh configuration could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ZenohConfigError {
    /// The file named by the URI variable could not be read.
    #[error("could not load the Zenoh configuration {path} (from {variable}): {cause}")]
    File {
        /// The variable.
        variable: &'static str,
        /// The path it named.
        path: String,
        /// What Zenoh said.
        cause: String,
    },
    /// A default key was refused (a bug).
    #[error("zenoh refused the default {key}={value}: {cause}")]
    Default {
        /// The key.
        key: &'static str,
        /// The value.
        value: &'static str,
        /// What Zenoh said.
        cause: String,
    },
    /// An entry of `ZENOH_CONFIG_OVERRIDE` is malformed or refused.
    #[error("{CONFIG_OVERRIDE_ENV}: bad entry '{entry}': {cause}")]
    Override {
        /// The entry.
        entry: String,
        /// Why.
        cause: String,
    },
    /// `ZENOH_ROUTER_CHECK_ATTEMPTS` is not an integer.
    #[error("ZENOH_ROUTER_CHECK_ATTEMPTS='{0}' is not an integer")]
    RouterCheckAttempts(String),
}

/// Which configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfigKind {
    /// A context's session (peer).
    Session,
    /// The router (`horus-ros router`, `rmw_zenohd`).
    Router,
}

impl ConfigKind {
    /// The variable naming a file that replaces the defaults.
    pub const fn uri_env(self) -> &'static str {
        match self {
            Self::Session => SESSION_CONFIG_URI_ENV,
            Self::Router => ROUTER_CONFIG_URI_ENV,
        }
    }
}

/// The configuration of `kind`, read from the environment through `get` as rmw_zenoh reads it.
pub fn config(
    kind: ConfigKind,
    get: impl Fn(&str) -> Option<String>,
) -> Result<zenoh::Config, ZenohConfigError> {
    let uri_env = kind.uri_env();
    let mut config = match get(uri_env).filter(|p| !p.is_empty()) {
        Some(path) => zenoh::Config::from_file(&path).map_err(|e| ZenohConfigError::File {
            variable: uri_env,
            path,
            cause: e.to_string(),
        })?,
        None => {
            let mut config = zenoh::Config::default();
            let own = match kind {
                ConfigKind::Session => SESSION,
                ConfigKind::Router => ROUTER,
            };
            for (key, value) in COMMON.iter().chain(own) {
                config
                    .insert_json5(key, value)
                    .map_err(|e| ZenohConfigError::Default {
                        key,
                        value,
                        cause: e.to_string(),
                    })?;
            }
            config
        }
    };
    if let Some(overrides) = get(CONFIG_OVERRIDE_ENV) {
        for entry in overrides.split(';').filter(|e| !e.trim().is_empty()) {
            let bad = |cause: String| ZenohConfigError::Override {
                entry: entry.to_owned(),
                cause,
            };
            let (key, value) = entry
                .split_once('=')
                .ok_or_else(|| bad("expected key/path=value".to_owned()))?;
            config
                .insert_json5(key.trim(), value.trim())
                .map_err(|e| bad(e.to_string()))?;
        }
    }
    Ok(config)
}

/// `ZENOH_ROUTER_CHECK_ATTEMPTS`: `Some(n)` attempts (`Some(0)`: forever), `None`: no check.
pub fn router_check_attempts(
    get: impl Fn(&str) -> Option<String>,
) -> Result<Option<u64>, ZenohConfigError> {
    match get(ROUTER_CHECK_ATTEMPTS_ENV).filter(|v| !v.trim().is_empty()) {
        None => Ok(Some(1)),
        Some(v) => match v.trim().parse::<i64>() {
            Ok(n) if n < 0 => Ok(None),
            Ok(n) => Ok(Some(n.unsigned_abs())),
            Err(_) => Err(ZenohConfigError::RouterCheckAttempts(v)),
        },
    }
}

/// Looks for a router as rmw_zenoh does at init: up to `attempts` times (0: until one is
/// found), one second apart; whether one was found.
pub(crate) fn wait_for_router(session: &zenoh::Session, attempts: u64) -> bool {
    let mut tried = 0u64;
    loop {
        if session.info().routers_zid().wait().next().is_some() {
            return true;
        }
        tried += 1;
        if attempts != 0 && tried >= attempts {
            return false;
        }
        std::thread::sleep(Duration::from_secs(1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_rmw_zenohs() {
        let session = config(ConfigKind::Session, |_| None).expect("session");
        let get = |c: &zenoh::Config, k: &str| c.get_json(k).expect(k);
        assert_eq!(get(&session, "mode"), r#""peer""#);
        assert_eq!(
            get(&session, "connect/endpoints"),
            r#"["tcp/localhost:7447"]"#
        );
        assert_eq!(get(&session, "listen/endpoints"), r#"["tcp/localhost:0"]"#);
        assert_eq!(get(&session, "scouting/multicast/enabled"), "false");
        assert_eq!(get(&session, "scouting/gossip/enabled"), "true");
        let router = config(ConfigKind::Router, |_| None).expect("router");
        assert_eq!(get(&router, "mode"), r#""router""#);
        assert_eq!(get(&router, "listen/endpoints"), r#"["tcp/[::]:7447"]"#);
    }

    #[test]
    fn overrides_apply_and_bad_ones_are_errors() {
        let env = |k: &str| {
            (k == CONFIG_OVERRIDE_ENV).then(|| {
                r#"connect/endpoints=["tcp/127.0.0.1:7999"];listen/endpoints=["tcp/127.0.0.1:0"]"#
                    .to_owned()
            })
        };
        let c = config(ConfigKind::Session, env).expect("overridden");
        assert_eq!(
            c.get_json("connect/endpoints").expect("key"),
            r#"["tcp/127.0.0.1:7999"]"#
        );
        let bad = |k: &str| (k == CONFIG_OVERRIDE_ENV).then(|| "mode".to_owned());
        assert!(matches!(
            config(ConfigKind::Session, bad),
            Err(ZenohConfigError::Override { .. })
        ));
        let missing =
            |k: &str| (k == SESSION_CONFIG_URI_ENV).then(|| "/nonexistent.json5".to_owned());
        assert!(matches!(
            config(ConfigKind::Session, missing),
            Err(ZenohConfigError::File { .. })
        ));
    }

    #[test]
    fn router_check_attempts_read_as_rmw_zenoh_reads_them() {
        let with =
            |v: &'static str| move |k: &str| (k == ROUTER_CHECK_ATTEMPTS_ENV).then(|| v.to_owned());
        assert_eq!(router_check_attempts(|_| None).expect("default"), Some(1));
        assert_eq!(router_check_attempts(with("0")).expect("0"), Some(0));
        assert_eq!(router_check_attempts(with("5")).expect("5"), Some(5));
        assert_eq!(router_check_attempts(with("-1")).expect("-1"), None);
        assert!(router_check_attempts(with("x")).is_err());
    }
}
