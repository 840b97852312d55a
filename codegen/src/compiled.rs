//! The types compiled into horus-ros-msgs ([`horus_ros_msgs::INTERFACES`]), by ROS type name:
//! generated code uses them rather than generating them again (so a generated message's
//! `std_msgs/Header` is the `Header` the rest of horus-ros publishes).

use std::collections::BTreeSet;
use std::sync::OnceLock;

use crate::definition::NamedType;
use crate::rust::rust_type_name;

/// Every type name compiled in: each interface and every type its description references.
fn names() -> &'static BTreeSet<String> {
    static NAMES: OnceLock<BTreeSet<String>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let mut out = BTreeSet::new();
        for (_, interfaces) in horus_ros_msgs::INTERFACES {
            for (_, describe) in interfaces.iter() {
                let d = describe();
                out.insert(d.type_description.type_name.clone());
                out.extend(
                    d.referenced_type_descriptions
                        .into_iter()
                        .map(|t| t.type_name),
                );
            }
        }
        out
    })
}

/// The Rust path of the compiled type `t`, if horus-ros-msgs has it.
pub fn path(t: &NamedType) -> Option<String> {
    if !names().contains(&t.to_string()) {
        return None;
    }
    // rmw_dds_common's types are written in Rust at the package's top level.
    if t.package == "rmw_dds_common" {
        return Some(format!("::horus_ros_msgs::rmw_dds_common::{}", t.name));
    }
    Some(format!(
        "::horus_ros_msgs::{}::{}::{}",
        t.package,
        t.namespace,
        rust_type_name(&t.name)
    ))
}
