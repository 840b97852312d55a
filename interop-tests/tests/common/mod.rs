//! What several tests of this crate share (each test binary takes what it needs).

pub mod hosts;
