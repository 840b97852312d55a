//! Errors of the QoS module.

/// Why a QoS profile or policy value could not be converted.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum QosError {
    /// A policy is UNKNOWN, which no DDS endpoint can be created with
    /// (rmw_cyclonedds `create_readwrite_qos` and rmw_fastrtps `fill_entity_qos_from_profile`
    /// both refuse it).
    #[error("QoS {policy} policy is UNKNOWN and cannot be mapped to DDS")]
    UnknownPolicy {
        /// The policy name as rmw spells it (`history`, `reliability`, ...).
        policy: &'static str,
    },
    /// The history depth does not fit DDS's signed 32-bit depth.
    #[error("unsupported history depth {0}: DDS allows at most 2147483647")]
    DepthTooLarge(usize),
    /// A string is not one of rmw's names for a policy value.
    #[error("'{value}' is not a valid {policy} policy value")]
    InvalidPolicyName {
        /// The policy name as rmw spells it (`history`, `reliability`, ...).
        policy: &'static str,
        /// The text that failed to parse.
        value: String,
    },
}
