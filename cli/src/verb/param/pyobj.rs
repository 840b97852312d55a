//! The Python side of ros2param's values: PyYAML's `yaml.safe_load` (YAML 1.1 implicit
//! resolvers, `yaml/resolver.py` and `yaml/constructor.py` of PyYAML 6.0), Python's `str()` and
//! `repr()` of what it loads, and rclpy (jazzy, 7.1) `rclpy.parameter.get_parameter_value` /
//! `parameter_value_to_python`, which `param set` and `param load` type values with.

use std::collections::HashMap;
use std::sync::OnceLock;

use horus_ros_dynamic::repr::{py_bytes, py_float, py_str};
use horus_ros_msgs::rcl_interfaces::msg::{ParameterType, ParameterValue};
use regex::Regex;
use yaml_rust2::parser::{Event, Parser, Tag};
use yaml_rust2::scanner::TScalarStyle;

/// A Python object as `yaml.safe_load` builds it.
#[derive(Clone, Debug, PartialEq)]
pub enum PyObj {
    /// `None`.
    None,
    /// `bool`.
    Bool(bool),
    /// `int` (PyYAML's are unbounded; beyond `i128` they are kept as their text).
    Int(i128),
    /// `float`.
    Float(f64),
    /// `str`.
    Str(String),
    /// `datetime.date` / `datetime.datetime`: the scalar's text.
    Timestamp(String),
    /// `list`.
    List(Vec<PyObj>),
    /// `dict`, in insertion order (a repeated key keeps its first place and takes the last value,
    /// as a Python `dict`).
    Dict(Vec<(PyObj, PyObj)>),
}

/// Why a YAML text could not be loaded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct LoadError(pub String);

/// A node under construction.
enum Open {
    List(Vec<PyObj>, usize),
    Dict(Vec<(PyObj, PyObj)>, Option<PyObj>, usize),
}

/// `yaml.safe_load(text)`: the first document (`None` for an empty stream).
pub fn safe_load(text: &str) -> Result<PyObj, LoadError> {
    let mut parser = Parser::new_from_str(text);
    let mut stack: Vec<Open> = Vec::new();
    let mut anchors: HashMap<usize, PyObj> = HashMap::new();
    let mut documents = 0usize;
    let mut root: Option<PyObj> = None;
    loop {
        let (event, _) = parser.next_token().map_err(|e| LoadError(e.to_string()))?;
        let done = match event {
            Event::StreamEnd => break,
            Event::DocumentStart => {
                documents += 1;
                if documents > 1 {
                    // PyYAML's `get_single_node`.
                    return Err(LoadError(
                        "expected a single document in the stream".to_owned(),
                    ));
                }
                None
            }
            Event::Scalar(value, style, anchor, tag) => {
                let obj = scalar(value, style, tag.as_ref());
                if anchor > 0 {
                    anchors.insert(anchor, obj.clone());
                }
                Some(obj)
            }
            Event::Alias(id) => Some(
                anchors
                    .get(&id)
                    .cloned()
                    .ok_or_else(|| LoadError("found undefined alias".to_owned()))?,
            ),
            Event::SequenceStart(anchor, _) => {
                stack.push(Open::List(Vec::new(), anchor));
                None
            }
            Event::MappingStart(anchor, _) => {
                stack.push(Open::Dict(Vec::new(), None, anchor));
                None
            }
            Event::SequenceEnd | Event::MappingEnd => match stack.pop() {
                Some(Open::List(items, anchor)) => {
                    let obj = PyObj::List(items);
                    if anchor > 0 {
                        anchors.insert(anchor, obj.clone());
                    }
                    Some(obj)
                }
                Some(Open::Dict(items, _, anchor)) => {
                    let obj = PyObj::Dict(items);
                    if anchor > 0 {
                        anchors.insert(anchor, obj.clone());
                    }
                    Some(obj)
                }
                None => None,
            },
            _ => None,
        };
        let Some(obj) = done else { continue };
        match stack.last_mut() {
            None => root = Some(obj),
            Some(Open::List(items, _)) => items.push(obj),
            Some(Open::Dict(items, key, _)) => match key.take() {
                None => {
                    if matches!(obj, PyObj::List(_) | PyObj::Dict(_)) {
                        return Err(LoadError(
                            "while constructing a mapping found unhashable key".to_owned(),
                        ));
                    }
                    *key = Some(obj);
                }
                Some(k) => match items.iter_mut().find(|(existing, _)| *existing == k) {
                    Some(entry) => entry.1 = obj,
                    None => items.push((k, obj)),
                },
            },
        }
    }
    Ok(root.unwrap_or(PyObj::None))
}

/// PyYAML's implicit resolvers (`resolver.py`), in the order they are tried.
struct Resolvers {
    bool_: Regex,
    float: Regex,
    int: Regex,
    null: Regex,
    timestamp: Regex,
}

fn resolvers() -> &'static Resolvers {
    static R: OnceLock<Resolvers> = OnceLock::new();
    R.get_or_init(|| {
        let re = |s: &str| Regex::new(s).expect("a valid resolver pattern");
        Resolvers {
            bool_: re("^(?:yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF)$"),
            float: re(r"^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+][0-9]+)?|\.[0-9][0-9_]*(?:[eE][-+][0-9]+)?|[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\.[0-9_]*|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"),
            int: re(r"^(?:[-+]?0b[0-1_]+|[-+]?0[0-7_]+|[-+]?(?:0|[1-9][0-9_]*)|[-+]?0x[0-9a-fA-F_]+|[-+]?[1-9][0-9_]*(?::[0-5]?[0-9])+)$"),
            null: re("^(?:~|null|Null|NULL|)$"),
            timestamp: re(r"^(?:[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]|[0-9][0-9][0-9][0-9]-[0-9][0-9]?-[0-9][0-9]?(?:[Tt]|[ \t]+)[0-9][0-9]?:[0-9][0-9]:[0-9][0-9](?:\.[0-9]*)?(?:[ \t]*(?:Z|[-+][0-9][0-9]?(?::[0-9][0-9])?))?)$"),
        }
    })
}

/// A scalar as PyYAML's safe constructor builds it: quoted scalars are strings, plain ones are
/// resolved; an explicit `!!str` tag makes a string.
fn scalar(value: String, style: TScalarStyle, tag: Option<&Tag>) -> PyObj {
    if let Some(tag) = tag {
        match tag.suffix.as_str() {
            "str" | "tag:yaml.org,2002:str" => return PyObj::Str(value),
            "int" | "tag:yaml.org,2002:int" => return construct_int(&value),
            "float" | "tag:yaml.org,2002:float" => return construct_float(&value),
            "bool" | "tag:yaml.org,2002:bool" => return construct_bool(&value),
            "null" | "tag:yaml.org,2002:null" => return PyObj::None,
            _ => {}
        }
    }
    if style != TScalarStyle::Plain {
        return PyObj::Str(value);
    }
    resolve_plain(value)
}

/// The object a plain scalar resolves to.
pub fn resolve_plain(value: String) -> PyObj {
    let r = resolvers();
    if r.bool_.is_match(&value) {
        construct_bool(&value)
    } else if r.float.is_match(&value) {
        construct_float(&value)
    } else if r.int.is_match(&value) {
        construct_int(&value)
    } else if r.null.is_match(&value) {
        PyObj::None
    } else if r.timestamp.is_match(&value) {
        PyObj::Timestamp(value)
    } else {
        PyObj::Str(value)
    }
}

/// `construct_yaml_bool`.
fn construct_bool(value: &str) -> PyObj {
    PyObj::Bool(matches!(
        value.to_ascii_lowercase().as_str(),
        "yes" | "true" | "on"
    ))
}

/// `construct_yaml_int`.
fn construct_int(value: &str) -> PyObj {
    let v = value.replace('_', "");
    let (sign, v) = match v.strip_prefix('-') {
        Some(rest) => (-1i128, rest.to_owned()),
        None => (1, v.strip_prefix('+').unwrap_or(&v).to_owned()),
    };
    let parsed = if v == "0" {
        Some(0)
    } else if let Some(b) = v.strip_prefix("0b") {
        i128::from_str_radix(b, 2).ok()
    } else if let Some(h) = v.strip_prefix("0x") {
        i128::from_str_radix(h, 16).ok()
    } else if let Some(o) = v.strip_prefix('0') {
        i128::from_str_radix(o, 8).ok()
    } else if v.contains(':') {
        v.split(':').try_fold(0i128, |acc, d| {
            d.parse::<i128>()
                .ok()
                .and_then(|d| acc.checked_mul(60)?.checked_add(d))
        })
    } else {
        v.parse::<i128>().ok()
    };
    match parsed {
        Some(n) => PyObj::Int(sign * n),
        None => PyObj::Str(value.to_owned()),
    }
}

/// `construct_yaml_float`.
fn construct_float(value: &str) -> PyObj {
    let v = value.replace('_', "").to_ascii_lowercase();
    let (sign, v) = match v.strip_prefix('-') {
        Some(rest) => (-1.0, rest.to_owned()),
        None => (1.0, v.strip_prefix('+').unwrap_or(&v).to_owned()),
    };
    let f = if v == ".inf" {
        f64::INFINITY
    } else if v == ".nan" {
        f64::NAN
    } else if v.contains(':') {
        v.split(':')
            .fold(0.0, |acc, d| acc * 60.0 + d.parse::<f64>().unwrap_or(0.0))
    } else {
        // Python's float() takes "1.", ".5" and "1.e5" alike; Rust's parse needs digits around
        // the dot only for the exponent form.
        let fixed = v.replace(".e", ".0e");
        fixed.parse::<f64>().unwrap_or(f64::NAN)
    };
    PyObj::Float(sign * f)
}

/// Python's `repr()` of a loaded object.
pub fn py_repr(obj: &PyObj) -> String {
    match obj {
        PyObj::Str(s) => py_str(s),
        PyObj::Timestamp(t) => format!("datetime.date({t})"),
        other => py_display(other),
    }
}

/// Python's `str()` of a loaded object.
pub fn py_display(obj: &PyObj) -> String {
    match obj {
        PyObj::None => "None".to_owned(),
        PyObj::Bool(true) => "True".to_owned(),
        PyObj::Bool(false) => "False".to_owned(),
        PyObj::Int(n) => n.to_string(),
        PyObj::Float(f) => py_float(*f),
        PyObj::Str(s) | PyObj::Timestamp(s) => s.clone(),
        PyObj::List(items) => {
            let items: Vec<String> = items.iter().map(py_repr).collect();
            format!("[{}]", items.join(", "))
        }
        PyObj::Dict(items) => {
            let items: Vec<String> = items
                .iter()
                .map(|(k, v)| format!("{}: {}", py_repr(k), py_repr(v)))
                .collect();
            format!("{{{}}}", items.join(", "))
        }
    }
}

/// Why a value cannot be made a `ParameterValue` (rclpy's field setters refuse it).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ValueError {
    /// An integer beyond int64.
    #[error("The '{0}' field must be an integer in [-9223372036854775808, 9223372036854775807]")]
    IntegerRange(&'static str),
}

/// rclpy `get_parameter_value(string_value)`: the value `yaml.safe_load` gives the text, typed
/// (a text YAML cannot parse, or a value that is no parameter type, stays the string itself).
pub fn get_parameter_value(string_value: &str) -> Result<ParameterValue, ValueError> {
    let yaml_value = safe_load(string_value).unwrap_or_else(|_| PyObj::Str(string_value.into()));
    let mut value = ParameterValue::default();
    let int64 = |n: i128, field| i64::try_from(n).map_err(|_| ValueError::IntegerRange(field));
    match yaml_value {
        PyObj::Bool(b) => {
            value.r#type = ParameterType::PARAMETER_BOOL;
            value.bool_value = b;
        }
        PyObj::Int(n) => {
            value.r#type = ParameterType::PARAMETER_INTEGER;
            value.integer_value = int64(n, "integer_value")?;
        }
        PyObj::Float(f) => {
            value.r#type = ParameterType::PARAMETER_DOUBLE;
            value.double_value = f;
        }
        PyObj::List(items) => {
            // Python's bool is an int: `all(isinstance(v, int))` holds for bools too.
            let all = |f: fn(&PyObj) -> bool| items.iter().all(f);
            if all(|v| matches!(v, PyObj::Bool(_))) {
                value.r#type = ParameterType::PARAMETER_BOOL_ARRAY;
                value.bool_array_value = items
                    .iter()
                    .map(|v| matches!(v, PyObj::Bool(true)))
                    .collect();
            } else if all(|v| matches!(v, PyObj::Int(_) | PyObj::Bool(_))) {
                value.r#type = ParameterType::PARAMETER_INTEGER_ARRAY;
                value.integer_array_value = items
                    .iter()
                    .map(|v| match v {
                        PyObj::Int(n) => int64(*n, "integer_array_value"),
                        PyObj::Bool(b) => Ok(i64::from(*b)),
                        _ => Ok(0),
                    })
                    .collect::<Result<_, _>>()?;
            } else if all(|v| matches!(v, PyObj::Float(_))) {
                value.r#type = ParameterType::PARAMETER_DOUBLE_ARRAY;
                value.double_array_value = items
                    .iter()
                    .map(|v| match v {
                        PyObj::Float(f) => *f,
                        _ => 0.0,
                    })
                    .collect();
            } else if all(|v| matches!(v, PyObj::Str(_))) {
                value.r#type = ParameterType::PARAMETER_STRING_ARRAY;
                value.string_array_value = items
                    .into_iter()
                    .map(|v| match v {
                        PyObj::Str(s) => s,
                        _ => String::new(),
                    })
                    .collect();
            } else {
                value.r#type = ParameterType::PARAMETER_STRING;
                value.string_value = string_value.to_owned();
            }
        }
        PyObj::Str(s) => {
            value.r#type = ParameterType::PARAMETER_STRING;
            value.string_value = s;
        }
        // None keeps the text; a mapping or a date would fail rclpy's string setter: the text.
        PyObj::None | PyObj::Dict(_) | PyObj::Timestamp(_) => {
            value.r#type = ParameterType::PARAMETER_STRING;
            value.string_value = string_value.to_owned();
        }
    }
    Ok(value)
}

/// What ros2param prints after a value's label in `param get` (Python's `str()` of rclpy's
/// field: `bytes` objects for a byte array, lists for the others); `None` for NOT_SET; `Err` with
/// the type for an unknown type.
pub fn get_display(v: &ParameterValue) -> Result<Option<String>, u8> {
    let list = |items: Vec<String>| format!("[{}]", items.join(", "));
    let py_bool = |b: bool| if b { "True" } else { "False" }.to_owned();
    Ok(Some(match v.r#type {
        ParameterType::PARAMETER_BOOL => py_bool(v.bool_value),
        ParameterType::PARAMETER_INTEGER => v.integer_value.to_string(),
        ParameterType::PARAMETER_DOUBLE => py_float(v.double_value),
        ParameterType::PARAMETER_STRING => v.string_value.clone(),
        ParameterType::PARAMETER_BYTE_ARRAY => list(
            v.byte_array_value
                .iter()
                .map(|b| py_bytes(&[u8::from(*b)]))
                .collect(),
        ),
        ParameterType::PARAMETER_BOOL_ARRAY => {
            list(v.bool_array_value.iter().map(|b| py_bool(*b)).collect())
        }
        ParameterType::PARAMETER_INTEGER_ARRAY => list(
            v.integer_array_value
                .iter()
                .map(ToString::to_string)
                .collect(),
        ),
        ParameterType::PARAMETER_DOUBLE_ARRAY => {
            list(v.double_array_value.iter().map(|f| py_float(*f)).collect())
        }
        ParameterType::PARAMETER_STRING_ARRAY => {
            list(v.string_array_value.iter().map(|s| py_str(s)).collect())
        }
        ParameterType::PARAMETER_NOT_SET => return Ok(None),
        other => return Err(other),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn typed(s: &str) -> (u8, String) {
        let v = get_parameter_value(s).expect("a value");
        (
            v.r#type,
            get_display(&v).expect("known").unwrap_or_default(),
        )
    }

    #[test]
    fn values_are_typed_as_rclpy_types_them() {
        use ParameterType as T;
        assert_eq!(typed("5"), (T::PARAMETER_INTEGER, "5".into()));
        assert_eq!(typed("0x1f"), (T::PARAMETER_INTEGER, "31".into()));
        assert_eq!(typed("010"), (T::PARAMETER_INTEGER, "8".into()));
        assert_eq!(typed("1_000"), (T::PARAMETER_INTEGER, "1000".into()));
        assert_eq!(typed("1:30"), (T::PARAMETER_INTEGER, "90".into()));
        assert_eq!(typed("1.5"), (T::PARAMETER_DOUBLE, "1.5".into()));
        assert_eq!(typed("1e5"), (T::PARAMETER_STRING, "1e5".into()));
        assert_eq!(typed("1.0e+5"), (T::PARAMETER_DOUBLE, "100000.0".into()));
        assert_eq!(typed(".inf"), (T::PARAMETER_DOUBLE, "inf".into()));
        assert_eq!(typed("inf"), (T::PARAMETER_STRING, "inf".into()));
        assert_eq!(typed("yes"), (T::PARAMETER_BOOL, "True".into()));
        assert_eq!(typed("Off"), (T::PARAMETER_BOOL, "False".into()));
        assert_eq!(typed("y"), (T::PARAMETER_STRING, "y".into()));
        assert_eq!(typed("'5'"), (T::PARAMETER_STRING, "5".into()));
        assert_eq!(typed(""), (T::PARAMETER_STRING, "".into()));
        assert_eq!(typed("null"), (T::PARAMETER_STRING, "null".into()));
        assert_eq!(
            typed("[1, 2]"),
            (T::PARAMETER_INTEGER_ARRAY, "[1, 2]".into())
        );
        assert_eq!(
            typed("[true, 1]"),
            (T::PARAMETER_INTEGER_ARRAY, "[1, 1]".into())
        );
        assert_eq!(typed("[]"), (T::PARAMETER_BOOL_ARRAY, "[]".into()));
        assert_eq!(
            typed("[a, 'b']"),
            (T::PARAMETER_STRING_ARRAY, "['a', 'b']".into())
        );
        assert_eq!(typed("[1, a]"), (T::PARAMETER_STRING, "[1, a]".into()));
        assert_eq!(typed("{a: 1}"), (T::PARAMETER_STRING, "{a: 1}".into()));
        assert_eq!(typed("[1.0, 2.5]").0, T::PARAMETER_DOUBLE_ARRAY);
    }

    #[test]
    fn python_str_of_loaded_values() {
        let v = safe_load("{a: [1, 'x', true, ~, 1.0e-5], b: 2}").expect("yaml");
        let PyObj::Dict(items) = v else {
            panic!("a dict")
        };
        assert_eq!(py_display(&items[0].1), "[1, 'x', True, None, 1e-05]");
        assert_eq!(py_display(&PyObj::Float(1e16)), "1e+16");
    }
}
