//! The RIHS01 type hash of a [`TypeDescription`] (REP-2011).
//!
//! Algorithm from rosidl_generator_type_description (jazzy) `__init__.py` `calculate_type_hash`:
//! the description as JSON `{"type_description": …, "referenced_type_descriptions": […]}` with
//! every field's `default_value` removed, dumped by Python
//! `json.dumps(separators=(', ', ': '), sort_keys=False, ensure_ascii=True)`, then SHA-256.

use serde::Serialize;
use sha2::{Digest, Sha256};
use std::io;

use crate::type_description_interfaces::msg::{
    FieldType, IndividualTypeDescription, TypeDescription,
};
use crate::type_hash::TypeHash;

#[derive(Serialize)]
struct HashableDescription<'a> {
    type_description: HashableType<'a>,
    referenced_type_descriptions: Vec<HashableType<'a>>,
}

#[derive(Serialize)]
struct HashableType<'a> {
    type_name: &'a str,
    fields: Vec<HashableField<'a>>,
}

#[derive(Serialize)]
struct HashableField<'a> {
    name: &'a str,
    #[serde(rename = "type")]
    field_type: &'a FieldTypeJson<'a>,
}

// Key order as rosidl's `serialize_field_type`.
#[derive(Serialize)]
struct FieldTypeJson<'a> {
    type_id: u8,
    capacity: u64,
    string_capacity: u64,
    nested_type_name: &'a str,
}

impl<'a> FieldTypeJson<'a> {
    fn new(t: &'a FieldType) -> Self {
        Self {
            type_id: t.type_id,
            capacity: t.capacity,
            string_capacity: t.string_capacity,
            nested_type_name: &t.nested_type_name,
        }
    }
}

/// The exact JSON text that RIHS01 hashes for `description`.
pub fn hashable_json(description: &TypeDescription) -> String {
    let all: Vec<&IndividualTypeDescription> = std::iter::once(&description.type_description)
        .chain(&description.referenced_type_descriptions)
        .collect();
    let field_types: Vec<Vec<FieldTypeJson<'_>>> = all
        .iter()
        .map(|t| {
            t.fields
                .iter()
                .map(|f| FieldTypeJson::new(&f.r#type))
                .collect()
        })
        .collect();
    let mut types = all.iter().zip(&field_types).map(|(t, fts)| HashableType {
        type_name: &t.type_name,
        fields: t
            .fields
            .iter()
            .zip(fts)
            .map(|(f, ft)| HashableField {
                name: &f.name,
                field_type: ft,
            })
            .collect(),
    });
    let Some(type_description) = types.next() else {
        return String::new(); // unreachable: `all` has at least the main type
    };
    let doc = HashableDescription {
        type_description,
        referenced_type_descriptions: types.collect(),
    };
    let mut out = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut out, PythonFormatter);
    // Serializing plain structs of strings and integers into a Vec cannot fail.
    if doc.serialize(&mut ser).is_err() {
        return String::new();
    }
    String::from_utf8(out).unwrap_or_default()
}

/// RIHS01 hash of `description`.
pub fn rihs01(description: &TypeDescription) -> TypeHash {
    let digest = Sha256::digest(hashable_json(description).as_bytes());
    TypeHash::rihs01(digest.into())
}

/// serde_json formatter reproducing Python's `json.dumps(separators=(', ', ': '),
/// ensure_ascii=True)`: `", "` between items, `": "` after keys, non-ASCII and DEL as `\uXXXX`.
struct PythonFormatter;

impl serde_json::ser::Formatter for PythonFormatter {
    fn begin_array_value<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        if first {
            Ok(())
        } else {
            w.write_all(b", ")
        }
    }

    fn begin_object_key<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        if first {
            Ok(())
        } else {
            w.write_all(b", ")
        }
    }

    fn begin_object_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(b": ")
    }

    fn write_string_fragment<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        fragment: &str,
    ) -> io::Result<()> {
        for c in fragment.chars() {
            if c.is_ascii() && c != '\u{7f}' {
                let mut buf = [0u8; 1];
                w.write_all(c.encode_utf8(&mut buf).as_bytes())?;
            } else {
                let mut units = [0u16; 2];
                for u in c.encode_utf16(&mut units) {
                    write!(w, "\\u{u:04x}")?;
                }
            }
        }
        Ok(())
    }
}
