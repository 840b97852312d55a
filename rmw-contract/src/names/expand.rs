//! Expansion of user-written names into fully-qualified ones.
//!
//! Follows rcl `src/rcl/expand_topic_name.c` (`rcl_expand_topic_name`) and the
//! final check of rcl `src/rcl/node_resolve_name.c` (`rcl_resolve_name`, which
//! validates the result with `rmw_validate_full_topic_name`), ros2/rcl 9.2
//! (jazzy). Remapping is not applied here.

use super::namespace::Namespace;
use super::node_name::NodeName;
use super::service_name::ServiceName;
use super::topic_name::{validate_full_topic_name, TopicName, TopicNameError};
use super::unexpanded::{validate_unexpanded_name, UnexpandedNameError};

/// rcl `SUBSTITUION_NODE_NAME`.
const SUBSTITUTION_NODE_NAME: &str = "node";
/// rcl `SUBSTITUION_NAMESPACE`.
const SUBSTITUTION_NAMESPACE: &str = "ns";
/// rcl `SUBSTITUION_NAMESPACE2`.
const SUBSTITUTION_NAMESPACE2: &str = "namespace";

/// Why a name could not be expanded into a valid fully-qualified name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ExpandError {
    /// The input fails `rcl_validate_topic_name` (rcl `RCL_RET_TOPIC_NAME_INVALID`).
    #[error(transparent)]
    InvalidInput(#[from] UnexpandedNameError),
    /// A `{substitution}` is neither built in nor given (rcl
    /// `RCL_RET_UNKNOWN_SUBSTITUTION`); holds it with its braces.
    #[error("unknown substitution: {substitution}")]
    UnknownSubstitution {
        /// The substitution, e.g. `{doesnotexist}`.
        substitution: String,
    },
    /// The expanded name fails `rmw_validate_full_topic_name` (rcl
    /// `RCL_RET_TOPIC_NAME_INVALID` / `RCL_RET_SERVICE_NAME_INVALID`).
    #[error("expanded name '{expanded}' is invalid: {cause}")]
    InvalidExpansion {
        /// The expanded string.
        expanded: String,
        /// Why it is invalid; indices refer to `expanded`.
        cause: TopicNameError,
    },
}

/// Expands `input` as `rcl_expand_topic_name` does, without validating the
/// result: `~` becomes `<ns>/<node>`, `{node}`, `{ns}` and `{namespace}` are
/// replaced, then `{key}` from `substitutions` (rcl's default map is empty),
/// and a relative result is prefixed with the namespace.
///
/// Unlike rcl, a substitution's value is not scanned again for `{...}`.
pub fn expand_name(
    input: &str,
    node: &NodeName,
    namespace: &Namespace,
    substitutions: &[(&str, &str)],
) -> Result<String, ExpandError> {
    validate_unexpanded_name(input)?;
    let has_substitution = input.contains('{');
    if input.starts_with('/') && !has_substitution {
        return Ok(input.to_owned());
    }
    // rcl joins with no extra '/' when the namespace is just "/".
    let sep = if namespace.is_root() { "" } else { "/" };
    let mut output = match input.strip_prefix('~') {
        Some(rest) => format!("{namespace}{sep}{node}{rest}"),
        None => input.to_owned(),
    };
    if has_substitution {
        output = substitute(&output, node, namespace, substitutions)?;
    }
    if !output.starts_with('/') {
        output = format!("{namespace}{sep}{output}");
    }
    Ok(output)
}

/// Replaces every `{key}` in `input`; braces are balanced and not nested, as
/// `validate_unexpanded_name` guarantees.
fn substitute(
    input: &str,
    node: &NodeName,
    namespace: &Namespace,
    substitutions: &[(&str, &str)],
) -> Result<String, ExpandError> {
    let mut output = String::with_capacity(input.len());
    let mut rest = input;
    while let Some(open) = rest.find('{') {
        let Some(close) = rest[open..].find('}').map(|c| open + c) else {
            break;
        };
        let key = &rest[open + 1..close];
        let replacement = match key {
            SUBSTITUTION_NODE_NAME => node.as_str(),
            SUBSTITUTION_NAMESPACE | SUBSTITUTION_NAMESPACE2 => namespace.as_str(),
            _ => substitutions
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| *v)
                .ok_or_else(|| ExpandError::UnknownSubstitution {
                    substitution: rest[open..=close].to_owned(),
                })?,
        };
        output.push_str(&rest[..open]);
        output.push_str(replacement);
        rest = &rest[close + 1..];
    }
    output.push_str(rest);
    Ok(output)
}

/// Expands `input` and validates the result as a fully-qualified name.
fn expand_validated(
    input: &str,
    node: &NodeName,
    namespace: &Namespace,
    substitutions: &[(&str, &str)],
) -> Result<String, ExpandError> {
    let expanded = expand_name(input, node, namespace, substitutions)?;
    match validate_full_topic_name(&expanded) {
        Ok(()) => Ok(expanded),
        Err(source) => Err(ExpandError::InvalidExpansion {
            expanded,
            cause: source,
        }),
    }
}

impl TopicName {
    /// Expands a user-written topic name (`chatter`, `~/state`, `{node}/x`,
    /// `/abs`) for the given node, as rcl does before remapping.
    pub fn expand(
        input: &str,
        node: &NodeName,
        namespace: &Namespace,
    ) -> Result<Self, ExpandError> {
        Self::expand_with(input, node, namespace, &[])
    }

    /// Like [`TopicName::expand`], with extra `{key}` substitutions.
    pub fn expand_with(
        input: &str,
        node: &NodeName,
        namespace: &Namespace,
        substitutions: &[(&str, &str)],
    ) -> Result<Self, ExpandError> {
        let expanded = expand_validated(input, node, namespace, substitutions)?;
        Ok(Self(expanded))
    }
}

impl ServiceName {
    /// Expands a user-written service name with the topic rules, as rcl does.
    pub fn expand(
        input: &str,
        node: &NodeName,
        namespace: &Namespace,
    ) -> Result<Self, ExpandError> {
        Self::expand_with(input, node, namespace, &[])
    }

    /// Like [`ServiceName::expand`], with extra `{key}` substitutions.
    pub fn expand_with(
        input: &str,
        node: &NodeName,
        namespace: &Namespace,
        substitutions: &[(&str, &str)],
    ) -> Result<Self, ExpandError> {
        let expanded = expand_validated(input, node, namespace, substitutions)?;
        Ok(Self(expanded))
    }
}
