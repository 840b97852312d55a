//! Rust types from ROS 2 interface files, without a ROS install.
//!
//! - [`ament`]: the ament resource index: installed packages' interfaces and their files.
//! - [`definition`]: what an interface file defines (rosidl_parser's model).
//! - [`msg`]: `.msg`/`.srv`/`.action` files (rosidl_adapter's grammar).
//! - [`idl`]: `.idl` files as rosidl generates them.
//! - [`type_description`]: their type descriptions and RIHS01 hashes, as Jazzy computes them.

pub mod ament;
pub mod definition;
pub mod error;
pub mod idl;
pub mod msg;
pub mod type_description;

pub use error::{Location, ParseError};
pub use type_description::{DescribeError, TypeRegistry};
