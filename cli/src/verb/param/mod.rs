//! `horus-ros param …`: ros2cli's `ros2 param` verbs (ros2param 0.32, Jazzy), calling a node's
//! parameter services (`<node>/list_parameters`, `get_parameters`, `set_parameters`,
//! `describe_parameters`; rcl_interfaces) as rclpy's `AsyncParameterClient` does.
//!
//! # `--json`
//!
//! - `param list`: `[{"node": "/n", "parameters": [{"name", "type"}…], "error": null | "…"}…]`,
//!   `type` as `--param-type` prints it (`"integer"`, `"string array"`…) or `null` without it.
//! - `param get`: `{"node", "name", "type", "value"}`; `type` as `param describe` prints it
//!   (`"not set"` with `value` `null` when the parameter is not set).
//! - `param set` / `param delete`: `{"node", "name", "successful", "reason"}`.
//! - `param describe`: `[{"name", "type", "description", "additional_constraints", "read_only",
//!   "dynamic_typing", "floating_point_range": [{"from_value", "to_value", "step"}],
//!   "integer_range": [{"from_value", "to_value", "step"}]}…]`.
//! - `param dump`: `{"/node": {"ros__parameters": {…}}}`, the document `dump` prints as YAML.
//! - `param load`: `{"node", "results": [{"name", "successful", "reason"}…]}`.
//!
//! A value is JSON's: a bool, a number, a string, an array (a byte array as numbers); a
//! non-finite double is `null`.

pub mod describe;
pub mod dump;
pub mod get;
pub mod list;
pub mod load;
pub mod pyobj;
pub mod set;

use std::time::{Duration, Instant};

use clap::Subcommand;
use horus_ros_msgs::rcl_interfaces::msg::{ParameterType, ParameterValue, SetParametersResult};
use horus_ros_msgs::Service;
use horus_ros_services::{EndpointBuilder, ServiceClient, ServiceError};
use serde_json::{json, Value};

use horus_ros_graph::GraphCache;

use crate::session::{GraphSource, Session};
use crate::verb::names;
use crate::{CliError, Global};

/// rclpy's `AsyncParameterClient.wait_for_services` timeout in ros2param (`api/__init__.py`).
const SERVICE_WAIT: Duration = Duration::from_secs(5);
/// How long one parameter service call may take (rclpy waits without a bound).
const CALL_TIMEOUT: Duration = Duration::from_secs(30);

/// The `param` verbs.
#[derive(Debug, Subcommand)]
pub enum ParamCommand {
    /// Output a list of available parameters.
    List(list::ListArgs),
    /// Get parameter.
    Get(get::GetArgs),
    /// Set parameter.
    Set(set::SetArgs),
    /// Show descriptive information about declared parameters.
    Describe(describe::DescribeArgs),
    /// Show all of the parameters of a node in a YAML file format.
    Dump(dump::DumpArgs),
    /// Load parameter file for a node.
    Load(load::LoadArgs),
    /// Delete parameter.
    Delete(set::DeleteArgs),
}

/// Runs a `param` verb.
pub fn run(global: &Global, command: ParamCommand) -> Result<(), CliError> {
    match command {
        ParamCommand::List(a) => list::run(global, &a),
        ParamCommand::Get(a) => get::run(global, &a),
        ParamCommand::Set(a) => set::run(global, &a),
        ParamCommand::Describe(a) => describe::run(global, &a),
        ParamCommand::Dump(a) => dump::run(global, &a),
        ParamCommand::Load(a) => load::run(global, &a),
        ParamCommand::Delete(a) => set::run_delete(global, &a),
    }
}

/// The node options every verb but `list` takes.
#[derive(Debug, Clone, clap::Args)]
pub struct NodeArgs {
    /// Name of the ROS node.
    pub node_name: String,
    /// Consider hidden nodes as well.
    #[arg(long)]
    pub include_hidden_nodes: bool,
    /// Wait for N seconds until node becomes available (default 1 sec).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub timeout: u64,
}

/// ros2node's `get_absolute_node_name`: a `/` prepended when missing.
pub fn absolute_node_name(name: &str) -> String {
    if name.starts_with('/') {
        name.to_owned()
    } else {
        format!("/{name}")
    }
}

/// The full names of the nodes in the graph (hidden ones only when asked), with their (name,
/// namespace).
pub fn node_names(source: &GraphSource, include_hidden: bool) -> Vec<(String, String, String)> {
    source.read(|c| node_names_in(c, include_hidden))
}

/// [`node_names`] of a graph.
fn node_names_in(c: &GraphCache, include_hidden: bool) -> Vec<(String, String, String)> {
    c.node_names()
        .into_iter()
        .filter(|n| include_hidden || !names::is_hidden_node(&n.name))
        .map(|n| {
            (
                n.name.clone(),
                n.namespace.clone(),
                names::node_full_name(&n.namespace, &n.name),
            )
        })
        .collect()
}

/// ros2param's `NodeStrategy`, then its `DirectNode`: the node is looked for in the graph the
/// query verbs read (the daemon's, started when none runs; with `--no-daemon`, a session of our
/// own) and, when found there, called from a node of our own that does not wait for discovery
/// (each call waits for its service, as ros2param's). Not found there, a session of our own
/// waits, as ros2node's `wait_for_node`, up to `--timeout` seconds for the node; "Node not
/// found" when it does not appear.
pub fn open_node(global: &Global, args: &NodeArgs) -> Result<(Session, String), CliError> {
    let node = absolute_node_name(&args.node_name);
    let listed = |c: &GraphCache| {
        node_names_in(c, args.include_hidden_nodes)
            .iter()
            .any(|(_, _, full)| *full == node)
    };
    let source = GraphSource::open(global)?;
    let session = match source {
        GraphSource::Daemon { .. } if source.read(listed) => {
            return Ok((Session::join(global)?, node));
        }
        GraphSource::Daemon { .. } => Session::open(global)?,
        GraphSource::Direct(session) => *session,
    };
    let deadline = Instant::now() + Duration::from_secs(args.timeout);
    loop {
        let seen = session.graph.generation();
        if session.graph.read(listed) {
            return Ok((session, node));
        }
        let now = Instant::now();
        if now >= deadline {
            return Err(CliError::new("Node not found"));
        }
        // Woken by the next graph change (a node appearing is one), not by polling.
        session
            .graph
            .wait_for_graph_change_since(seen, deadline - now);
    }
}

/// A client of one of `node`'s parameter services (`<node>/<service>`).
pub fn client<S: Service>(
    session: &Session,
    node: &str,
    service: &str,
) -> Result<ServiceClient<S>, CliError> {
    Ok(ServiceClient::<S>::builder()
        .name(format!("{node}/{service}"))
        .node(&session.node)
        .build()?)
}

/// ros2param's text when a node's parameter services did not come within 5 s.
pub fn wait_failed(node: &str) -> String {
    format!("Wait for service timed out waiting for parameter services for node {node}")
}

/// Waits (5 s, as ros2param) for the service, then calls it; the errors are ros2param's texts.
pub fn call<S: Service>(
    client: &mut ServiceClient<S>,
    node: &str,
    request: S::Request,
) -> Result<S::Response, CliError> {
    if !client.wait_for_service(SERVICE_WAIT) {
        return Err(CliError::new(wait_failed(node)));
    }
    client
        .call(request, CALL_TIMEOUT)
        .map_err(|e| call_error(node, &e))
}

/// ros2param's text when a call failed.
pub fn call_error(node: &str, e: &ServiceError) -> CliError {
    CliError::new(format!(
        "Exception while calling service of node {node}: {e}"
    ))
}

/// ros2param's report of one set: `msg`, then `: {reason}` when the node gave one, on stdout
/// when it succeeded, else on stderr (ros2param 0.32.2 `verb/set.py`, `verb/delete.py` and
/// `api/__init__.py` `load_parameter_file`).
pub fn print_result(msg: &str, result: &SetParametersResult) {
    let mut msg = msg.to_owned();
    if !result.reason.is_empty() {
        msg.push_str(": ");
        msg.push_str(&result.reason);
    }
    if result.successful {
        println!("{msg}");
    } else {
        eprintln!("{msg}");
    }
}

/// ros2param's `get_parameter_type_string`; `None` for a type it does not know.
pub fn type_string(t: u8) -> Option<&'static str> {
    Some(match t {
        ParameterType::PARAMETER_BOOL => "boolean",
        ParameterType::PARAMETER_INTEGER => "integer",
        ParameterType::PARAMETER_DOUBLE => "double",
        ParameterType::PARAMETER_STRING => "string",
        ParameterType::PARAMETER_BYTE_ARRAY => "byte array",
        ParameterType::PARAMETER_BOOL_ARRAY => "boolean array",
        ParameterType::PARAMETER_INTEGER_ARRAY => "integer array",
        ParameterType::PARAMETER_DOUBLE_ARRAY => "double array",
        ParameterType::PARAMETER_STRING_ARRAY => "string array",
        ParameterType::PARAMETER_NOT_SET => "not set",
        _ => return None,
    })
}

/// A parameter type's name for `--json` (ros2param's, or `"unknown"`).
pub fn type_json(t: u8) -> &'static str {
    type_string(t).unwrap_or("unknown")
}

/// A double as JSON (`null` when not finite).
fn double_json(f: f64) -> Value {
    serde_json::Number::from_f64(f).map_or(Value::Null, Value::Number)
}

/// A parameter value as JSON (`null` when not set).
pub fn value_json(v: &ParameterValue) -> Value {
    match v.r#type {
        ParameterType::PARAMETER_BOOL => json!(v.bool_value),
        ParameterType::PARAMETER_INTEGER => json!(v.integer_value),
        ParameterType::PARAMETER_DOUBLE => double_json(v.double_value),
        ParameterType::PARAMETER_STRING => json!(v.string_value),
        ParameterType::PARAMETER_BYTE_ARRAY => Value::Array(
            v.byte_array_value
                .iter()
                .map(|b| json!(u8::from(*b)))
                .collect(),
        ),
        ParameterType::PARAMETER_BOOL_ARRAY => json!(v.bool_array_value),
        ParameterType::PARAMETER_INTEGER_ARRAY => json!(v.integer_array_value),
        ParameterType::PARAMETER_DOUBLE_ARRAY => Value::Array(
            v.double_array_value
                .iter()
                .map(|f| double_json(*f))
                .collect(),
        ),
        ParameterType::PARAMETER_STRING_ARRAY => json!(v.string_array_value),
        _ => Value::Null,
    }
}
