//! The types compiled into horus-ros-msgs, by ROS name, with their descriptions: what the CLI
//! knows without an install (`interface list`, `service call` of a compiled service type).

use std::sync::OnceLock;

use horus_ros_msgs::TypeDescription;

/// A type compiled into horus-ros-msgs.
#[derive(Clone, Copy, Debug)]
pub struct CompiledType {
    /// `pkg/msg/Name` or `pkg/srv/Name`.
    pub name: &'static str,
    /// Its description (with every type it references).
    pub describe: fn() -> TypeDescription,
}

impl CompiledType {
    /// Whether this is a service (`pkg/srv/Name`).
    pub fn is_service(&self) -> bool {
        self.name.split('/').nth(1) == Some("srv")
    }
}

/// Every compiled message, service and action type ([`horus_ros_msgs::INTERFACES`]), messages
/// first, then services, then actions, each sorted by name.
pub fn compiled_types() -> &'static [CompiledType] {
    static TYPES: OnceLock<Vec<CompiledType>> = OnceLock::new();
    TYPES.get_or_init(|| {
        let mut all: Vec<CompiledType> = horus_ros_msgs::INTERFACES
            .iter()
            .flat_map(|(_, interfaces)| interfaces.iter())
            .map(|(name, describe)| CompiledType {
                name,
                describe: *describe,
            })
            .collect();
        let kind = |t: &CompiledType| match t.name.split('/').nth(1) {
            Some("msg") => 0,
            Some("srv") => 1,
            _ => 2,
        };
        all.sort_by(|a, b| (kind(a), a.name).cmp(&(kind(b), b.name)));
        all
    })
}

/// The compiled type named `type_name` (`pkg/msg/Name` or `pkg/srv/Name`).
pub fn compiled_type(type_name: &str) -> Option<&'static CompiledType> {
    compiled_types().iter().find(|t| t.name == type_name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_compiled_type_is_listed_once_and_describes_itself() {
        let mut names: Vec<&str> = compiled_types().iter().map(|t| t.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), compiled_types().len());
        for t in compiled_types() {
            assert_eq!((t.describe)().type_description.type_name, t.name);
        }
        assert!(compiled_type("std_srvs/srv/SetBool").is_some_and(CompiledType::is_service));
        assert!(compiled_type("std_msgs/msg/String").is_some_and(|t| !t.is_service()));
    }
}
