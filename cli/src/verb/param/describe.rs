//! `horus-ros param describe` (ros2param `verb/describe.py`).

use horus_ros_dynamic::repr::py_float;
use horus_ros_msgs::rcl_interfaces::msg::ParameterDescriptor;
use horus_ros_msgs::rcl_interfaces::srv::{DescribeParameters, DescribeParametersRequest};
use serde_json::{json, Value};

use super::{call, client, open_node, type_json, type_string, NodeArgs};
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `param describe`.
#[derive(Debug, clap::Args)]
pub struct DescribeArgs {
    #[command(flatten)]
    node: NodeArgs,
    /// Names of the parameters.
    #[arg(required = true, num_args = 1..)]
    pub parameter_names: Vec<String>,
}

/// Runs `param describe`: one block per descriptor the node answers with.
pub fn run(global: &Global, args: &DescribeArgs) -> Result<(), CliError> {
    let (session, node) = open_node(global, &args.node)?;
    let mut describe = client::<DescribeParameters>(&session, &node, "describe_parameters")?;
    let response = call(
        &mut describe,
        &node,
        DescribeParametersRequest {
            names: args.parameter_names.clone(),
        },
    )?;
    if global.json {
        let list: Vec<Value> = response.descriptors.iter().map(descriptor_json).collect();
        return names::print_json(&Value::Array(list));
    }
    let mut out = String::new();
    for d in &response.descriptors {
        render(&mut out, d)?;
    }
    print!("{out}");
    Ok(())
}

/// ros2param's `_print_descriptor`.
fn render(out: &mut String, d: &ParameterDescriptor) -> Result<(), CliError> {
    // ros2param's mapping raises KeyError on an unknown type.
    let type_ = type_string(d.r#type).ok_or_else(|| CliError::new(d.r#type.to_string()))?;
    out.push_str(&format!("Parameter name: {}\n  Type: {type_}\n", d.name));
    if !d.description.is_empty() {
        out.push_str(&format!("  Description: {}\n", d.description));
    }
    out.push_str("  Constraints:\n");
    if d.read_only {
        out.push_str("    Read only: true\n");
    }
    // `floating_point_range + integer_range`, the first one.
    if let Some(r) = d.floating_point_range.first() {
        out.push_str(&format!(
            "    Min value: {}\n    Max value: {}\n",
            py_float(r.from_value),
            py_float(r.to_value)
        ));
        if r.step != 0.0 {
            out.push_str(&format!("    Step: {}\n", py_float(r.step)));
        }
    } else if let Some(r) = d.integer_range.first() {
        out.push_str(&format!(
            "    Min value: {}\n    Max value: {}\n",
            r.from_value, r.to_value
        ));
        if r.step != 0 {
            out.push_str(&format!("    Step: {}\n", r.step));
        }
    }
    if !d.additional_constraints.is_empty() {
        out.push_str(&format!(
            "    Additional constraints: {}\n",
            d.additional_constraints
        ));
    }
    Ok(())
}

/// A descriptor as JSON.
fn descriptor_json(d: &ParameterDescriptor) -> Value {
    let float = |f: f64| serde_json::Number::from_f64(f).map_or(Value::Null, Value::Number);
    json!({
        "name": d.name,
        "type": type_json(d.r#type),
        "description": d.description,
        "additional_constraints": d.additional_constraints,
        "read_only": d.read_only,
        "dynamic_typing": d.dynamic_typing,
        "floating_point_range": d.floating_point_range.iter().map(|r| json!({
            "from_value": float(r.from_value),
            "to_value": float(r.to_value),
            "step": float(r.step),
        })).collect::<Vec<_>>(),
        "integer_range": d.integer_range.iter().map(|r| json!({
            "from_value": r.from_value,
            "to_value": r.to_value,
            "step": r.step,
        })).collect::<Vec<_>>(),
    })
}
