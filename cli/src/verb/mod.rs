//! One module per verb, as ros2cli keeps one file per verb.

pub mod action;
pub mod completions;
pub mod daemon;
pub mod demo;
pub mod echo_options;
pub mod graph;
pub mod interface;
pub mod lifecycle;
pub mod names;
pub mod node;
pub mod param;
#[cfg(feature = "zenoh")]
pub mod router;
pub mod service;
pub mod topic;
pub mod type_name;
