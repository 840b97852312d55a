//! `horus-ros param dump` (ros2param `verb/dump.py`): the node's parameters as rcl's parameter
//! file, `{/node: {ros__parameters: {…}}}`, written as PyYAML's `yaml.dump(…,
//! default_flow_style=False)` writes it (keys sorted, block style), then an empty line (`print`).

use horus_ros_dynamic::pyyaml::{self, PyValue};
use horus_ros_msgs::rcl_interfaces::msg::{ParameterType, ParameterValue};
use horus_ros_msgs::rcl_interfaces::srv::{
    GetParameters, GetParametersRequest, ListParameters, ListParametersRequest,
};
use serde_json::{Map, Value};

use super::{client, open_node, value_json, wait_failed, NodeArgs, CALL_TIMEOUT, SERVICE_WAIT};
use crate::verb::names;
use crate::{CliError, Global};

/// Stands for Python's `None` (a parameter not set) in the tree given to the YAML writer, which
/// has no null; replaced by `null` in its output.
const NULL_MARK: &str = "horus_ros_null_2f6c9a1e";

/// Arguments of `param dump`.
#[derive(Debug, clap::Args)]
pub struct DumpArgs {
    #[command(flatten)]
    node: NodeArgs,
}

/// A value of the parameter tree.
enum Tree {
    Dict(Vec<(String, Tree)>),
    Leaf(ParameterValue),
}

/// Runs `param dump`.
pub fn run(global: &Global, args: &DumpArgs) -> Result<(), CliError> {
    let (session, node) = open_node(global, &args.node)?;
    let mut list = client::<ListParameters>(&session, &node, "list_parameters")?;
    if !list.wait_for_service(SERVICE_WAIT) {
        // ros2param prints this and ends with status 0.
        eprintln!("{}", wait_failed(&node));
        return Ok(());
    }
    let names = match list.call(ListParametersRequest::default(), CALL_TIMEOUT) {
        Ok(r) => {
            let mut names = r.result.names;
            names.sort();
            names
        }
        Err(e) => {
            eprintln!("Exception while calling list_parameters service of node '{node}': {e}");
            return Ok(());
        }
    };
    let mut get = client::<GetParameters>(&session, &node, "get_parameters")?;
    let values = match get.call(
        GetParametersRequest {
            names: names.clone(),
        },
        CALL_TIMEOUT,
    ) {
        Ok(r) => r.values,
        Err(e) => {
            eprintln!("Exception while calling get_parameters service of node '{node}': {e}");
            return Ok(());
        }
    };
    // `insert_dict` for each (name, value), in name order (zip stops at the shorter).
    let mut root = Vec::new();
    for (name, value) in names.iter().zip(values) {
        insert(&mut root, name, value)?;
    }
    if global.json {
        let mut doc = Map::new();
        doc.insert(
            node.clone(),
            serde_json::json!({ "ros__parameters": tree_json(&root) }),
        );
        return names::print_json(&Value::Object(doc));
    }
    let document = PyValue::Map(vec![(
        node,
        PyValue::Map(vec![("ros__parameters".to_owned(), tree_yaml(root))]),
    )]);
    let text = pyyaml::dump(&document, false).replace(NULL_MARK, "null");
    println!("{text}");
    Ok(())
}

/// ros2param's `insert_dict`: `a.b.c` nests as `a: {b: {c: …}}`.
fn insert(
    dict: &mut Vec<(String, Tree)>,
    key: &str,
    value: ParameterValue,
) -> Result<(), CliError> {
    match key.split_once('.') {
        Some((head, rest)) => {
            let index = match dict.iter().position(|(k, _)| k == head) {
                Some(i) => i,
                None => {
                    dict.push((head.to_owned(), Tree::Dict(Vec::new())));
                    dict.len() - 1
                }
            };
            match &mut dict[index].1 {
                Tree::Dict(inner) => insert(inner, rest, value),
                // Python: `TypeError: '<type>' object does not support item assignment`.
                Tree::Leaf(v) => Err(CliError::new(format!(
                    "'{}' object does not support item assignment",
                    python_type(v)
                ))),
            }
        }
        None => {
            match dict.iter_mut().find(|(k, _)| k == key) {
                Some(entry) => entry.1 = Tree::Leaf(value),
                None => dict.push((key.to_owned(), Tree::Leaf(value))),
            }
            Ok(())
        }
    }
}

/// The Python type of `parameter_value_to_python`'s result.
fn python_type(v: &ParameterValue) -> &'static str {
    match v.r#type {
        ParameterType::PARAMETER_BOOL => "bool",
        ParameterType::PARAMETER_INTEGER => "int",
        ParameterType::PARAMETER_DOUBLE => "float",
        ParameterType::PARAMETER_STRING => "str",
        ParameterType::PARAMETER_NOT_SET => "NoneType",
        _ => "list",
    }
}

/// The tree as PyYAML sees it: mappings with sorted keys (`sort_keys=True`).
fn tree_yaml(items: Vec<(String, Tree)>) -> PyValue {
    let mut items: Vec<(String, PyValue)> = items
        .into_iter()
        .map(|(k, t)| {
            let v = match t {
                Tree::Dict(inner) => tree_yaml(inner),
                Tree::Leaf(v) => value_yaml(&v),
            };
            (k, v)
        })
        .collect();
    items.sort_by(|a, b| a.0.cmp(&b.0));
    PyValue::Map(items)
}

/// `parameter_value_to_python` as PyYAML represents it. A byte array is written as its numbers
/// (PyYAML writes rclpy's `bytes` items as `!!binary`).
fn value_yaml(v: &ParameterValue) -> PyValue {
    match v.r#type {
        ParameterType::PARAMETER_BOOL => PyValue::Bool(v.bool_value),
        ParameterType::PARAMETER_INTEGER => PyValue::Int(v.integer_value.into()),
        ParameterType::PARAMETER_DOUBLE => PyValue::Float(v.double_value),
        ParameterType::PARAMETER_STRING => PyValue::Str(v.string_value.clone()),
        ParameterType::PARAMETER_BYTE_ARRAY => PyValue::List(
            v.byte_array_value
                .iter()
                .map(|b| PyValue::Int(u8::from(*b).into()))
                .collect(),
        ),
        ParameterType::PARAMETER_BOOL_ARRAY => PyValue::List(
            v.bool_array_value
                .iter()
                .map(|b| PyValue::Bool(*b))
                .collect(),
        ),
        ParameterType::PARAMETER_INTEGER_ARRAY => PyValue::List(
            v.integer_array_value
                .iter()
                .map(|i| PyValue::Int((*i).into()))
                .collect(),
        ),
        ParameterType::PARAMETER_DOUBLE_ARRAY => PyValue::List(
            v.double_array_value
                .iter()
                .map(|f| PyValue::Float(*f))
                .collect(),
        ),
        ParameterType::PARAMETER_STRING_ARRAY => PyValue::List(
            v.string_array_value
                .iter()
                .map(|s| PyValue::Str(s.clone()))
                .collect(),
        ),
        _ => PyValue::Str(NULL_MARK.to_owned()),
    }
}

/// The tree as JSON.
fn tree_json(items: &[(String, Tree)]) -> Value {
    let mut map = Map::new();
    for (k, t) in items {
        let v = match t {
            Tree::Dict(inner) => tree_json(inner),
            Tree::Leaf(v) => value_json(v),
        };
        map.insert(k.clone(), v);
    }
    Value::Object(map)
}
