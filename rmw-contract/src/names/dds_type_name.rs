//! ROS type names to DDS type names and back.
//!
//! Mangling as rmw_fastrtps_cpp `src/type_support_common.hpp`
//! `_create_type_name` and rmw_cyclonedds_cpp `MessageTypeSupport_impl.hpp` /
//! `ServiceTypeSupport_impl.hpp` (`<ns>::dds_::<Name>_`, `_Request_`,
//! `_Response_`); demangling as rmw_fastrtps_shared_cpp `src/demangle.cpp`
//! `_demangle_if_ros_type` and `_demangle_service_type_only` (jazzy).

use super::type_name::{RosTypeName, RosTypeNameError};

/// The namespace rosidl inserts before DDS type names.
const DDS_NAMESPACE: &str = "dds_::";
/// DDS suffix of service request types.
const REQUEST_TYPE_SUFFIX: &str = "_Request_";
/// DDS suffix of service response types.
const RESPONSE_TYPE_SUFFIX: &str = "_Response_";

/// Which half of a service a DDS type carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServiceTypeRole {
    /// `<Name>_Request_`.
    Request,
    /// `<Name>_Response_`.
    Response,
}

/// Why a DDS type name is not that of a ROS type.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum DdsTypeNameError {
    /// No `dds_::` namespace, or (for messages) no trailing `_`.
    #[error("not a ROS type: '{0}'")]
    NotRosType(String),
    /// A service type without a `_Request_`/`_Response_` suffix at its end.
    #[error("service type contains 'dds_::' but does not have a suffix: '{0}'")]
    NoServiceSuffix(String),
    /// The demangled name is not a valid `package/kind/Name`.
    #[error("demangled type name '{demangled}' is invalid: {cause}")]
    InvalidTypeName {
        /// The demangled string.
        demangled: String,
        /// Why it is invalid.
        cause: RosTypeNameError,
    },
}

impl RosTypeName {
    /// `pkg::kind::dds_::`, the DDS namespace of this type.
    fn dds_prefix(&self) -> String {
        format!("{}::{}::{DDS_NAMESPACE}", self.package(), self.kind())
    }

    /// The DDS type name of a message: `pkg/msg/Name` → `pkg::msg::dds_::Name_`.
    pub fn to_dds_type_name(&self) -> String {
        format!("{}{}_", self.dds_prefix(), self.name())
    }

    /// The DDS type of one half of a service: `pkg/srv/Name` →
    /// `pkg::srv::dds_::Name_Request_` or `pkg::srv::dds_::Name_Response_`.
    pub fn to_dds_service_type_name(&self, role: ServiceTypeRole) -> String {
        let suffix = match role {
            ServiceTypeRole::Request => REQUEST_TYPE_SUFFIX,
            ServiceTypeRole::Response => RESPONSE_TYPE_SUFFIX,
        };
        format!("{}{}{suffix}", self.dds_prefix(), self.name())
    }

    /// Demangles any ROS DDS type (`_demangle_if_ros_type`):
    /// `pkg::msg::dds_::Name_` → `pkg/msg/Name`; a service half gives e.g.
    /// `pkg/srv/Name_Request`.
    pub fn from_dds_type_name(dds_type: &str) -> Result<Self, DdsTypeNameError> {
        let not_ros = || DdsTypeNameError::NotRosType(dds_type.to_owned());
        let without_underscore = dds_type.strip_suffix('_').ok_or_else(not_ros)?;
        let (namespace, name) = without_underscore
            .split_once(DDS_NAMESPACE)
            .ok_or_else(not_ros)?;
        parse_demangled(namespace, name)
    }

    /// Demangles a service half (`_demangle_service_type_only`):
    /// `pkg::srv::dds_::Name_Request_` → (`pkg/srv/Name`, `Request`).
    pub fn from_dds_service_type_name(
        dds_type: &str,
    ) -> Result<(Self, ServiceTypeRole), DdsTypeNameError> {
        let (namespace, rest) = dds_type
            .split_once(DDS_NAMESPACE)
            .ok_or_else(|| DdsTypeNameError::NotRosType(dds_type.to_owned()))?;
        let (name, role) = if let Some(name) = rest.strip_suffix(RESPONSE_TYPE_SUFFIX) {
            (name, ServiceTypeRole::Response)
        } else if let Some(name) = rest.strip_suffix(REQUEST_TYPE_SUFFIX) {
            (name, ServiceTypeRole::Request)
        } else {
            return Err(DdsTypeNameError::NoServiceSuffix(dds_type.to_owned()));
        };
        Ok((parse_demangled(namespace, name)?, role))
    }
}

/// Joins `pkg::kind::` and `Name` into `pkg/kind/Name` and validates it.
fn parse_demangled(namespace: &str, name: &str) -> Result<RosTypeName, DdsTypeNameError> {
    let demangled = format!("{}{name}", namespace.replace("::", "/"));
    RosTypeName::new(&demangled).map_err(|source| DdsTypeNameError::InvalidTypeName {
        demangled,
        cause: source,
    })
}
