//! rclpy's own CDR of messages (`peers/jazzy_cdr.py`): what `serialize_message` writes for a
//! default-constructed message and for one filled with a value in every field, and whether
//! `deserialize_message` reads bytes as those messages.

use std::io::Write;
use std::process::{Command, Stdio};

use serde_json::Value;

/// Runs `jazzy_cdr.py` on one request (`{"make": [...]}` or `{"compare": {...}}`, see the
/// script) and returns its answer.
pub fn ask(request: &Value) -> Result<Value, String> {
    let mut child = Command::new(crate::python())
        .arg(crate::peer_script("jazzy_cdr.py"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("starting {}: {e}", crate::python().display()))?;
    child
        .stdin
        .take()
        .ok_or("no piped stdin")?
        .write_all(request.to_string().as_bytes())
        .map_err(|e| format!("writing to jazzy_cdr.py: {e}"))?;
    let out = child
        .wait_with_output()
        .map_err(|e| format!("reading jazzy_cdr.py: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "jazzy_cdr.py failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("jazzy_cdr.py printed no JSON: {e}"))
}

/// Bytes from the script's hex.
pub fn from_hex(s: &str) -> Result<Vec<u8>, String> {
    (0..s.len() / 2)
        .map(|i| {
            s.get(2 * i..2 * i + 2)
                .and_then(|b| u8::from_str_radix(b, 16).ok())
                .ok_or_else(|| format!("not hex: {s}"))
        })
        .collect()
}

/// Hex of bytes, as the script reads them.
pub fn to_hex(b: &[u8]) -> String {
    b.iter().map(|b| format!("{b:02x}")).collect()
}
