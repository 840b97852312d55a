//! Rust types from ROS 2 interface files, without a ROS install: a `build.rs` [`Builder`] in
//! the manner of prost-build, whose generated types describe and hash exactly as Jazzy's.
//!
//! - [`ament`]: the ament resource index: installed packages' interfaces and their files.
//! - [`definition`]: what an interface file defines (rosidl_parser's model).
//! - [`msg`]: `.msg`/`.srv`/`.action` files (rosidl_adapter's grammar).
//! - [`idl`]: `.idl` files as rosidl generates them.
//! - [`type_description`]: their type descriptions and RIHS01 hashes, as Jazzy computes them.
//! - [`rust`]: the Rust source of a package; [`builder`]: inputs, dependencies, output files.
//! - [`compiled`]: the types horus-ros-msgs already has.

pub mod ament;
pub mod builder;
pub mod compiled;
pub mod definition;
pub mod error;
#[doc(hidden)]
pub mod fuzzing;
pub mod idl;
pub mod msg;
pub mod rust;
pub mod type_description;

pub use builder::{Builder, GenerateError, Generated};
pub use error::{Location, ParseError};
pub use type_description::{DescribeError, TypeRegistry};
