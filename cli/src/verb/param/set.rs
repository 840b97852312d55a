//! `horus-ros param set` and `param delete` (ros2param `verb/set.py`, `verb/delete.py`).

use horus_ros_msgs::rcl_interfaces::msg::{Parameter, ParameterValue, SetParametersResult};
use horus_ros_msgs::rcl_interfaces::srv::{SetParameters, SetParametersRequest};
use serde_json::json;

use super::{call, client, open_node, pyobj, NodeArgs};
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `param set`.
#[derive(Debug, clap::Args)]
pub struct SetArgs {
    #[command(flatten)]
    node: NodeArgs,
    /// Name of the parameter.
    pub parameter_name: String,
    /// Value of the parameter.
    #[arg(allow_negative_numbers = true)]
    pub value: String,
}

/// Arguments of `param delete`.
#[derive(Debug, clap::Args)]
pub struct DeleteArgs {
    #[command(flatten)]
    node: NodeArgs,
    /// Name of the parameter.
    pub parameter_name: String,
}

/// Runs `param set`: the value typed as rclpy's `get_parameter_value` types it (YAML).
pub fn run(global: &Global, args: &SetArgs) -> Result<(), CliError> {
    let value = pyobj::get_parameter_value(&args.value)?;
    let result = set_one(global, &args.node, &args.parameter_name, value)?;
    report(
        global,
        &args.node.node_name,
        &args.parameter_name,
        &result,
        ("Set parameter successful", "Setting parameter failed"),
    )
}

/// Runs `param delete`: sets the parameter to NOT_SET.
pub fn run_delete(global: &Global, args: &DeleteArgs) -> Result<(), CliError> {
    let result = set_one(
        global,
        &args.node,
        &args.parameter_name,
        ParameterValue::default(),
    )?;
    report(
        global,
        &args.node.node_name,
        &args.parameter_name,
        &result,
        (
            "Deleted parameter successfully",
            "Deleting parameter failed",
        ),
    )
}

/// Calls `<node>/set_parameters` with one parameter.
fn set_one(
    global: &Global,
    node_args: &NodeArgs,
    name: &str,
    value: ParameterValue,
) -> Result<SetParametersResult, CliError> {
    let (session, node) = open_node(global, node_args)?;
    let mut set = client::<SetParameters>(&session, &node, "set_parameters")?;
    let response = call(
        &mut set,
        &node,
        SetParametersRequest {
            parameters: vec![Parameter {
                name: name.to_owned(),
                value,
            }],
        },
    )?;
    response.results.into_iter().next().ok_or_else(|| {
        CliError::new(format!(
            "Exception while calling service of node {node}: no result"
        ))
    })
}

/// Prints ros2param's line: on stdout when successful, else on stderr (exit status 0 both).
fn report(
    global: &Global,
    node: &str,
    name: &str,
    result: &SetParametersResult,
    (ok, failed): (&str, &str),
) -> Result<(), CliError> {
    if global.json {
        return names::print_json(&json!({
            "node": super::absolute_node_name(node),
            "name": name,
            "successful": result.successful,
            "reason": result.reason,
        }));
    }
    super::print_result(if result.successful { ok } else { failed }, result);
    Ok(())
}
