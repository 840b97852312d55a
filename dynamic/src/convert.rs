//! rosidl_runtime_py (jazzy `convert.py`) over dynamic values: `message_to_ordereddict` (what
//! `ros2 service echo` dumps as YAML) and `message_to_csv`, with their `truncate_length`,
//! `no_arr` and `no_str` options.
//!
//! Python values are as rclpy stores fields: numeric fixed arrays as numpy arrays, numeric
//! sequences as `array.array`, other arrays and sequences as lists, `byte` as a one-byte `bytes`,
//! `char` as a one-character `str`.

use super::pyyaml::PyValue;
use super::repr::{py_bytes, py_float, py_float32_numpy};
use super::{Container, Elem, FieldTy, Schema, Value};

/// The options `ros2 service echo` / `ros2 topic echo` pass on.
#[derive(Clone, Copy, Debug, Default)]
pub struct ConvertOptions {
    /// `--truncate-length` (`None` with `--full-length`).
    pub truncate_length: Option<usize>,
    /// `--no-arr`.
    pub no_arr: bool,
    /// `--no-str`.
    pub no_str: bool,
}

/// rosidl_runtime_py `__get_type_name` of an element type.
fn type_name(e: &Elem) -> String {
    match e {
        Elem::Bool => "boolean".to_owned(),
        Elem::Byte => "octet".to_owned(),
        Elem::Char => "char".to_owned(),
        Elem::WChar => "wchar".to_owned(),
        Elem::Int { bits, signed } => format!("{}int{bits}", if *signed { "" } else { "u" }),
        Elem::F32 => "float".to_owned(),
        Elem::F64 => "double".to_owned(),
        Elem::LongDouble => "long double".to_owned(),
        Elem::Str(_) => "string".to_owned(),
        Elem::WStr(_) => "wstring".to_owned(),
        Elem::Nested(n) => n.clone(),
    }
}

/// rosidl_runtime_py `__abbreviate_array_info`.
fn abbreviate(ty: &FieldTy, len: usize) -> String {
    let t = type_name(&ty.elem);
    match ty.container {
        Container::Array(n) => format!("<array type: {t}[{n}]>"),
        Container::Sequence(Some(max)) => {
            format!("<sequence type: {t}[{max}], length: {len}>")
        }
        Container::Sequence(None) => format!("<sequence type: {t}, length: {len}>"),
        Container::Single => "unknown".to_owned(),
    }
}

fn truncate_str(s: &str, limit: Option<usize>) -> String {
    match limit {
        Some(n) if s.chars().count() > n => {
            let mut t: String = s.chars().take(n).collect();
            t.push_str("...");
            t
        }
        _ => s.to_owned(),
    }
}

/// `message_to_ordereddict` of a struct value of type `type_name`.
pub fn to_ordereddict(schema: &Schema, type_name: &str, v: &Value, o: ConvertOptions) -> PyValue {
    let (Ok(s), Value::Struct(fields)) = (schema.get(type_name), v) else {
        return PyValue::Map(Vec::new());
    };
    // rclpy hides rosidl's placeholder member of an empty struct: `OrderedDict()`.
    if s.is_empty_placeholder() {
        return PyValue::Map(Vec::new());
    }
    let mut out = Vec::with_capacity(fields.len());
    for (m, f) in s.members.iter().zip(fields) {
        let value = match (m.ty.container, f) {
            (Container::Single, f) => elem_value(schema, &m.ty.elem, f, o),
            (_, Value::List(items)) => {
                if o.no_arr {
                    PyValue::Str(abbreviate(&m.ty, items.len()))
                } else {
                    list_value(schema, &m.ty.elem, items, o)
                }
            }
            (_, f) => elem_value(schema, &m.ty.elem, f, o),
        };
        out.push((m.name.clone(), value));
    }
    PyValue::Map(out)
}

/// A list field: truncated to `truncate_length` items (then `'...'`), each item converted.
fn list_value(schema: &Schema, e: &Elem, items: &[Value], o: ConvertOptions) -> PyValue {
    let limit = o.truncate_length.filter(|n| items.len() > *n);
    let shown = limit.map_or(items, |n| &items[..n]);
    let mut out: Vec<PyValue> = shown.iter().map(|i| elem_value(schema, e, i, o)).collect();
    if limit.is_some() {
        out.push(PyValue::Str("...".to_owned()));
    }
    PyValue::List(out)
}

fn elem_value(schema: &Schema, e: &Elem, v: &Value, o: ConvertOptions) -> PyValue {
    match (e, v) {
        (Elem::Nested(n), v) => to_ordereddict(schema, n, v, o),
        (_, Value::Bool(b)) => PyValue::Bool(*b),
        (_, Value::Int(i)) => PyValue::Int(*i),
        (_, Value::Float(f)) => PyValue::Float(*f),
        (_, Value::Str(s)) => {
            if o.no_str {
                PyValue::Str(format!("<string length: <{}>>", s.chars().count()))
            } else {
                PyValue::Str(truncate_str(s, o.truncate_length))
            }
        }
        // `bytes`: `''.join(chr(c) for c in value)`.
        (_, Value::Byte(b)) => PyValue::Str(char::from(*b).to_string()),
        (_, Value::List(items)) => list_value(schema, e, items, o),
        (_, Value::Struct(_)) => PyValue::Map(Vec::new()),
    }
}

/// `message_to_csv` of a struct value of type `type_name`.
pub fn to_csv(schema: &Schema, type_name: &str, v: &Value, o: ConvertOptions) -> String {
    let (Ok(s), Value::Struct(fields)) = (schema.get(type_name), v) else {
        return String::new();
    };
    if s.is_empty_placeholder() {
        return String::new();
    }
    let mut out = String::new();
    for (m, f) in s.members.iter().zip(fields) {
        // `if result: result += ','`: no separator after empty leading values.
        if !out.is_empty() {
            out.push(',');
        }
        match (m.ty.container, f) {
            (Container::Single, f) => out.push_str(&csv_scalar(schema, &m.ty.elem, f, false, o)),
            (container, Value::List(items)) => {
                if o.no_arr {
                    out.push_str(&abbreviate(&m.ty, items.len()));
                    continue;
                }
                // numpy holds fixed numeric arrays: float32 items print as numpy's float32.
                let numpy32 = matches!(container, Container::Array(_));
                let mut r = String::new();
                for (j, item) in items.iter().enumerate() {
                    if !r.is_empty() {
                        r.push(',');
                    }
                    if o.truncate_length.is_some_and(|n| j >= n) {
                        r.push_str("...");
                        break;
                    }
                    r.push_str(&csv_scalar(schema, &m.ty.elem, item, numpy32, o));
                }
                out.push_str(&r);
            }
            (_, f) => out.push_str(&csv_scalar(schema, &m.ty.elem, f, false, o)),
        }
    }
    out
}

/// `to_string` of one value in `message_to_csv`: Python `str()` after the string options.
fn csv_scalar(schema: &Schema, e: &Elem, v: &Value, numpy32: bool, o: ConvertOptions) -> String {
    match (e, v) {
        (Elem::Nested(n), v) => to_csv(schema, n, v, o),
        (_, Value::Bool(b)) => (if *b { "True" } else { "False" }).to_owned(),
        (_, Value::Int(i)) => i.to_string(),
        (Elem::F32, Value::Float(f)) if numpy32 => py_float32_numpy(*f as f32),
        (_, Value::Float(f)) => py_float(*f),
        (_, Value::Str(s)) => {
            if o.no_str {
                format!("<string length: <{}>>", s.chars().count())
            } else {
                truncate_str(s, o.truncate_length)
            }
        }
        (_, Value::Byte(b)) => match o.truncate_length {
            // A one-byte `bytes` is truncated only with a limit of 0 (`b'...'` appended).
            Some(0) => "b'...'".to_owned(),
            _ => py_bytes(&[*b]),
        },
        (_, Value::List(items)) => items
            .iter()
            .map(|i| csv_scalar(schema, e, i, numpy32, o))
            .collect::<Vec<_>>()
            .join(","),
        (_, Value::Struct(_)) => String::new(),
    }
}
