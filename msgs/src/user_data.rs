//! DDS USER_DATA `key=value;` strings as ROS 2 writes and reads them.
//!
//! Parsing follows rmw (jazzy) `rmw/impl/cpp/key_value.hpp` `parse_key_value`; the type hash entry
//! follows rmw_dds_common (jazzy) `qos.cpp` `parse_type_hash_from_user_data`.

use std::collections::BTreeMap;

use crate::type_hash::{TypeHash, TypeHashError};

/// Parses `key=value;key=value;` USER_DATA into a map, exactly as rmw's `parse_key_value`:
/// keys are alphanumeric, values are raw bytes up to `;` (`;;` inside a value is kept as one
/// `;`), trailing NULs are accepted. Anything malformed yields an empty map (not an error: other
/// DDS applications use USER_DATA for other things).
pub fn parse_key_value(data: &[u8]) -> BTreeMap<String, Vec<u8>> {
    parse_key_value_inner(data).unwrap_or_default()
}

fn parse_key_value_inner(data: &[u8]) -> Option<BTreeMap<String, Vec<u8>>> {
    let mut m = BTreeMap::new();
    if data.is_empty() {
        return None;
    }
    let mut keyfound = false;
    let mut key = String::new();
    let mut value: Vec<u8> = Vec::new();
    let mut prev = 0u8;
    for &u in data {
        if keyfound {
            if u == b';' && prev != b';' {
                prev = u;
                continue;
            } else if u != b';' && prev == b';' {
                if value.is_empty() {
                    return None;
                }
                m.insert(std::mem::take(&mut key), std::mem::take(&mut value));
                keyfound = false;
            } else {
                value.push(u);
            }
        }
        if !keyfound {
            if u == b'=' {
                if key.is_empty() {
                    return None;
                }
                keyfound = true;
            } else if u.is_ascii_alphanumeric() {
                key.push(char::from(u));
            } else if u == 0 && key.is_empty() && !m.is_empty() {
                break; // trailing NULs
            } else if prev != b';' || !key.is_empty() {
                return None;
            }
        }
        prev = u;
    }
    if keyfound {
        if value.is_empty() {
            return None;
        }
        m.insert(key, value);
    } else if !key.is_empty() {
        return None;
    }
    Some(m)
}

/// The type hash announced in an endpoint's USER_DATA (`typehash=RIHS01_…;`).
///
/// No `typehash` entry (or unparsable key-value data) gives [`TypeHash::ZERO`], as rmw_dds_common
/// does; a present but malformed hash is an error.
pub fn parse_type_hash_from_user_data(data: &[u8]) -> Result<TypeHash, TypeHashError> {
    let kv = parse_key_value(data);
    match kv.get("typehash") {
        None => Ok(TypeHash::ZERO),
        Some(v) => {
            let s = std::str::from_utf8(v).map_err(|_| TypeHashError::NotUtf8)?;
            TypeHash::parse(s)
        }
    }
}
