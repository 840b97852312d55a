//! horus-ros actions.

pub mod interfaces;
