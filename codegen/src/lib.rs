//! Rust types from ROS 2 interface files, without a ROS install.
//!
//! - [`definition`]: what an interface file defines (rosidl_parser's model).
//! - [`msg`]: `.msg`/`.srv`/`.action` files (rosidl_adapter's grammar).
//! - [`idl`]: `.idl` files as rosidl generates them.
//! - [`fuzzing`]: the fuzz targets' entry points.

pub mod definition;
pub mod error;
pub mod fuzzing;
pub mod idl;

pub use error::{Location, ParseError};
