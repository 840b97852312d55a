//! What `topic pub` needs besides its loop: the time stamps ros2cli fills at each publication
//! ([`Stamps`], rosidl_runtime_py jazzy `set_message_fields` with `expand_header_auto` and
//! `expand_time_now`). Its QoS options are [`super::qos::QosArgs`], its message type a
//! [`super::message_type::MessageType`].

use std::time::{SystemTime, UNIX_EPOCH};

use yaml_rust2::Yaml;

use crate::dynamic::{Container, Elem, Schema, Value};

/// The time fields ros2cli sets to the current time at each publication: a `std_msgs/Header`
/// given as `auto` (its `stamp`) and a `builtin_interfaces/Time` given as `now`, found by
/// [`Stamps::take`]. Each is a path of indices from the message to the `Time` value (a struct's
/// field, or a sequence's element).
#[derive(Debug, Default)]
pub struct Stamps(Vec<Vec<usize>>);

const HEADER: &str = "std_msgs/msg/Header";
const TIME: &str = "builtin_interfaces/msg/Time";

impl Stamps {
    /// Takes out of `doc` (values for a message of type `type_name`) the `auto` headers and
    /// `now` times, as rosidl_runtime_py's `set_message_fields(…, expand_header_auto=True,
    /// expand_time_now=True)` does: those fields keep their defaults and are stamped at each
    /// publication. Values of any other shape are left for the filling to judge.
    pub fn take(schema: &Schema, type_name: &str, doc: &mut Yaml) -> Self {
        let mut stamps = Self::default();
        stamps.walk(schema, type_name, doc, &mut Vec::new());
        stamps
    }

    /// Whether there is no field to stamp.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    fn walk(&mut self, schema: &Schema, type_name: &str, doc: &mut Yaml, path: &mut Vec<usize>) {
        let (Ok(s), Yaml::Hash(map)) = (schema.get(type_name), doc) else {
            return;
        };
        let keys: Vec<Yaml> = map.keys().cloned().collect();
        for key in keys {
            let Yaml::String(field) = &key else { continue };
            let Some(index) = s.members.iter().position(|m| &m.name == field) else {
                continue;
            };
            let member = &s.members[index];
            let Elem::Nested(nested) = &member.ty.elem else {
                continue;
            };
            let Some(value) = map.get_mut(&key) else {
                continue;
            };
            path.push(index);
            match (member.ty.container, value) {
                (Container::Single, Yaml::String(v)) if nested == HEADER && v == "auto" => {
                    if let Some(stamp) = header_stamp(schema) {
                        let mut p = path.clone();
                        p.push(stamp);
                        self.0.push(p);
                        map.remove(&key);
                    }
                }
                (Container::Single, Yaml::String(v))
                    if nested == TIME && v == "now" && is_time(schema) =>
                {
                    self.0.push(path.clone());
                    map.remove(&key);
                }
                (Container::Single, value @ Yaml::Hash(_)) => {
                    self.walk(schema, nested, value, path);
                }
                (Container::Array(_) | Container::Sequence(_), Yaml::Array(items)) => {
                    for (i, item) in items.iter_mut().enumerate() {
                        path.push(i);
                        self.walk(schema, nested, item, path);
                        path.pop();
                    }
                }
                _ => {}
            }
            path.pop();
        }
    }

    /// Sets every stamped field of `message` to `now` (rclpy's `Clock().now().to_msg()`: the
    /// system time, in whole seconds and nanoseconds).
    pub fn apply(&self, message: &mut Value, now: SystemTime) {
        let since = now.duration_since(UNIX_EPOCH).unwrap_or_default();
        let time = Value::Struct(vec![
            Value::Int(i128::from(since.as_secs())),
            Value::Int(i128::from(since.subsec_nanos())),
        ]);
        for path in &self.0 {
            if let Some(at) = at_path(message, path) {
                *at = time.clone();
            }
        }
    }
}

/// The value at `path` (field or element indices) inside `value`.
fn at_path<'a>(value: &'a mut Value, path: &[usize]) -> Option<&'a mut Value> {
    let Some((first, rest)) = path.split_first() else {
        return Some(value);
    };
    match value {
        Value::Struct(items) | Value::List(items) => at_path(items.get_mut(*first)?, rest),
        _ => None,
    }
}

/// The index of `stamp` in `std_msgs/msg/Header`, when it is a `builtin_interfaces/msg/Time`.
fn header_stamp(schema: &Schema) -> Option<usize> {
    let header = schema.get(HEADER).ok()?;
    let index = header.members.iter().position(|m| m.name == "stamp")?;
    let m = &header.members[index];
    (m.ty.container == Container::Single
        && m.ty.elem == Elem::Nested(TIME.to_owned())
        && is_time(schema))
    .then_some(index)
}

/// Whether `builtin_interfaces/msg/Time` is `int32 sec, uint32 nanosec`, as [`Stamps::apply`]
/// writes it.
fn is_time(schema: &Schema) -> bool {
    schema.get(TIME).is_ok_and(|t| {
        t.members
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>()
            == ["sec", "nanosec"]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamic::{repr, yaml};
    use crate::verb::topic::message_type::MessageType;
    use std::time::Duration;

    fn header_type() -> MessageType {
        MessageType::installed("std_msgs/msg/Header", crate::CliError::new)
            .expect("usable")
            .expect("compiled")
    }

    #[test]
    fn auto_headers_and_now_times_are_stamped_at_each_publication() {
        let t = header_type();
        let mut doc = yaml_rust2::YamlLoader::load_from_str("{stamp: now, frame_id: map}")
            .expect("yaml")
            .remove(0);
        let stamps = Stamps::take(&t.schema, &t.name, &mut doc);
        assert!(!stamps.is_empty());
        let mut v = yaml::fill_from_doc(&t.schema, &t.name, &doc).expect("filled");
        stamps.apply(&mut v, UNIX_EPOCH + Duration::new(12, 34));
        assert_eq!(
            repr::repr(&t.schema, &t.name, &v),
            "std_msgs.msg.Header(stamp=builtin_interfaces.msg.Time(sec=12, nanosec=34), \
             frame_id='map')"
        );
    }
}
