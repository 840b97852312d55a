//! Interface type names as the verbs take them: `pkg/msg/Name` or `pkg/Name` (rosidl_runtime_py
//! jazzy `get_message` / `get_service`, which complete the short form), with ros2cli's errors.

use crate::CliError;

/// `pkg/<kind>/Name` for `pkg/<kind>/Name` or `pkg/Name`; `None` for anything else (`Err` with
/// the middle part when there are three valid parts of another kind).
fn normalize(t: &str, kind: &str) -> Result<String, Option<()>> {
    let valid = |s: &str| {
        !s.is_empty()
            && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
            && !s.starts_with(|c: char| c.is_ascii_digit())
    };
    match t.split('/').collect::<Vec<_>>().as_slice() {
        [pkg, name] if valid(pkg) && valid(name) => Ok(format!("{pkg}/{kind}/{name}")),
        [pkg, k, name] if *k == kind && valid(pkg) && valid(name) => Ok(t.to_owned()),
        [_, _, _] => Err(Some(())),
        _ => Err(None),
    }
}

/// A message type: `pkg/msg/Name`, or `pkg/Name` completed with `msg`; anything else is
/// ros2cli's `The passed message type is invalid`.
pub fn normalize_message_type(t: &str) -> Result<String, CliError> {
    normalize(t, "msg").map_err(|_| CliError::new("The passed message type is invalid"))
}

/// A service type: `pkg/srv/Name`, or `pkg/Name` completed with `srv`; three parts of another
/// kind are `The passed type is not a service`, anything else `The passed service type is
/// invalid` (ros2service).
pub fn normalize_service_type(t: &str) -> Result<String, CliError> {
    normalize(t, "srv").map_err(|three_parts| {
        CliError::new(match three_parts {
            Some(()) => "The passed type is not a service",
            None => "The passed service type is invalid",
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn message_types_are_normalized_as_rosidl_runtime_py_does() {
        assert_eq!(
            normalize_message_type("std_msgs/String").expect("short"),
            "std_msgs/msg/String"
        );
        assert_eq!(
            normalize_message_type("std_msgs/msg/String").expect("full"),
            "std_msgs/msg/String"
        );
        for bad in ["std_srvs/srv/SetBool", "String", "a/b/c/d", "/x"] {
            assert_eq!(
                normalize_message_type(bad).map_err(|e| e.message),
                Err("The passed message type is invalid".to_owned()),
                "{bad}"
            );
        }
    }

    #[test]
    fn service_types_are_normalized_as_ros2cli_does() {
        assert_eq!(
            normalize_service_type("example_interfaces/AddTwoInts").expect("short"),
            "example_interfaces/srv/AddTwoInts"
        );
        assert_eq!(
            normalize_service_type("std_srvs/srv/Empty").expect("full"),
            "std_srvs/srv/Empty"
        );
        assert_eq!(
            normalize_service_type("std_msgs/msg/String").map_err(|e| e.message),
            Err("The passed type is not a service".to_owned())
        );
        assert_eq!(
            normalize_service_type("nonsense").map_err(|e| e.message),
            Err("The passed service type is invalid".to_owned())
        );
    }
}
