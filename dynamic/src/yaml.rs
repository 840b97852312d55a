//! ros2cli's request values: a YAML document (`yaml.safe_load`) applied to a default message as
//! rosidl_runtime_py (jazzy) `set_message_fields` does, with the errors rclpy's field setters
//! raise (rosidl_generator_py jazzy `_msg.py.em`).
//!
//! Deliberate differences, each to refuse a value ros2cli would silently mangle: an integer
//! field takes a float only if it is integral (Python truncates), a `bool` field takes no
//! string (Python makes `'false'` true), and a `byte` field takes an integer 0..=255 (Python's
//! `bytes(n)` makes n zero bytes).

use yaml_rust2::{ScanError, Yaml, YamlLoader};

use super::repr::{py_float, py_str};
use super::{Container, Elem, FieldTy, Member, Schema, SchemaError, Value};

/// Why a message is not filled from a YAML document ([`fill_from_yaml`], or from JSON with
/// [`fill_from_json`](crate::json::fill_from_json)). The messages are those of ros2cli
/// (`set_message_fields` and rclpy's field setters); an error inside a nested message is that
/// message's error.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FillError {
    /// The text is not YAML.
    #[error("invalid YAML: {cause}")]
    Yaml {
        /// The YAML scanner's error (with its position).
        cause: ScanError,
    },
    /// The type (or a type it uses) cannot be used.
    #[error(transparent)]
    Schema(#[from] SchemaError),
    /// A message's value is not a mapping.
    #[error("Value '{value}' is expected to be a dictionary but is a {found}")]
    NotADictionary {
        /// The value, as Python's `str()` shows it.
        value: String,
        /// Its Python type (`list`, `int`…).
        found: &'static str,
    },
    /// A key that is no field of the message.
    #[error("'{}' object has no attribute '{field}'", short_name(.type_name))]
    NoSuchField {
        /// The message type (`pkg/msg/Name`).
        type_name: String,
        /// The key.
        field: String,
    },
    /// A value of the wrong type for its field.
    #[error("The '{field}' field must be {}", type_requirement(.expected))]
    WrongType {
        /// The field's name.
        field: String,
        /// The field's element type.
        expected: Elem,
    },
    /// A number beyond its field's range.
    #[error("The '{field}' field must be {}", range_requirement(.expected))]
    OutOfRange {
        /// The field's name.
        field: String,
        /// The field's element type.
        expected: Elem,
    },
    /// A string longer than its field's bound.
    #[error("The '{field}' field must be string value not longer than {max}")]
    TooLong {
        /// The field's name.
        field: String,
        /// The bound.
        max: u64,
    },
    /// An array or sequence field's value that is no list of the right length and elements.
    #[error("The '{field}' field must be {}", container_requirement(.expected))]
    WrongContainer {
        /// The field's name.
        field: String,
        /// The field's type.
        expected: FieldTy,
    },
    /// A string that is no integer, for an integer field (Python's `int()` error).
    #[error("invalid literal for int() with base 10: {}", py_str(.text))]
    InvalidInteger {
        /// The field's name.
        field: String,
        /// The string.
        text: String,
    },
    /// A string that is no number, for a float field (Python's `float()` error).
    #[error("could not convert string to float: {}", py_str(.text))]
    InvalidFloat {
        /// The field's name.
        field: String,
        /// The string.
        text: String,
    },
    /// The default value of a struct type is not a struct (a bug).
    #[error("internal error: '{type_name}' is not a struct")]
    NotAStruct {
        /// The type.
        type_name: String,
    },
}

/// The class name Python shows for `type_name`: its last part.
fn short_name(type_name: &str) -> &str {
    type_name.rsplit('/').next().unwrap_or(type_name)
}

/// Parses `text` as YAML and fills a message of type `type_name` with it.
pub fn fill_from_yaml(schema: &Schema, type_name: &str, text: &str) -> Result<Value, FillError> {
    let docs =
        YamlLoader::load_from_str(text).map_err(|source| FillError::Yaml { cause: source })?;
    let doc = docs.into_iter().next().unwrap_or(Yaml::Null);
    fill_from_doc(schema, type_name, &doc)
}

/// Fills a message of type `type_name` with a YAML document already parsed (what
/// [`fill_from_yaml`] does after parsing).
pub fn fill_from_doc(schema: &Schema, type_name: &str, doc: &Yaml) -> Result<Value, FillError> {
    let mut value = schema.default_value(type_name)?;
    fill_struct(schema, type_name, &mut value, doc)?;
    Ok(value)
}

/// Python's type name of a YAML value (`type(v).__name__`).
fn py_type(y: &Yaml) -> &'static str {
    match y {
        Yaml::Integer(_) => "int",
        Yaml::Real(_) => "float",
        Yaml::String(_) => "str",
        Yaml::Boolean(_) => "bool",
        Yaml::Array(_) => "list",
        Yaml::Hash(_) => "dict",
        Yaml::Null | Yaml::BadValue | Yaml::Alias(_) => "NoneType",
    }
}

/// Python's `str()` of a YAML value (for messages).
fn py_display(y: &Yaml) -> String {
    match y {
        Yaml::Integer(i) => i.to_string(),
        Yaml::Real(r) => real(r).map_or_else(|| r.clone(), py_float),
        Yaml::String(s) => s.clone(),
        Yaml::Boolean(b) => if *b { "True" } else { "False" }.to_owned(),
        Yaml::Array(a) => format!(
            "[{}]",
            a.iter().map(py_repr_yaml).collect::<Vec<_>>().join(", ")
        ),
        Yaml::Hash(h) => format!(
            "{{{}}}",
            h.iter()
                .map(|(k, v)| format!("{}: {}", py_repr_yaml(k), py_repr_yaml(v)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        Yaml::Null | Yaml::BadValue | Yaml::Alias(_) => "None".to_owned(),
    }
}

/// Python's `repr()` of a YAML value.
fn py_repr_yaml(y: &Yaml) -> String {
    match y {
        Yaml::String(s) => py_str(s),
        other => py_display(other),
    }
}

/// A YAML float (`.inf`, `-.inf`, `.nan` as YAML spells them).
fn real(r: &str) -> Option<f64> {
    match r.trim_start_matches('+') {
        ".inf" | ".Inf" | ".INF" => Some(f64::INFINITY),
        "-.inf" | "-.Inf" | "-.INF" => Some(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => Some(f64::NAN),
        other => other.replace('_', "").parse().ok(),
    }
}

fn fill_struct(
    schema: &Schema,
    type_name: &str,
    value: &mut Value,
    y: &Yaml,
) -> Result<(), FillError> {
    let s = schema.get(type_name)?;
    let Yaml::Hash(map) = y else {
        return Err(FillError::NotADictionary {
            value: py_display(y),
            found: py_type(y),
        });
    };
    let Value::Struct(fields) = value else {
        return Err(FillError::NotAStruct {
            type_name: type_name.to_owned(),
        });
    };
    let hidden = s.is_empty_placeholder();
    for (k, v) in map {
        let key = py_display(k);
        let index = s
            .members
            .iter()
            .position(|m| m.name == key)
            .filter(|_| !hidden)
            .ok_or_else(|| FillError::NoSuchField {
                type_name: s.name.clone(),
                field: key,
            })?;
        let member = &s.members[index];
        fields[index] = convert_member(schema, member, v)?;
    }
    Ok(())
}

fn convert_member(schema: &Schema, m: &Member, y: &Yaml) -> Result<Value, FillError> {
    match m.ty.container {
        Container::Single => {
            // rosidl_runtime_py's `set_message_fields` stores `field_type(value)`: in a string
            // field `str(value)`, whatever the value (a list or a dictionary too); in an
            // integer field `int(value)`, which cuts a float's fraction off.
            let converted;
            let y = match (&m.ty.elem, y) {
                (Elem::Str(_) | Elem::WStr(_), Yaml::Array(_) | Yaml::Hash(_)) => {
                    converted = Yaml::String(py_display(y));
                    &converted
                }
                (Elem::Int { .. }, Yaml::Real(r)) => match real(r) {
                    Some(f) if f.is_finite() && f.abs() < 1e18 => {
                        converted = Yaml::Integer(f.trunc() as i64);
                        &converted
                    }
                    _ => y,
                },
                _ => y,
            };
            convert_elem(schema, &m.ty.elem, y).map_err(|e| e.into_error(&m.name, &m.ty.elem))
        }
        Container::Array(_) | Container::Sequence(_) => {
            let wrong = || FillError::WrongContainer {
                field: m.name.clone(),
                expected: m.ty.clone(),
            };
            let Yaml::Array(items) = y else {
                return Err(wrong());
            };
            match m.ty.container {
                Container::Array(n) if items.len() != n => return Err(wrong()),
                Container::Sequence(Some(n)) if items.len() > n => return Err(wrong()),
                _ => {}
            }
            items
                .iter()
                .map(|item| match convert_elem(schema, &m.ty.elem, item) {
                    Ok(v) => Ok(v),
                    Err(ElemError::Nested(e)) => Err(e),
                    Err(_) => Err(wrong()),
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Value::List)
        }
    }
}

/// What rosidl's assertion message for arrays and sequences says a field of type `ty` must be.
fn container_requirement(ty: &FieldTy) -> String {
    let mut parts = vec!["a set or sequence".to_owned()];
    match ty.container {
        Container::Array(n) => parts.push(format!("with length {n}")),
        Container::Sequence(Some(n)) => parts.push(format!("with length <= {n}")),
        _ => {}
    }
    if let Elem::Str(Some(n)) | Elem::WStr(Some(n)) = ty.elem {
        parts.push(format!("and each string value not longer than {n}"));
    }
    parts.push(format!(
        "and each value of type '{}'",
        python_type(&ty.elem)
    ));
    match ty.elem {
        Elem::Int { bits, signed: true } => {
            let b = 1i128 << (bits - 1);
            parts.push(format!("and each integer in [{}, {}]", -b, b - 1));
        }
        Elem::Int {
            bits,
            signed: false,
        } => parts.push(format!(
            "and each unsigned integer in [0, {}]",
            (1i128 << bits) - 1
        )),
        Elem::F32 => parts.push(
            "and each float in [-340282346600000016151267322115014000640.000000, \
             340282346600000016151267322115014000640.000000]"
                .to_owned(),
        ),
        _ => {}
    }
    parts.join(" ")
}

/// What rclpy's setter says a field of element type `e` must be, given a value of another type.
fn type_requirement(e: &Elem) -> String {
    match e {
        Elem::Nested(n) => format!("a sub message of type '{}'", short_name(n)),
        Elem::Byte => "of type 'bytes' or 'ByteString' with length 1".to_owned(),
        Elem::Char => "of type 'str' or 'UserString' with length 1 and the character ord() in \
                       [-128, 127]"
            .to_owned(),
        other => format!("of type '{}'", python_type(other)),
    }
}

/// What rclpy's setter says a number of element type `e` must be, given one out of range.
fn range_requirement(e: &Elem) -> String {
    match e {
        Elem::Int { bits, signed: true } => {
            let b = 1i128 << (bits - 1);
            format!("an integer in [{}, {}]", -b, b - 1)
        }
        Elem::Int { bits, .. } => format!("an unsigned integer in [0, {}]", (1i128 << bits) - 1),
        _ => "a float in [-3.402823466e+38, 3.402823466e+38]".to_owned(),
    }
}

/// The Python type rclpy stores an element as.
fn python_type(e: &Elem) -> String {
    match e {
        Elem::Bool => "bool".to_owned(),
        Elem::Byte => "bytes".to_owned(),
        Elem::Char | Elem::WChar | Elem::Str(_) | Elem::WStr(_) => "str".to_owned(),
        Elem::Int { .. } => "int".to_owned(),
        Elem::F32 | Elem::F64 | Elem::LongDouble => "float".to_owned(),
        Elem::Nested(n) => n.rsplit('/').next().unwrap_or(n).to_owned(),
    }
}

enum ElemError {
    /// Not of the element's type.
    Type,
    /// Out of range.
    Range,
    /// A string too long.
    TooLong(u64),
    /// A string that Python's `int()` refuses.
    Int(String),
    /// A string that Python's `float()` refuses.
    Float(String),
    /// An error inside a nested message, already complete.
    Nested(FillError),
}

impl ElemError {
    /// The error of field `field` of element type `e`.
    fn into_error(self, field: &str, e: &Elem) -> FillError {
        let field = field.to_owned();
        match self {
            ElemError::Type => FillError::WrongType {
                field,
                expected: e.clone(),
            },
            ElemError::Range => FillError::OutOfRange {
                field,
                expected: e.clone(),
            },
            ElemError::TooLong(max) => FillError::TooLong { field, max },
            ElemError::Int(text) => FillError::InvalidInteger { field, text },
            ElemError::Float(text) => FillError::InvalidFloat { field, text },
            ElemError::Nested(e) => e,
        }
    }
}

fn convert_elem(schema: &Schema, e: &Elem, y: &Yaml) -> Result<Value, ElemError> {
    match e {
        Elem::Nested(n) => {
            let mut v = schema
                .default_value(n)
                .map_err(|e| ElemError::Nested(e.into()))?;
            fill_struct(schema, n, &mut v, y).map_err(ElemError::Nested)?;
            Ok(v)
        }
        Elem::Bool => match y {
            Yaml::Boolean(b) => Ok(Value::Bool(*b)),
            Yaml::Integer(i) => Ok(Value::Bool(*i != 0)),
            _ => Err(ElemError::Type),
        },
        Elem::Int { bits, signed } => {
            let i: i128 = match y {
                Yaml::Integer(i) => i128::from(*i),
                Yaml::Boolean(b) => i128::from(*b),
                Yaml::Real(r) => {
                    if let Ok(i) = r.replace('_', "").parse::<i128>() {
                        i
                    } else {
                        let f = real(r).ok_or(ElemError::Type)?;
                        if f.fract() != 0.0 || !f.is_finite() {
                            return Err(ElemError::Type);
                        }
                        f as i128
                    }
                }
                Yaml::String(s) => s
                    .trim()
                    .parse::<i128>()
                    .map_err(|_| ElemError::Int(s.clone()))?,
                _ => return Err(ElemError::Type),
            };
            let (lo, hi) = if *signed {
                (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
            } else {
                (0, (1i128 << bits) - 1)
            };
            if i < lo || i > hi {
                return Err(ElemError::Range);
            }
            Ok(Value::Int(i))
        }
        Elem::F32 | Elem::F64 | Elem::LongDouble => {
            let f = match y {
                Yaml::Integer(i) => *i as f64,
                Yaml::Real(r) => real(r).ok_or(ElemError::Type)?,
                Yaml::Boolean(b) => f64::from(u8::from(*b)),
                Yaml::String(s) => py_parse_float(s).ok_or_else(|| ElemError::Float(s.clone()))?,
                _ => return Err(ElemError::Type),
            };
            if *e == Elem::F32 && f.is_finite() && f.abs() > 3.402823466e+38 {
                return Err(ElemError::Range);
            }
            Ok(Value::Float(f))
        }
        Elem::Str(bound) | Elem::WStr(bound) => {
            let s = match y {
                Yaml::Hash(_) | Yaml::Array(_) => return Err(ElemError::Type),
                other => py_display(other),
            };
            if let Some(n) = bound {
                if s.chars().count() as u64 > *n {
                    return Err(ElemError::TooLong(*n));
                }
            }
            Ok(Value::Str(s))
        }
        Elem::Char | Elem::WChar => {
            // One character that CDR can carry: 8 bits for `char`, one UTF-16 unit for `wchar`
            // (as one character string or as its code).
            let limit = if *e == Elem::Char { 256 } else { 65536 };
            let c = match y {
                Yaml::String(s) => {
                    let mut chars = s.chars();
                    match (chars.next(), chars.next()) {
                        (Some(c), None) => Some(c),
                        _ => None,
                    }
                }
                Yaml::Integer(i) => u32::try_from(*i).ok().and_then(char::from_u32),
                _ => None,
            };
            c.filter(|c| u32::from(*c) < limit)
                .map(|c| Value::Str(c.to_string()))
                .ok_or(ElemError::Type)
        }
        Elem::Byte => match y {
            Yaml::Integer(i) => u8::try_from(*i)
                .map(Value::Byte)
                .map_err(|_| ElemError::Type),
            Yaml::String(s) if s.len() == 1 => Ok(Value::Byte(s.as_bytes()[0])),
            _ => Err(ElemError::Type),
        },
    }
}

/// Python `float(str)`.
fn py_parse_float(s: &str) -> Option<f64> {
    let t = s.trim().to_ascii_lowercase();
    match t.trim_start_matches(['+', '-']) {
        "inf" | "infinity" | "nan" => {
            let neg = t.starts_with('-');
            let v = if t.ends_with("nan") {
                f64::NAN
            } else {
                f64::INFINITY
            };
            Some(if neg { -v } else { v })
        }
        _ => t.replace('_', "").parse().ok(),
    }
}

/// A member's `.msg` default as rosidl writes it into descriptions (`False`, `0`, `1.5`, a raw
/// string, `[1, 2]`), as a value; `None` if it cannot be read.
pub(super) fn parse_default(schema: &Schema, m: &Member) -> Option<Value> {
    let text = m.default.trim();
    if let (Container::Single, Elem::Str(_) | Elem::WStr(_)) = (m.ty.container, &m.ty.elem) {
        return Some(Value::Str(unquote(text).to_owned()));
    }
    let text = if text.starts_with('(') && text.ends_with(')') {
        format!("[{}]", &text[1..text.len() - 1])
    } else {
        text.to_owned()
    };
    let doc = YamlLoader::load_from_str(&text).ok()?.into_iter().next()?;
    let doc = match doc {
        Yaml::String(s) if m.ty.container == Container::Single => {
            Yaml::String(unquote(&s).to_owned())
        }
        other => other,
    };
    convert_member(schema, m, &doc).ok()
}

fn unquote(s: &str) -> &str {
    for q in ['"', '\''] {
        if s.len() >= 2 && s.starts_with(q) && s.ends_with(q) {
            return &s[1..s.len() - 1];
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use std::error::Error as _;

    use super::*;
    use horus_ros_msgs::rcl_interfaces::srv::{SetParameters, SetParametersRequest};
    use horus_ros_msgs::{Message, Service};

    /// The error of filling a `SetParameters` request from `text`.
    fn fill_error(text: &str) -> FillError {
        let schema = Schema::from_description(&SetParameters::type_description()).expect("schema");
        fill_from_yaml(&schema, SetParametersRequest::TYPE_NAME, text).expect_err("refused")
    }

    #[test]
    fn errors_carry_the_field_and_show_rclpys_messages() {
        let e = fill_error("parameters: [{value: {type: 300}}]");
        assert_eq!(
            e,
            FillError::OutOfRange {
                field: "type".to_owned(),
                expected: Elem::Int {
                    bits: 8,
                    signed: false
                },
            }
        );
        assert_eq!(
            e.to_string(),
            "The 'type' field must be an unsigned integer in [0, 255]"
        );
        let e = fill_error("parameters: [{value: {byte_array_value: 3}}]");
        assert!(
            matches!(&e, FillError::WrongContainer { field, .. } if field == "byte_array_value"),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "The 'byte_array_value' field must be a set or sequence and each value of type 'bytes'"
        );
        let e = fill_error("parameters: [{value: 1}]");
        assert_eq!(
            e.to_string(),
            "Value '1' is expected to be a dictionary but is a int"
        );
        let e = fill_error("parameters: [{value: {double_value: x}}]");
        assert_eq!(e.to_string(), "could not convert string to float: 'x'");
        let e = fill_error("parameters: [{nme: a}]");
        assert_eq!(e.to_string(), "'Parameter' object has no attribute 'nme'");
        let e = fill_error("parameters: [{value: {bool_value: []}}]");
        assert_eq!(
            e.to_string(),
            "The 'bool_value' field must be of type 'bool'"
        );
    }

    /// The value at `path` (field indexes, list items taken as their first) of a
    /// `SetParameters` request filled from `text`.
    fn filled(text: &str, path: &[usize]) -> Value {
        let schema = Schema::from_description(&SetParameters::type_description()).expect("schema");
        let mut v = fill_from_yaml(&schema, SetParametersRequest::TYPE_NAME, text).expect("filled");
        for &i in path {
            v = match v {
                Value::Struct(mut fields) => fields.swap_remove(i),
                Value::List(mut items) => items.swap_remove(i),
                other => panic!("{other:?}"),
            };
        }
        v
    }

    #[test]
    fn scalar_fields_take_what_python_converts() {
        // `str(value)` in a string field (`parameters[0].name`), whatever the value.
        let name = |text: &str| filled(text, &[0, 0, 0]);
        assert_eq!(
            name("parameters: [{name: [1, a]}]"),
            Value::Str("[1, 'a']".into())
        );
        assert_eq!(
            name("parameters: [{name: {a: 1}}]"),
            Value::Str("{'a': 1}".into())
        );
        assert_eq!(
            name("parameters: [{name: true}]"),
            Value::Str("True".into())
        );
        // `int(value)` in an integer field (`parameters[0].value.type`): `int(2.9)` is 2.
        let kind = |text: &str| filled(text, &[0, 0, 1, 0]);
        assert_eq!(kind("parameters: [{value: {type: 2.9}}]"), Value::Int(2));
        let e = fill_error("parameters: [{value: {type: -2.9}}]");
        assert!(matches!(e, FillError::OutOfRange { .. }), "{e:?}");
        // In a sequence, each element must be of the element's type.
        let e = fill_error("parameters: [{value: {string_array_value: [[1]]}}]");
        assert!(matches!(e, FillError::WrongContainer { .. }), "{e:?}");
        let e = fill_error("parameters: [{value: {integer_array_value: [1.5]}}]");
        assert!(matches!(e, FillError::WrongContainer { .. }), "{e:?}");
    }

    #[test]
    fn invalid_yaml_keeps_the_scanner_error_and_shows_it_once() {
        let e = fill_error("{a: [");
        let FillError::Yaml { cause } = &e else {
            panic!("{e:?}")
        };
        // The typed cause is kept; the message shows it, so `source()` does not repeat it.
        assert_eq!(e.to_string(), format!("invalid YAML: {cause}"));
        assert!(e.source().is_none());
    }
}
