//! ROS 2 (Jazzy) interface types for horus-ros: serde structs with CDR encoding, DDS type names,
//! type descriptions and RIHS01 type hashes (REP-2011).
//!
//! - [`Message`] / [`Service`]: what every interface type provides; [`RosField`] describes
//!   struct fields generically; [`DescriptionBuilder`] builds descriptions.
//! - [`TypeHash`]: `RIHS01_…` hashes, USER_DATA helpers in [`user_data`].
//! - [`cdr`]: [`to_cdr`] / [`from_cdr`] with the encapsulation header.
//! - [`runtime`]: what generated structs use: bound checks at encode ([`runtime::Bounded`]),
//!   fixed arrays of any length; [`WString`] is a ROS `wstring`.
//! - One module per ROS package, each with `msg` / `srv` submodules.

#[macro_use]
mod macros;

pub mod cdr;
pub mod description;
pub mod field;
#[doc(hidden)]
pub mod fuzzing;
pub mod message;
pub mod rihs;
pub mod runtime;
pub mod type_hash;
pub mod user_data;
mod wstring;

pub mod builtin_interfaces;
pub mod example_interfaces;
pub mod geometry_msgs;
pub mod rcl_interfaces;
pub mod rmw_dds_common;
pub mod sensor_msgs;
pub mod service_msgs;
pub mod std_msgs;
pub mod std_srvs;
pub mod type_description_interfaces;

pub use cdr::{from_cdr, to_cdr, CdrError};
pub use description::DescriptionBuilder;
pub use field::{Byte, RosField};
pub use message::{dds_type_name, ros_type_name_from_dds, Action, Message, Service};
/// serde, as the generated types (horus-ros-codegen) name it.
pub use serde;
pub use type_description_interfaces::msg::{
    Field, FieldType, IndividualTypeDescription, TypeDescription,
};
pub use type_hash::{TypeHash, TypeHashError};
pub use wstring::WString;
