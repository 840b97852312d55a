//! Shared by the tests that run the crate's examples as the programs they are.

/// The built example `name` (`cargo test` builds every example of the crate beside the tests).
pub use horus_ros_test_support::built_example as example_path;
