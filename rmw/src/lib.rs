//! RMW core.
