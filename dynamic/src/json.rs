//! Dynamic messages as JSON: a message as a JSON object of its fields (integers as numbers,
//! floats as numbers or `null` when not finite, strings, booleans, `byte`s as numbers, arrays and
//! sequences as arrays, nested messages as objects), and a message filled from JSON as from
//! ros2cli's YAML — JSON is YAML's flow syntax, so [`fill_from_json`] is
//! [`fill_from_yaml`](crate::yaml::fill_from_yaml) on the JSON text, with the same checks and
//! errors.

use serde_json::{json, Map, Value as Json};

use crate::{Container, Elem, Schema, Value};

/// The message `value` of type `type_name` as a JSON object of its fields; `null` if `value` is
/// not a `type_name` (a value not made for this schema).
pub fn to_json(schema: &Schema, type_name: &str, value: &Value) -> Json {
    let (Ok(s), Value::Struct(fields)) = (schema.get(type_name), value) else {
        return Json::Null;
    };
    let mut map = Map::new();
    // Python hides rosidl's placeholder member of an empty struct.
    if s.is_empty_placeholder() {
        return Json::Object(map);
    }
    for (m, f) in s.members.iter().zip(fields) {
        let value = match (m.ty.container, f) {
            (Container::Single, f) => elem_json(schema, &m.ty.elem, f),
            (_, Value::List(items)) => Json::Array(
                items
                    .iter()
                    .map(|i| elem_json(schema, &m.ty.elem, i))
                    .collect(),
            ),
            (_, f) => elem_json(schema, &m.ty.elem, f),
        };
        map.insert(m.name.clone(), value);
    }
    Json::Object(map)
}

fn elem_json(schema: &Schema, e: &Elem, v: &Value) -> Json {
    match (e, v) {
        (Elem::Nested(n), v) => to_json(schema, n, v),
        (_, Value::Bool(b)) => json!(b),
        (_, Value::Int(i)) => i64::try_from(*i)
            .map(Json::from)
            .or_else(|_| u64::try_from(*i).map(Json::from))
            .unwrap_or_else(|_| json!(i.to_string())),
        (_, Value::Float(f)) => serde_json::Number::from_f64(*f).map_or(Json::Null, Json::Number),
        (_, Value::Str(s)) => json!(s),
        (_, Value::Byte(b)) => json!(b),
        (_, Value::List(items)) => {
            Json::Array(items.iter().map(|i| elem_json(schema, e, i)).collect())
        }
        (_, Value::Struct(_)) => Json::Null,
    }
}

/// A message of type `type_name` filled from `json` as `service call` fills one from YAML
/// (fields not given keep their defaults).
pub fn fill_from_json(
    schema: &Schema,
    type_name: &str,
    json: &Json,
) -> Result<Value, crate::yaml::FillError> {
    crate::yaml::fill_from_yaml(schema, type_name, &json.to_string())
}
