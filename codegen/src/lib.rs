//! Rust types from ROS 2 interface files, without a ROS install.
//!
//! - [`ament`]: the ament resource index: installed packages' interfaces and their files.
//! - [`definition`]: what an interface file defines (rosidl_parser's model).
//! - [`msg`]: `.msg`/`.srv`/`.action` files (rosidl_adapter's grammar).
//! - [`idl`]: `.idl` files as rosidl generates them.

pub mod ament;
pub mod definition;
pub mod error;

pub use error::{Location, ParseError};
