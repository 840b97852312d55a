//! Fuzzing entry points of the interface parsers: each takes arbitrary bytes and panics only on a
//! bug (called by the `fuzz/` targets and `tests/fuzz_idl.rs`).
//!
//! - [`idl`]: bytes as an `.idl` file's text ([`crate::idl::parse_idl`]).

use std::path::Path;

/// Parses `data` (if UTF-8) as an `.idl` file; an error must point inside the text.
pub fn idl(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Err(e) = crate::idl::parse_idl(Path::new("fuzz.idl"), text) {
        let lines = text.split('\n').count();
        assert!(
            e.location.line >= 1 && e.location.line <= lines && e.location.column >= 1,
            "{e} lies outside the text"
        );
    }
}
