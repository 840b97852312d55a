//! Validated ROS interface type names: `package/kind/Name`.
//!
//! Package names follow rosidl_adapter `parser.py` `VALID_PACKAGE_NAME_PATTERN`
//! (ros2/rosidl, jazzy). Type names are checked more loosely than rosidl's
//! `VALID_MESSAGE_NAME_PATTERN` (`^[A-Z][A-Za-z0-9]*$`), because generated
//! types carry `_`-joined suffixes (`AddTwoInts_Request`, `Fibonacci_SendGoal`,
//! `SetBool_Event`).

use core::fmt;

/// The interface kind in a type name (`msg`, `srv`, `action`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum InterfaceKind {
    /// `msg`.
    Msg,
    /// `srv`.
    Srv,
    /// `action`.
    Action,
}

impl InterfaceKind {
    /// The kind as spelled in type names.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Msg => "msg",
            Self::Srv => "srv",
            Self::Action => "action",
        }
    }

    /// Parses `msg`, `srv` or `action`.
    pub fn from_name(kind: &str) -> Option<Self> {
        match kind {
            "msg" => Some(Self::Msg),
            "srv" => Some(Self::Srv),
            "action" => Some(Self::Action),
            _ => None,
        }
    }
}

impl fmt::Display for InterfaceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a string is not a valid `package/kind/Name` type name. Indices are
/// byte offsets into the whole input.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RosTypeNameError {
    /// Not three `/`-separated parts.
    #[error("type name must have the form '<package>/<msg|srv|action>/<Name>'")]
    WrongForm,
    /// The package part breaks rosidl's package-name rule.
    #[error(
        "package name must start with a lowercase letter, contain only [a-z0-9_], \
         and have no '__' nor a trailing '_' (index {index})"
    )]
    InvalidPackage {
        /// Offset of the offending byte (0 when empty).
        index: usize,
    },
    /// The middle part is not `msg`, `srv` or `action`.
    #[error("interface kind must be 'msg', 'srv' or 'action', not '{kind}'")]
    UnknownKind {
        /// The middle part as given.
        kind: String,
    },
    /// The last part is not a valid type name.
    #[error(
        "type name must start with a letter, contain only alphanumerics or '_', \
         and not end with '_' (index {index})"
    )]
    InvalidName {
        /// Offset of the offending byte (that of the part's start when empty).
        index: usize,
    },
}

/// A ROS interface type name such as `std_msgs/msg/String` or
/// `example_interfaces/srv/AddTwoInts`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RosTypeName {
    full: String,
    package_len: usize,
    kind: InterfaceKind,
}

impl RosTypeName {
    /// Parses and validates `package/kind/Name`.
    pub fn new(type_name: &str) -> Result<Self, RosTypeNameError> {
        let mut parts = type_name.split('/');
        let (Some(package), Some(kind), Some(name), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return Err(RosTypeNameError::WrongForm);
        };
        check_package(package).map_err(|index| RosTypeNameError::InvalidPackage { index })?;
        let kind = InterfaceKind::from_name(kind).ok_or_else(|| RosTypeNameError::UnknownKind {
            kind: kind.to_owned(),
        })?;
        let name_start = type_name.len() - name.len();
        check_name(name).map_err(|i| RosTypeNameError::InvalidName {
            index: name_start + i,
        })?;
        Ok(Self {
            full: type_name.to_owned(),
            package_len: package.len(),
            kind,
        })
    }

    /// Builds `package/kind/name` from its parts, validating them.
    pub fn from_parts(
        package: &str,
        kind: InterfaceKind,
        name: &str,
    ) -> Result<Self, RosTypeNameError> {
        Self::new(&format!("{package}/{kind}/{name}"))
    }

    /// The whole name, e.g. `std_msgs/msg/String`.
    pub fn as_str(&self) -> &str {
        &self.full
    }

    /// The package, e.g. `std_msgs`.
    pub fn package(&self) -> &str {
        &self.full[..self.package_len]
    }

    /// The interface kind.
    pub fn kind(&self) -> InterfaceKind {
        self.kind
    }

    /// The type's own name, e.g. `String`.
    pub fn name(&self) -> &str {
        let start = self.package_len + 1 + self.kind.as_str().len() + 1;
        &self.full[start..]
    }
}

/// rosidl `VALID_PACKAGE_NAME_PATTERN`: `[a-z][a-z0-9_]*`, no `__`, no
/// trailing `_`. Returns the offending offset.
fn check_package(package: &str) -> Result<(), usize> {
    let bytes = package.as_bytes();
    match bytes.first() {
        Some(b) if b.is_ascii_lowercase() => {}
        _ => return Err(0),
    }
    for (i, &b) in bytes.iter().enumerate() {
        if !(b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_') {
            return Err(i);
        }
        if b == b'_' && (i + 1 == bytes.len() || bytes[i + 1] == b'_') {
            return Err(i);
        }
    }
    Ok(())
}

/// A letter, then `[A-Za-z0-9_]`, not ending with `_`. Returns the offending
/// offset within `name`.
fn check_name(name: &str) -> Result<(), usize> {
    let bytes = name.as_bytes();
    match bytes.first() {
        Some(b) if b.is_ascii_alphabetic() => {}
        _ => return Err(0),
    }
    if let Some(i) = bytes
        .iter()
        .position(|&b| !(b.is_ascii_alphanumeric() || b == b'_'))
    {
        return Err(i);
    }
    if bytes.ends_with(b"_") {
        return Err(bytes.len() - 1);
    }
    Ok(())
}

impl fmt::Display for RosTypeName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.full)
    }
}

impl core::str::FromStr for RosTypeName {
    type Err = RosTypeNameError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::new(s)
    }
}

impl TryFrom<&str> for RosTypeName {
    type Error = RosTypeNameError;

    fn try_from(s: &str) -> Result<Self, Self::Error> {
        Self::new(s)
    }
}

impl AsRef<str> for RosTypeName {
    fn as_ref(&self) -> &str {
        &self.full
    }
}
