//! Reading the ROS 2 discovery environment exactly as rcl (Jazzy) does.
//!
//! Sources: rcl `src/rcl/domain_id.c` (`rcl_get_default_domain_id`),
//! `src/rcl/discovery_options.c` (`rcl_get_automatic_discovery_range`,
//! `rcl_get_discovery_static_peers`), `src/rcl/localhost.c` and `src/rcl/init.c`
//! (the deprecated `ROS_LOCALHOST_ONLY` overriding the discovery options), rcl 9.x (Jazzy).

use std::fmt;
use std::str::FromStr;

/// `ROS_DOMAIN_ID`.
pub const DOMAIN_ID_ENV: &str = "ROS_DOMAIN_ID";
/// `ROS_AUTOMATIC_DISCOVERY_RANGE`.
pub const DISCOVERY_RANGE_ENV: &str = "ROS_AUTOMATIC_DISCOVERY_RANGE";
/// `ROS_STATIC_PEERS`.
pub const STATIC_PEERS_ENV: &str = "ROS_STATIC_PEERS";
/// `ROS_LOCALHOST_ONLY` (deprecated since Jazzy, still honoured).
pub const LOCALHOST_ONLY_ENV: &str = "ROS_LOCALHOST_ONLY";

/// Longest static peer address rcl keeps (`RMW_DISCOVERY_OPTIONS_STATIC_PEERS_MAX_LENGTH` - 1).
pub const STATIC_PEER_MAX_LENGTH: usize = 255;

/// A DDS domain id usable with the RTPS well-known port mapping.
///
/// Port numbers are `7400 + 250 * domain + offset`, so domains above 232 do not fit in a UDP port
/// (Cyclone DDS and Fast DDS reject them for the same reason).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct DomainId(u16);

impl DomainId {
    /// The largest domain id the RTPS port mapping allows.
    pub const MAX: u16 = 232;

    /// A domain id, checked against [`DomainId::MAX`].
    pub fn new(id: u32) -> Result<Self, DomainIdError> {
        if id > u32::from(Self::MAX) {
            return Err(DomainIdError::OutOfRange { value: id.into() });
        }
        // Checked above: id <= 232 fits in u16.
        Ok(Self(id as u16))
    }

    /// The id as a number.
    pub const fn get(self) -> u16 {
        self.0
    }
}

impl fmt::Display for DomainId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

/// Parses a domain id as rcl does (`strtoul(value, &end, 0)`: decimal, `0x` hex or `0` octal),
/// but rejects trailing garbage that rcl would silently ignore.
impl FromStr for DomainId {
    type Err = DomainIdError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        let (digits, radix) = if let Some(h) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X"))
        {
            (h, 16)
        } else if t.len() > 1 && t.starts_with('0') {
            (&t[1..], 8)
        } else {
            (t, 10)
        };
        let value = u64::from_str_radix(digits, radix).map_err(|_| DomainIdError::NotANumber {
            value: s.to_owned(),
        })?;
        let value32 = u32::try_from(value).map_err(|_| DomainIdError::OutOfRange { value })?;
        Self::new(value32)
    }
}

/// Why a domain id was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum DomainIdError {
    /// Not an integral number (rcl: "ROS_DOMAIN_ID is not an integral number").
    #[error("ROS_DOMAIN_ID '{value}' is not an integral number")]
    NotANumber {
        /// The value given.
        value: String,
    },
    /// Too large for the RTPS port mapping.
    #[error("ROS_DOMAIN_ID {value} is out of range: DDS domain ids go from 0 to 232")]
    OutOfRange {
        /// The value given.
        value: u64,
    },
}

/// `rmw_automatic_discovery_range_t`: how far automatic discovery reaches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum DiscoveryRange {
    /// No automatic discovery (static peers are ignored too, as rcl does).
    Off,
    /// Only this host.
    Localhost,
    /// The local subnet (Jazzy's default).
    #[default]
    Subnet,
    /// Leave the middleware's own configuration untouched.
    SystemDefault,
}

impl DiscoveryRange {
    /// Reads `ROS_AUTOMATIC_DISCOVERY_RANGE`'s value as rcl does: empty means SUBNET (Jazzy's
    /// default), an unknown value means LOCALHOST (the second item is then a warning to log).
    pub fn from_env_value(value: &str) -> (Self, Option<String>) {
        match value {
            "" | "SUBNET" => (Self::Subnet, None),
            "OFF" => (Self::Off, None),
            "LOCALHOST" => (Self::Localhost, None),
            "SYSTEM_DEFAULT" => (Self::SystemDefault, None),
            other => (
                Self::Localhost,
                Some(format!(
                    "Invalid value '{other}' specified for '{DISCOVERY_RANGE_ENV}', assuming localhost only"
                )),
            ),
        }
    }
}

impl fmt::Display for DiscoveryRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Off => "OFF",
            Self::Localhost => "LOCALHOST",
            Self::Subnet => "SUBNET",
            Self::SystemDefault => "SYSTEM_DEFAULT",
        })
    }
}

/// `rmw_discovery_options_t`: the discovery range plus static peers.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct DiscoveryOptions {
    /// How far automatic discovery reaches.
    pub range: DiscoveryRange,
    /// Hosts to contact whatever the range (`ROS_STATIC_PEERS`, `;`-separated).
    pub static_peers: Vec<String>,
}

/// What [`read_environment`] found, plus the warnings rcl would log.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Environment {
    /// The domain.
    pub domain_id: DomainId,
    /// Discovery configuration.
    pub discovery: DiscoveryOptions,
    /// Warnings rcl would print for these values.
    pub warnings: Vec<String>,
}

/// Reads `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE`, `ROS_STATIC_PEERS` and
/// `ROS_LOCALHOST_ONLY` through `get` (a lookup such as `std::env::var`), as rcl's init does.
pub fn read_environment(
    get: impl Fn(&str) -> Option<String>,
) -> Result<Environment, DomainIdError> {
    let mut warnings = Vec::new();
    let domain_id = match get(DOMAIN_ID_ENV) {
        Some(v) if !v.is_empty() => v.parse()?,
        _ => DomainId::default(),
    };

    // rcl init.c: ROS_LOCALHOST_ONLY=1 wins over the new variables; any other non-empty value
    // disables it; empty means "not set".
    let localhost_only = get(LOCALHOST_ONLY_ENV).filter(|v| !v.is_empty());
    if let Some(v) = &localhost_only {
        warnings.push(format!(
            "{LOCALHOST_ONLY_ENV} is deprecated but still honored if it is enabled. \
             Use {DISCOVERY_RANGE_ENV} and {STATIC_PEERS_ENV} instead."
        ));
        if v.starts_with('1') {
            warnings.push(
                "'localhost_only' is enabled, 'automatic_discovery_range' and 'static_peers' will be ignored."
                    .to_owned(),
            );
            return Ok(Environment {
                domain_id,
                discovery: DiscoveryOptions {
                    range: DiscoveryRange::Localhost,
                    static_peers: Vec::new(),
                },
                warnings,
            });
        }
    }

    let (range, warning) =
        DiscoveryRange::from_env_value(&get(DISCOVERY_RANGE_ENV).unwrap_or_default());
    warnings.extend(warning);
    let peers_value = get(STATIC_PEERS_ENV).unwrap_or_default();
    let mut static_peers = Vec::new();
    for peer in peers_value.split(';').filter(|p| !p.is_empty()) {
        if peer.len() > STATIC_PEER_MAX_LENGTH {
            warnings.push(format!(
                "Static peer {peer} specified to '{STATIC_PEERS_ENV}' is too long (maximum of {STATIC_PEER_MAX_LENGTH}); skipping"
            ));
        } else {
            static_peers.push(peer.to_owned());
        }
    }
    if range == DiscoveryRange::Off && !static_peers.is_empty() {
        warnings.push(format!(
            "Note: {DISCOVERY_RANGE_ENV} is set to OFF, but found static peers in {STATIC_PEERS_ENV}. \
             {STATIC_PEERS_ENV} will be ignored."
        ));
        static_peers.clear();
    }
    Ok(Environment {
        domain_id,
        discovery: DiscoveryOptions {
            range,
            static_peers,
        },
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> Result<Environment, DomainIdError> {
        let map: HashMap<String, String> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        read_environment(|k| map.get(k).cloned())
    }

    #[test]
    fn domain_id_parses_like_strtoul_base_0() {
        for (input, expected) in [
            ("0", 0),
            ("7", 7),
            ("232", 232),
            ("0x10", 16),
            ("010", 8),
            (" 42 ", 42),
        ] {
            assert_eq!(
                input.parse::<DomainId>().map(DomainId::get),
                Ok(expected),
                "{input}"
            );
        }
    }

    #[test]
    fn domain_id_rejects_garbage_and_out_of_range() {
        assert!(matches!(
            "abc".parse::<DomainId>(),
            Err(DomainIdError::NotANumber { .. })
        ));
        assert!(matches!(
            "12abc".parse::<DomainId>(),
            Err(DomainIdError::NotANumber { .. })
        ));
        assert!(matches!(
            "-1".parse::<DomainId>(),
            Err(DomainIdError::NotANumber { .. })
        ));
        assert_eq!(
            "233".parse::<DomainId>(),
            Err(DomainIdError::OutOfRange { value: 233 })
        );
        assert_eq!(
            "99999999999".parse::<DomainId>(),
            Err(DomainIdError::OutOfRange {
                value: 99_999_999_999
            })
        );
    }

    #[test]
    fn defaults_are_jazzy_defaults() {
        let e = env(&[]).expect("empty environment is valid");
        assert_eq!(e.domain_id.get(), 0);
        assert_eq!(
            e.discovery,
            DiscoveryOptions {
                range: DiscoveryRange::Subnet,
                static_peers: vec![]
            }
        );
        assert!(e.warnings.is_empty());
        assert_eq!(
            env(&[("ROS_DOMAIN_ID", "")]).map(|e| e.domain_id.get()),
            Ok(0)
        );
    }

    #[test]
    fn discovery_range_values() {
        for (v, r) in [
            ("OFF", DiscoveryRange::Off),
            ("LOCALHOST", DiscoveryRange::Localhost),
            ("SUBNET", DiscoveryRange::Subnet),
            ("SYSTEM_DEFAULT", DiscoveryRange::SystemDefault),
        ] {
            let e = env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", v)]).expect("valid");
            assert_eq!(e.discovery.range, r);
            assert!(e.warnings.is_empty());
        }
        // Invalid (including lower case) means LOCALHOST with rcl's warning.
        let e = env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "localhost")]).expect("valid");
        assert_eq!(e.discovery.range, DiscoveryRange::Localhost);
        assert_eq!(
            e.warnings,
            vec!["Invalid value 'localhost' specified for 'ROS_AUTOMATIC_DISCOVERY_RANGE', assuming localhost only"]
        );
    }

    #[test]
    fn static_peers_split_and_ignored_when_off() {
        let e = env(&[("ROS_STATIC_PEERS", "192.168.0.1;robot.local;")]).expect("valid");
        assert_eq!(e.discovery.static_peers, vec!["192.168.0.1", "robot.local"]);
        let long = "a".repeat(256);
        let e = env(&[("ROS_STATIC_PEERS", &format!("{long};ok"))]).expect("valid");
        assert_eq!(e.discovery.static_peers, vec!["ok"]);
        assert_eq!(e.warnings.len(), 1);
        let e = env(&[
            ("ROS_STATIC_PEERS", "h1"),
            ("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF"),
        ])
        .expect("valid");
        assert!(e.discovery.static_peers.is_empty());
        assert_eq!(e.warnings.len(), 1);
    }

    #[test]
    fn localhost_only_is_deprecated_but_wins() {
        let e = env(&[
            ("ROS_LOCALHOST_ONLY", "1"),
            ("ROS_AUTOMATIC_DISCOVERY_RANGE", "SUBNET"),
            ("ROS_STATIC_PEERS", "h1"),
        ])
        .expect("valid");
        assert_eq!(
            e.discovery,
            DiscoveryOptions {
                range: DiscoveryRange::Localhost,
                static_peers: vec![]
            }
        );
        assert_eq!(e.warnings.len(), 2);
        let e = env(&[
            ("ROS_LOCALHOST_ONLY", "0"),
            ("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF"),
        ])
        .expect("valid");
        assert_eq!(e.discovery.range, DiscoveryRange::Off);
        assert_eq!(e.warnings.len(), 1);
    }
}
