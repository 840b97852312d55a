//! Which DDS implementation a [`Context`](crate::Context) runs on.
//!
//! - [`Backend::RustDds`] (the default): RustDDS, pure Rust, always built in.
//! - [`Backend::Cyclone`]: Eclipse Cyclone DDS 11 (the DDS of rmw_cyclonedds_cpp), built in with
//!   the cargo feature `cyclone`.
//!
//! Chosen per context with [`ContextBuilder::backend`](crate::ContextBuilder::backend), else by
//! the environment variable [`BACKEND_ENV`] (`rustdds` or `cyclone`), else RustDDS.

use std::fmt;
use std::str::FromStr;

/// The environment variable that chooses the backend of contexts that do not set one.
pub const BACKEND_ENV: &str = "HORUS_ROS_BACKEND";

/// A DDS implementation horus-ros can run on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Backend {
    /// RustDDS: pure Rust. Cannot send USER_DATA (so no type hashes or enclaves for peers),
    /// has no static peers, but carries `related_sample_identity` (both service conventions).
    #[default]
    RustDds,
    /// Cyclone DDS through `cyclors`: USER_DATA, rmw_cyclonedds' discovery configuration and
    /// `CYCLONEDDS_URI`; speaks only the rmw_cyclonedds service convention.
    Cyclone,
}

impl Backend {
    /// Every backend, built in or not.
    pub const ALL: [Backend; 2] = [Backend::RustDds, Backend::Cyclone];

    /// The name used by [`BACKEND_ENV`] and `Display`.
    pub const fn name(self) -> &'static str {
        match self {
            Self::RustDds => "rustdds",
            Self::Cyclone => "cyclone",
        }
    }

    /// Whether this build of horus-ros includes the backend (Cyclone needs the feature `cyclone`).
    pub const fn is_available(self) -> bool {
        match self {
            Self::RustDds => true,
            Self::Cyclone => cfg!(feature = "cyclone"),
        }
    }

    /// Whether samples carry `related_sample_identity` both ways (needed to call or serve peers
    /// that follow the rmw_fastrtps service convention). Cyclone DDS has no API for it.
    pub const fn carries_sample_identity(self) -> bool {
        matches!(self, Self::RustDds)
    }

    /// Whether participants and endpoints announce USER_DATA (`enclave=`, `typehash=`,
    /// `clientid=`/`serviceid=`), as rmw_cyclonedds does. RustDDS cannot send it.
    pub const fn announces_user_data(self) -> bool {
        matches!(self, Self::Cyclone)
    }

    /// The backend [`BACKEND_ENV`] asks for through `get` (e.g. `std::env::var`); `None` if unset
    /// or empty.
    pub fn from_env_with(
        get: impl Fn(&str) -> Option<String>,
    ) -> Result<Option<Self>, BackendError> {
        match get(BACKEND_ENV) {
            None => Ok(None),
            Some(v) if v.trim().is_empty() => Ok(None),
            Some(v) => v.parse().map(Some),
        }
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Backend {
    type Err = BackendError;

    /// `rustdds` or `cyclone` (case-insensitive; `cyclonedds` also accepted).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "rustdds" => Ok(Self::RustDds),
            "cyclone" | "cyclonedds" => Ok(Self::Cyclone),
            _ => Err(BackendError::Unknown {
                value: s.to_owned(),
            }),
        }
    }
}

/// Why a backend cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BackendError {
    /// The name is not a backend.
    #[error(
        "unknown DDS backend '{value}' (expected 'rustdds' or 'cyclone', e.g. in {BACKEND_ENV})"
    )]
    Unknown {
        /// The value given.
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
        assert_eq!(Backend::from_env_with(|_| None), Ok(None));
        assert_eq!(Backend::from_env_with(|_| Some(String::new())), Ok(None));
        assert_eq!(
            Backend::from_env_with(|k| (k == BACKEND_ENV).then(|| "cyclone".to_owned())),
            Ok(Some(Backend::Cyclone))
        );
        for b in Backend::ALL {
            assert_eq!(b.to_string().parse::<Backend>(), Ok(b));
        }
        assert!(Backend::RustDds.is_available());
        assert_eq!(Backend::Cyclone.is_available(), cfg!(feature = "cyclone"));
    }
}
