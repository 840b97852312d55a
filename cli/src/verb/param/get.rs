//! `horus-ros param get` (ros2param `verb/get.py`).

use horus_ros_msgs::rcl_interfaces::msg::ParameterType;
use horus_ros_msgs::rcl_interfaces::srv::{GetParameters, GetParametersRequest};
use serde_json::json;

use super::{call, client, open_node, pyobj, type_json, value_json, NodeArgs};
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `param get`.
#[derive(Debug, clap::Args)]
pub struct GetArgs {
    #[command(flatten)]
    node: NodeArgs,
    /// Name of the parameter.
    pub parameter_name: String,
    /// Hide the type information.
    #[arg(long)]
    pub hide_type: bool,
}

/// ros2param's label for a value of type `t` (`None` for an unknown type).
fn label(t: u8) -> Option<&'static str> {
    Some(match t {
        ParameterType::PARAMETER_BOOL => "Boolean value is:",
        ParameterType::PARAMETER_INTEGER => "Integer value is:",
        ParameterType::PARAMETER_DOUBLE => "Double value is:",
        ParameterType::PARAMETER_STRING => "String value is:",
        ParameterType::PARAMETER_BYTE_ARRAY => "Byte values are:",
        ParameterType::PARAMETER_BOOL_ARRAY => "Boolean values are:",
        ParameterType::PARAMETER_INTEGER_ARRAY => "Integer values are:",
        ParameterType::PARAMETER_DOUBLE_ARRAY => "Double values are:",
        ParameterType::PARAMETER_STRING_ARRAY => "String values are:",
        ParameterType::PARAMETER_NOT_SET => "Parameter not set.",
        _ => return None,
    })
}

/// Runs `param get`: `<label> <value>` (`<value>` alone with `--hide-type`).
pub fn run(global: &Global, args: &GetArgs) -> Result<(), CliError> {
    let (session, node) = open_node(global, &args.node)?;
    let mut get = client::<GetParameters>(&session, &node, "get_parameters")?;
    let response = call(
        &mut get,
        &node,
        GetParametersRequest {
            names: vec![args.parameter_name.clone()],
        },
    )?;
    let Some(value) = response.values.first() else {
        return Err(CliError::new("Parameter not set"));
    };
    if global.json {
        return names::print_json(&json!({
            "node": node,
            "name": args.parameter_name,
            "type": type_json(value.r#type),
            "value": value_json(value),
        }));
    }
    let (Some(label), Ok(shown)) = (label(value.r#type), pyobj::get_display(value)) else {
        return Err(CliError::new(format!(
            "Unknown parameter type '{}'",
            value.r#type
        )));
    };
    // `print(label, value) if value is not None else print(label)`; `print(value)` when hidden.
    match (args.hide_type, shown) {
        (false, Some(v)) => println!("{label} {v}"),
        (false, None) => println!("{label}"),
        (true, Some(v)) => println!("{v}"),
        (true, None) => println!("None"),
    }
    Ok(())
}
