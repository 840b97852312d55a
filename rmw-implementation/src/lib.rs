//! Which backend a horus-ros context runs on, as rmw_implementation picks the rmw library: the
//! one crate that knows which backends are built in (each is a crate of its own behind the
//! backend contract, `horus-ros-rmw-contract`, and a cargo feature here).
//!
//! - [`Backend::RustDds`] (the default, for `rmw_fastrtps_cpp`): RustDDS, pure Rust
//!   (`horus-ros-rmw-rustdds`, feature `rustdds`, on by default).
//! - [`Backend::Cyclone`] (for `rmw_cyclonedds_cpp`): Eclipse Cyclone DDS 11 (the DDS of
//!   rmw_cyclonedds_cpp; `horus-ros-rmw-cyclone`, feature `cyclone`).
//! - [`Backend::Zenoh`] (for `rmw_zenoh_cpp`): Zenoh 1.8, wire-compatible with rmw_zenoh_cpp
//!   0.2.10 (liveliness tokens, data keys, attachments; `horus-ros-rmw-zenoh`, feature `zenoh`).
//!
//! Chosen per context with `ContextBuilder::backend` (horus-ros-rmw), else by the environment
//! variable [`BACKEND_ENV`] (`rustdds`, `cyclone` or `zenoh`), else by
//! [`RMW_IMPLEMENTATION_ENV`] as rcl reads it, else RustDDS (see [`Backend::select`]). What a
//! backend is (its name, rmw implementation, vendor, capabilities) is said by its own crate;
//! this one knows the names it can pick, as rmw_implementation knows library names.
//!
//! How rcl reads `RMW_IMPLEMENTATION` (Jazzy): rmw_implementation `src/functions.cpp`
//! (`load_library`) takes `rcpputils::get_env_var("RMW_IMPLEMENTATION")` (rcutils_get_env: an
//! unset variable reads as ""); a non-empty value loads that library and only that one, an empty
//! one the default; rcl `src/rcl/rmw_implementation_identifier_check.c` then requires
//! `strcmp(rmw_get_implementation_identifier(), value) == 0`. No trimming, no case folding.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use horus_ros_rmw_contract::{Capabilities, Implementation, VendorId};

/// The environment variable that chooses the backend of contexts that do not set one; it wins
/// over [`RMW_IMPLEMENTATION_ENV`].
pub const BACKEND_ENV: &str = "HORUS_ROS_BACKEND";

/// The environment variable with which ROS 2 chooses its rmw implementation (rcl's
/// `RMW_IMPLEMENTATION_ENV_VAR_NAME`).
pub const RMW_IMPLEMENTATION_ENV: &str = "RMW_IMPLEMENTATION";

/// The values of [`RMW_IMPLEMENTATION_ENV`] horus-ros speaks, and the backend each one means.
///
/// Jazzy's rmw_fastrtps_cpp and rmw_fastrtps_dynamic_cpp put the same bytes on the wire (they
/// differ only in how type support is loaded), so both run on RustDDS, which follows the
/// rmw_fastrtps service convention; rmw_cyclonedds_cpp runs on Cyclone DDS.
pub const RMW_IMPLEMENTATIONS: [(&str, Backend); 4] = [
    ("rmw_fastrtps_cpp", Backend::RustDds),
    ("rmw_fastrtps_dynamic_cpp", Backend::RustDds),
    ("rmw_cyclonedds_cpp", Backend::Cyclone),
    ("rmw_zenoh_cpp", Backend::Zenoh),
];

/// Jazzy's default rmw implementation (rmw_implementation_cmake's
/// `get_default_rmw_implementation`), used when [`RMW_IMPLEMENTATION_ENV`] is unset or empty.
pub const DEFAULT_RMW_IMPLEMENTATION: &str = "rmw_fastrtps_cpp";

/// A backend horus-ros can run on, built in or not; the default is RustDDS, as Jazzy's default
/// rmw is rmw_fastrtps_cpp.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Backend {
    /// RustDDS: pure Rust. Cannot send USER_DATA (so no type hashes or enclaves for peers),
    /// has no static peers, but carries `related_sample_identity` (both service conventions).
    RustDds,
    /// Cyclone DDS through `cyclors`: USER_DATA, rmw_cyclonedds' discovery configuration and
    /// `CYCLONEDDS_URI`; speaks only the rmw_cyclonedds service convention.
    Cyclone,
    /// Zenoh (the zenoh crate): rmw_zenoh_cpp's liveliness-token graph, data keys and
    /// attachments; `ZENOH_SESSION_CONFIG_URI`, `ZENOH_CONFIG_OVERRIDE`,
    /// `ZENOH_ROUTER_CHECK_ATTEMPTS`. Services as queryables are not there yet.
    Zenoh,
}

impl Backend {
    /// Every backend, built in or not.
    pub const ALL: [Backend; 3] = [Backend::RustDds, Backend::Cyclone, Backend::Zenoh];

    /// The name used by [`BACKEND_ENV`] and `Display`.
    pub const fn name(self) -> &'static str {
        match self {
            Self::RustDds => "rustdds",
            Self::Cyclone => "cyclone",
            Self::Zenoh => "zenoh",
        }
    }

    /// Whether this build of horus-ros includes the backend (its cargo feature: `rustdds`,
    /// `cyclone` or `zenoh`).
    pub const fn is_available(self) -> bool {
        match self {
            Self::RustDds => cfg!(feature = "rustdds"),
            Self::Cyclone => cfg!(feature = "cyclone"),
            Self::Zenoh => cfg!(feature = "zenoh"),
        }
    }

    /// Its implementation of the backend contract: the one place that knows which backends
    /// are built in.
    pub fn implementation(self) -> Result<Arc<dyn Implementation>, BackendError> {
        match self {
            #[cfg(feature = "rustdds")]
            Self::RustDds => Ok(Arc::new(horus_ros_rmw_rustdds::RustDds)),
            #[cfg(feature = "cyclone")]
            Self::Cyclone => Ok(Arc::new(horus_ros_rmw_cyclone::Cyclone)),
            #[cfg(feature = "zenoh")]
            Self::Zenoh => Ok(Arc::new(horus_ros_rmw_zenoh::Zenoh::default())),
            #[allow(unreachable_patterns)]
            _ => Err(BackendError::NotBuiltIn { backend: self }),
        }
    }

    /// What its crate says of it, when it is built in: the one table of the built-in backends'
    /// own constants.
    const fn built_in(self) -> Option<BuiltIn> {
        match self {
            #[cfg(feature = "rustdds")]
            Self::RustDds => Some(BuiltIn {
                capabilities: horus_ros_rmw_rustdds::CAPABILITIES,
                vendor_id: horus_ros_rmw_rustdds::VENDOR_ID,
                configuration_env: horus_ros_rmw_rustdds::CONFIGURATION_ENV,
            }),
            #[cfg(feature = "cyclone")]
            Self::Cyclone => Some(BuiltIn {
                capabilities: horus_ros_rmw_cyclone::CAPABILITIES,
                vendor_id: horus_ros_rmw_cyclone::VENDOR_ID,
                configuration_env: horus_ros_rmw_cyclone::CONFIGURATION_ENV,
            }),
            #[cfg(feature = "zenoh")]
            Self::Zenoh => Some(BuiltIn {
                capabilities: horus_ros_rmw_zenoh::CAPABILITIES,
                vendor_id: horus_ros_rmw_zenoh::VENDOR_ID,
                configuration_env: horus_ros_rmw_zenoh::CONFIGURATION_ENV,
            }),
            #[allow(unreachable_patterns)]
            _ => None,
        }
    }

    /// The environment variables its own configuration reads, beyond ROS's (`CYCLONEDDS_URI`
    /// for Cyclone DDS), as its crate lists them: what else, with the domain and the discovery
    /// options, decides which graph a context sees. None for a backend not built in (no context
    /// can run on it).
    pub const fn configuration_env(self) -> &'static [&'static str] {
        match self.built_in() {
            Some(b) => b.configuration_env,
            None => &[],
        }
    }

    /// What it can do, as its crate says (the same as its [`implementation`](Self::implementation)
    /// reports); `None` when it is not built in.
    pub const fn capabilities(self) -> Option<Capabilities> {
        match self.built_in() {
            Some(b) => Some(b.capabilities),
            None => None,
        }
    }

    /// The vendor id of its participants, as its crate says; `None` when it is not built in.
    pub const fn vendor_id(self) -> Option<VendorId> {
        match self.built_in() {
            Some(b) => Some(b.vendor_id),
            None => None,
        }
    }

    /// The rmw implementation this backend stands in for, as `RMW_IMPLEMENTATION` names it:
    /// `rmw_fastrtps_cpp` (Jazzy's default) for RustDDS, `rmw_cyclonedds_cpp` for Cyclone DDS.
    pub const fn rmw_implementation(self) -> &'static str {
        match self {
            Self::RustDds => DEFAULT_RMW_IMPLEMENTATION,
            Self::Cyclone => "rmw_cyclonedds_cpp",
            Self::Zenoh => "rmw_zenoh_cpp",
        }
    }

    /// The backend for a non-empty `RMW_IMPLEMENTATION` value, compared byte for byte as rcl
    /// does: rmw_implementation loads the library `lib<value>.so` and rcl checks
    /// `strcmp(rmw_get_implementation_identifier(), value)`, so case and blanks count.
    pub fn from_rmw_implementation(value: &str) -> Result<Self, BackendError> {
        RMW_IMPLEMENTATIONS
            .iter()
            .find(|(name, _)| *name == value)
            .map(|&(_, backend)| backend)
            .ok_or_else(|| BackendError::UnsupportedRmw {
                value: value.to_owned(),
            })
    }

    /// Chooses the backend from the values of [`BACKEND_ENV`] and [`RMW_IMPLEMENTATION_ENV`]
    /// (`None` when unset):
    ///
    /// 1. `HORUS_ROS_BACKEND`, unless empty or blank: `rustdds`, `cyclone` or `zenoh`, else
    ///    [`BackendError::Unknown`].
    /// 2. `RMW_IMPLEMENTATION`, unless empty (rmw_implementation's `load_library` and rcl's
    ///    identifier check treat an empty value as unset): one of [`RMW_IMPLEMENTATIONS`], else
    ///    [`BackendError::UnsupportedRmw`] (rcl fails too: it loads only the library named).
    /// 3. Neither: the [default](Backend::default): RustDDS, standing in for Jazzy's default
    ///    rmw_fastrtps_cpp, when built in.
    pub fn select(
        horus_ros_backend: Option<&str>,
        rmw_implementation: Option<&str>,
    ) -> Result<Self, BackendError> {
        if let Some(v) = horus_ros_backend.filter(|v| !v.trim().is_empty()) {
            return v.parse();
        }
        match rmw_implementation.filter(|v| !v.is_empty()) {
            Some(v) => Self::from_rmw_implementation(v),
            None => Ok(Self::default()),
        }
    }

    /// [`Backend::select`] over the environment read through `get` (e.g. `std::env::var`).
    pub fn from_env_with(get: impl Fn(&str) -> Option<String>) -> Result<Self, BackendError> {
        Self::select(
            get(BACKEND_ENV).as_deref(),
            get(RMW_IMPLEMENTATION_ENV).as_deref(),
        )
    }
}

/// What a built-in backend's crate says of it.
#[derive(Clone, Copy)]
struct BuiltIn {
    capabilities: Capabilities,
    vendor_id: VendorId,
    configuration_env: &'static [&'static str],
}

impl Default for Backend {
    /// RustDDS (standing in for Jazzy's default rmw_fastrtps_cpp) when built in, else the first
    /// of Cyclone DDS and Zenoh that is, as rmw_implementation_cmake's
    /// `get_default_rmw_implementation` takes the first rmw installed when rmw_fastrtps_cpp is
    /// not; RustDDS when none is (creating a context then says it is not built in).
    fn default() -> Self {
        Self::ALL
            .into_iter()
            .find(|b| b.is_available())
            .unwrap_or(Self::RustDds)
    }
}

/// `rmw_fastrtps_cpp, rmw_fastrtps_dynamic_cpp (rustdds), rmw_cyclonedds_cpp (cyclone)`.
fn supported_rmw_implementations() -> String {
    RMW_IMPLEMENTATIONS
        .iter()
        .map(|(name, backend)| format!("{name} ({backend})"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Backend {
    type Err = BackendError;

    /// `rustdds`, `cyclone` or `zenoh` (case-insensitive; `cyclonedds` also accepted).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "rustdds" => Ok(Self::RustDds),
            "cyclone" | "cyclonedds" => Ok(Self::Cyclone),
            "zenoh" => Ok(Self::Zenoh),
            _ => Err(BackendError::Unknown {
                value: s.to_owned(),
            }),
        }
    }
}

/// Why a backend cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BackendError {
    /// The name is not a backend.
    #[error(
        "unknown backend '{value}' (expected 'rustdds', 'cyclone' or 'zenoh', e.g. in {BACKEND_ENV})"
    )]
    Unknown {
        /// The value given.
        value: String,
    },
    /// `RMW_IMPLEMENTATION` names an rmw implementation horus-ros does not speak (e.g.
    /// `rmw_connextdds`, or a misspelling); rcl would fail to load it as well.
    #[error(
        "{RMW_IMPLEMENTATION_ENV}='{}' is not supported by horus-ros: it speaks {} or, when \
         unset or empty, {DEFAULT_RMW_IMPLEMENTATION} (rustdds); set {BACKEND_ENV} to rustdds, \
         cyclone or zenoh to override it",
        value.escape_debug(),
        supported_rmw_implementations()
    )]
    UnsupportedRmw {
        /// The value of `RMW_IMPLEMENTATION`.
        value: String,
    },
    /// The backend exists but this build does not include it.
    #[error("the {backend} backend is not built in (enable the cargo feature `{backend}` of horus-ros-rmw)")]
    NotBuiltIn {
        /// The backend asked for.
        backend: Backend,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names_and_environment() {
        assert_eq!("rustdds".parse::<Backend>(), Ok(Backend::RustDds));
        assert_eq!(" Cyclone ".parse::<Backend>(), Ok(Backend::Cyclone));
        assert_eq!("cyclonedds".parse::<Backend>(), Ok(Backend::Cyclone));
        assert!(matches!(
            "fastdds".parse::<Backend>(),
            Err(BackendError::Unknown { .. })
        ));
        assert_eq!(
            Backend::from_env_with(|k| (k == BACKEND_ENV).then(|| "cyclone".to_owned())),
            Ok(Backend::Cyclone)
        );
        assert_eq!(
            Backend::from_env_with(
                |k| (k == RMW_IMPLEMENTATION_ENV).then(|| "rmw_cyclonedds_cpp".to_owned())
            ),
            Ok(Backend::Cyclone)
        );
        assert_eq!(Backend::from_env_with(|_| None), Ok(Backend::default()));
        for b in Backend::ALL {
            assert_eq!(b.to_string().parse::<Backend>(), Ok(b));
        }
        assert_eq!(Backend::RustDds.is_available(), cfg!(feature = "rustdds"));
        assert_eq!(Backend::Cyclone.is_available(), cfg!(feature = "cyclone"));
        assert_eq!(Backend::Zenoh.is_available(), cfg!(feature = "zenoh"));
        assert_eq!("ZENOH".parse::<Backend>(), Ok(Backend::Zenoh));
    }

    /// The selection table: `HORUS_ROS_BACKEND` (first) over `RMW_IMPLEMENTATION` (second).
    #[test]
    fn selection_table() {
        use Backend::{Cyclone, RustDds, Zenoh};
        // Unset: the default (RustDDS, for rmw_fastrtps_cpp, when built in).
        let default = Backend::default();
        let ok = [
            // RMW_IMPLEMENTATION alone, as rcl reads it (empty = unset).
            (None, None, default),
            (None, Some(""), default),
            (None, Some("rmw_fastrtps_cpp"), RustDds),
            (None, Some("rmw_fastrtps_dynamic_cpp"), RustDds),
            (None, Some("rmw_cyclonedds_cpp"), Cyclone),
            (None, Some("rmw_zenoh_cpp"), Zenoh),
            (Some("zenoh"), Some("rmw_fastrtps_cpp"), Zenoh),
            // HORUS_ROS_BACKEND wins over RMW_IMPLEMENTATION, even over an unsupported one.
            (Some("rustdds"), Some("rmw_cyclonedds_cpp"), RustDds),
            (Some("cyclone"), Some("rmw_fastrtps_cpp"), Cyclone),
            (Some("cyclone"), None, Cyclone),
            (Some("rustdds"), Some("rmw_zenoh_cpp"), RustDds),
            (Some(" Cyclone "), Some("rmw_connextdds"), Cyclone),
            // An empty or blank HORUS_ROS_BACKEND is unset.
            (Some(""), Some("rmw_cyclonedds_cpp"), Cyclone),
            (Some("  "), None, default),
            (Some(""), Some(""), default),
        ];
        for (horus, rmw, want) in ok {
            assert_eq!(Backend::select(horus, rmw), Ok(want), "{horus:?} {rmw:?}");
        }
        // Unsupported or misspelt rmw implementations: an error, never a fallback. Names are
        // compared as rcl compares them (library names: case and blanks count).
        for rmw in [
            "rmw_zenoh",
            "rmw_connextdds",
            "rmw_gurumdds_cpp",
            "rmw_cyclone_cpp",
            "RMW_CYCLONEDDS_CPP",
            "rmw_cyclonedds_cpp ",
            " rmw_fastrtps_cpp",
            " ",
        ] {
            for horus in [None, Some(""), Some(" ")] {
                assert_eq!(
                    Backend::select(horus, Some(rmw)),
                    Err(BackendError::UnsupportedRmw {
                        value: rmw.to_owned()
                    }),
                    "{horus:?} {rmw:?}"
                );
            }
        }
        // A bad HORUS_ROS_BACKEND is an error of its own, whatever RMW_IMPLEMENTATION says.
        assert_eq!(
            Backend::select(Some("fastdds"), Some("rmw_cyclonedds_cpp")),
            Err(BackendError::Unknown {
                value: "fastdds".to_owned()
            })
        );
    }

    /// The names this crate picks by are the ones each built-in backend's crate gives itself,
    /// and what each says of itself is what its implementation reports.
    #[test]
    fn built_in_backends_are_what_their_crates_say() {
        for b in Backend::ALL.into_iter().filter(|b| b.is_available()) {
            let implementation = b.implementation().expect("built in");
            assert_eq!(implementation.name(), b.name());
            assert_eq!(implementation.rmw_implementation(), b.rmw_implementation());
            assert_eq!(Some(implementation.capabilities()), b.capabilities());
            assert_eq!(Some(implementation.vendor_id()), b.vendor_id());
        }
        for b in Backend::ALL.into_iter().filter(|b| !b.is_available()) {
            assert!(matches!(
                b.implementation(),
                Err(BackendError::NotBuiltIn { backend }) if backend == b
            ));
            assert_eq!(b.capabilities(), None);
            assert!(b.configuration_env().is_empty());
        }
    }

    #[test]
    fn rmw_names_round_trip() {
        for b in Backend::ALL {
            assert_eq!(
                Backend::from_rmw_implementation(b.rmw_implementation()),
                Ok(b)
            );
        }
        assert_eq!(Backend::RustDds.rmw_implementation(), "rmw_fastrtps_cpp");
        assert_eq!(Backend::Cyclone.rmw_implementation(), "rmw_cyclonedds_cpp");
    }

    /// The default is RustDDS (Jazzy's default rmw_fastrtps_cpp) when built in, else the first
    /// backend built in.
    #[test]
    fn the_default_is_rustdds_or_the_first_built_in() {
        let default = Backend::default();
        if Backend::RustDds.is_available() {
            assert_eq!(default, Backend::RustDds);
            assert_eq!(default.rmw_implementation(), DEFAULT_RMW_IMPLEMENTATION);
        } else if let Some(first) = Backend::ALL.into_iter().find(|b| b.is_available()) {
            assert_eq!(default, first);
        } else {
            assert_eq!(default, Backend::RustDds);
        }
    }

    #[test]
    fn unsupported_rmw_message_names_value_choices_and_override() {
        let message = Backend::select(None, Some("rmw_connextdds"))
            .expect_err("unsupported")
            .to_string();
        assert_eq!(
            message,
            "RMW_IMPLEMENTATION='rmw_connextdds' is not supported by horus-ros: it speaks \
             rmw_fastrtps_cpp (rustdds), rmw_fastrtps_dynamic_cpp (rustdds), \
             rmw_cyclonedds_cpp (cyclone), rmw_zenoh_cpp (zenoh) or, when unset or empty, \
             rmw_fastrtps_cpp (rustdds); set HORUS_ROS_BACKEND to rustdds, cyclone or zenoh to \
             override it"
        );
        // Control characters are shown escaped, on one line.
        let message = Backend::select(None, Some("rmw\nx\t"))
            .expect_err("bad")
            .to_string();
        assert!(
            message.starts_with("RMW_IMPLEMENTATION='rmw\\nx\\t' "),
            "{message}"
        );
        assert!(!message.contains('\n'));
    }
}
