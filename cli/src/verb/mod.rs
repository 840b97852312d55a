//! One module per verb, as ros2cli keeps one file per verb.

pub mod demo;
