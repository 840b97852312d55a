//! Fuzzing entry points for the dynamic type system: each takes arbitrary bytes and panics only
//! on a bug (called by the `fuzz/` targets and `tests/fuzz_dynamic.rs`).
//!
//! - [`cdr`]: a body decoded as one of the compiled types, through its description, as
//!   `service call` reads replies and `service echo` reads events.
//! - [`yaml`]: a YAML document filled into one of those types, as `service call` reads its
//!   argument.
//! - [`description`]: a `GetTypeDescription_Response` from a peer, turned into a schema as
//!   `service call` does for types it does not know, then a body decoded with it.

use std::sync::OnceLock;

use horus_ros_msgs::cdr::from_cdr;
use horus_ros_msgs::description::{EVENT_SUFFIX, REQUEST_SUFFIX, RESPONSE_SUFFIX};
use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;
use horus_ros_msgs::type_description_interfaces::srv::GetTypeDescriptionResponse;
use horus_ros_msgs::{example_interfaces, rcl_interfaces, std_srvs, type_description_interfaces};
use horus_ros_msgs::{Message, Service, TypeDescription};

use super::convert::{to_csv, to_ordereddict, ConvertOptions};
use super::pyyaml::dump;
use super::repr::repr;
use super::yaml::fill_from_yaml;
use super::{sub_description, Elem, Schema, Value};

/// Most types of one received description that [`description`] tries (each is a root).
const MAX_DESCRIPTION_ROOTS: usize = 16;

/// The compiled types [`cdr`] and [`yaml`] select from: one schema holding them all, and the
/// root type names in selector order.
struct Compiled {
    schema: Schema,
    roots: Vec<String>,
}

fn compiled() -> &'static Compiled {
    static COMPILED: OnceLock<Compiled> = OnceLock::new();
    COMPILED.get_or_init(|| {
        fn service<S: Service>(descriptions: &mut Vec<TypeDescription>, roots: &mut Vec<String>) {
            descriptions.push(S::type_description());
            for suffix in [REQUEST_SUFFIX, RESPONSE_SUFFIX, EVENT_SUFFIX] {
                roots.push(format!("{}{suffix}", S::TYPE_NAME));
            }
        }
        let mut descriptions = Vec::new();
        let mut roots = Vec::new();
        service::<example_interfaces::srv::AddTwoInts>(&mut descriptions, &mut roots);
        service::<std_srvs::srv::Empty>(&mut descriptions, &mut roots);
        service::<std_srvs::srv::Trigger>(&mut descriptions, &mut roots);
        service::<std_srvs::srv::SetBool>(&mut descriptions, &mut roots);
        service::<rcl_interfaces::srv::ListParameters>(&mut descriptions, &mut roots);
        service::<rcl_interfaces::srv::GetParameters>(&mut descriptions, &mut roots);
        service::<rcl_interfaces::srv::GetParameterTypes>(&mut descriptions, &mut roots);
        service::<rcl_interfaces::srv::SetParameters>(&mut descriptions, &mut roots);
        service::<rcl_interfaces::srv::SetParametersAtomically>(&mut descriptions, &mut roots);
        service::<rcl_interfaces::srv::DescribeParameters>(&mut descriptions, &mut roots);
        service::<type_description_interfaces::srv::GetTypeDescription>(
            &mut descriptions,
            &mut roots,
        );
        descriptions.push(ParticipantEntitiesInfo::type_description());
        roots.push(ParticipantEntitiesInfo::TYPE_NAME.to_owned());
        let mut schema = Schema::default();
        for d in &descriptions {
            schema.add(d).expect("compiled descriptions convert");
        }
        for root in &roots {
            schema.check(root).expect("compiled types are complete");
        }
        Compiled { schema, roots }
    })
}

/// One schema holding every compiled type [`compiled_roots`] names.
pub fn compiled_schema() -> &'static Schema {
    &compiled().schema
}

/// The compiled root type names, in the order the selector bytes of [`cdr`] and [`yaml`] pick
/// them (modulo their number).
pub fn compiled_roots() -> &'static [String] {
    &compiled().roots
}

/// Whether a value holds a string with a NUL, which CDR strings cannot carry (decoding keeps
/// such bytes, encoding refuses them).
fn has_nul(v: &Value) -> bool {
    match v {
        Value::Str(s) => s.contains('\0'),
        Value::List(items) | Value::Struct(items) => items.iter().any(has_nul),
        Value::Bool(_) | Value::Int(_) | Value::Float(_) | Value::Byte(_) => false,
    }
}

/// A value of type `name` that came from outside (decoded or filled): it prints as
/// `service call` / `service echo` print values, and, unless it holds what CDR cannot carry,
/// encodes to bytes that decode to a value encoding the same.
fn check_value(schema: &Schema, name: &str, value: &Value) {
    let _ = repr(schema, name, value);
    let options = ConvertOptions {
        truncate_length: Some(128),
        no_arr: false,
        no_str: false,
    };
    let dict = to_ordereddict(schema, name, value, options);
    let _ = dump(&dict, false);
    let _ = dump(&dict, true);
    let _ = to_csv(schema, name, value, ConvertOptions::default());
    match super::cdr::encode(schema, name, value) {
        Ok(encoded) => {
            let again = super::cdr::decode(schema, name, &encoded, false)
                .unwrap_or_else(|e| panic!("an encoded {name} does not decode: {e}"));
            let re_encoded = super::cdr::encode(schema, name, &again)
                .unwrap_or_else(|e| panic!("a decoded {name} does not encode: {e}"));
            assert_eq!(
                re_encoded, encoded,
                "round trip of {name} changed the value"
            );
        }
        Err(e) => assert!(
            has_nul(value) || uses(schema, name, &|e| matches!(e, Elem::LongDouble)),
            "a {name} value does not encode: {e}"
        ),
    }
}

/// Whether type `name` has (recursively) a field whose element satisfies `pred`.
fn uses(schema: &Schema, name: &str, pred: &dyn Fn(&Elem) -> bool) -> bool {
    schema.get(name).is_ok_and(|s| {
        s.members.iter().any(|m| {
            pred(&m.ty.elem)
                || matches!(&m.ty.elem, Elem::Nested(n) if n != name && uses(schema, n, pred))
        })
    })
}

/// A body: `flags, selector, body`; bit 0 of `flags` is the byte order (1 = big-endian), the
/// selector picks one of [`compiled_roots`].
pub fn cdr(data: &[u8]) {
    let [flags, selector, body @ ..] = data else {
        return;
    };
    let c = compiled();
    let name = &c.roots[usize::from(*selector) % c.roots.len()];
    if let Ok(value) = super::cdr::decode(&c.schema, name, body, flags & 1 == 1) {
        check_value(&c.schema, name, &value);
    }
}

/// A YAML document as `service call` takes it: `selector, text` (text as UTF-8, invalid bytes
/// replaced); the selector picks one of [`compiled_roots`].
pub fn yaml(data: &[u8]) {
    let [selector, text @ ..] = data else {
        return;
    };
    let c = compiled();
    let name = &c.roots[usize::from(*selector) % c.roots.len()];
    let text = String::from_utf8_lossy(text);
    if let Ok(value) = fill_from_yaml(&c.schema, name, &text) {
        check_value(&c.schema, name, &value);
    }
}

/// A type description from a peer's `~/get_type_description`, then a body: `length (u16 LE),
/// GetTypeDescription_Response payload (CDR with header) of that length, flags, body`.
///
/// The description is hashed (as `service call` checks it against the hash it asked for); then
/// for each of its types (at most `MAX_DESCRIPTION_ROOTS`, 16), as `service call` and `service
/// echo` do: its sub-description, a schema from it, checked; then its default value (what an
/// empty YAML argument gives) and the body decoded as that type are checked as [`cdr`] checks
/// values.
pub fn description(data: &[u8]) {
    let Some((len, rest)) = data.split_first_chunk::<2>() else {
        return;
    };
    let len = usize::from(u16::from_le_bytes(*len)).min(rest.len());
    let (payload, rest) = rest.split_at(len);
    let Ok(response) = from_cdr::<GetTypeDescriptionResponse>(payload) else {
        return;
    };
    let (big_endian, body) = match rest.split_first() {
        Some((flags, body)) => (flags & 1 == 1, body),
        None => (false, rest),
    };
    let d = &response.type_description;
    let _ = d.compute_type_hash();
    let names = std::iter::once(&d.type_description)
        .chain(&d.referenced_type_descriptions)
        .map(|t| t.type_name.clone())
        .take(MAX_DESCRIPTION_ROOTS);
    for name in names {
        let Ok(sub) = sub_description(d, &name) else {
            continue;
        };
        let Ok(schema) = Schema::from_description(&sub).and_then(|s| s.check(&name).map(|()| s))
        else {
            continue;
        };
        // The default value (an empty YAML argument fills nothing else).
        if let Ok(value) = fill_from_yaml(&schema, &name, "{}") {
            check_value(&schema, &name, &value);
        }
        if let Ok(value) = super::cdr::decode(&schema, &name, body, big_endian) {
            check_value(&schema, &name, &value);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_compiled_root_is_in_the_schema() {
        let c = compiled();
        assert_eq!(c.roots.len(), 34);
        for root in &c.roots {
            assert!(c.schema.default_value(root).is_ok(), "{root}");
        }
    }
}
