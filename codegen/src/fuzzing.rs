//! Fuzzing entry points of the interface parsers: each takes arbitrary bytes and panics only on a
//! bug (called by the `fuzz/` targets and `tests/fuzz_idl.rs`).
//!
//! - [`idl`]: bytes as an `.idl` file's text ([`crate::idl::parse_idl`]).
//! - [`msg`]: a kind byte (`m`essage, `s`ervice, `a`ction) then a `.msg`/`.srv`/`.action` file's
//!   text ([`crate::msg`]).

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

/// Parses `data` as [`msg`] does; `Err` for bytes that are no input (not UTF-8, or empty).
pub fn parse_msg(data: &[u8]) -> Result<Result<(), crate::ParseError>, String> {
    let (&kind, rest) = data.split_first().ok_or("no kind byte")?;
    let text = std::str::from_utf8(rest).map_err(|e| e.to_string())?;
    let file = Path::new("fuzz");
    Ok(match kind {
        b's' => crate::msg::parse_service("fuzz_pkg", "Fuzz", file, text).map(|_| ()),
        b'a' => crate::msg::parse_action("fuzz_pkg", "Fuzz", file, text).map(|_| ()),
        _ => crate::msg::parse_message("fuzz_pkg", "Fuzz", file, text).map(|_| ()),
    })
}

/// Parses `data` (a kind byte, then UTF-8 text) as a `.msg`, `.srv` or `.action` file; an error
/// must point inside the text.
pub fn msg(data: &[u8]) {
    if let Ok(Err(e)) = parse_msg(data) {
        let text = String::from_utf8_lossy(&data[1..]);
        let lines = text.lines().count().max(1);
        assert!(
            e.location.line >= 1
                && e.location.line <= lines
                && e.location.column >= 1
                && e.location.column
                    <= text
                        .lines()
                        .nth(e.location.line - 1)
                        .map_or(0, |l| l.chars().count())
                        + 1,
            "{e} lies outside the text"
        );
    }
}
