//! `horus-ros param load` (ros2param `verb/load.py`, `api.load_parameter_file`): the parameters
//! of an rcl parameter file set on a node in one `set_parameters` call, read as rclpy's
//! `parameter_dict_from_yaml_file` reads it.

use horus_ros_msgs::rcl_interfaces::msg::Parameter;
use horus_ros_msgs::rcl_interfaces::srv::{SetParameters, SetParametersRequest};
use serde_json::{json, Value};

use super::pyobj::{self, PyObj};
use super::{call, client, open_node, NodeArgs};
use crate::verb::names;
use crate::{CliError, Global};

/// rcl's wildcard node key.
const WILDCARD: &str = "/**";

/// Arguments of `param load`.
#[derive(Debug, clap::Args)]
pub struct LoadArgs {
    #[command(flatten)]
    node: NodeArgs,
    /// Parameter file.
    pub parameter_file: String,
    /// Do not load parameters in the '/**' namespace into the node.
    #[arg(long)]
    pub no_use_wildcard: bool,
}

/// Why a parameter file cannot be used (rclpy's texts).
#[derive(Debug, thiserror::Error)]
pub enum ParameterFileError {
    /// The file could not be read.
    #[error("[Errno {}] {}: {}", .source.raw_os_error().unwrap_or(0), io_text(.source), pyobj_repr(.path))]
    Read {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not YAML.
    #[error("{0}")]
    Yaml(#[from] pyobj::LoadError),
    /// No node entry is selected.
    #[error("Param file does not contain selected parameters")]
    NothingSelected,
    /// A node entry has no `ros__parameters` mapping.
    #[error("YAML file is not a valid ROS parameter file for node {0}")]
    NotAParameterFile(String),
    /// A value cannot be a parameter value.
    #[error(transparent)]
    Value(#[from] pyobj::ValueError),
}

/// Python's text of an OS error (without Rust's " (os error N)").
fn io_text(e: &std::io::Error) -> String {
    let text = e.to_string();
    match text.find(" (os error") {
        Some(i) => text[..i].to_owned(),
        None => text,
    }
}

fn pyobj_repr(s: &str) -> String {
    horus_ros_dynamic::repr::py_str(s)
}

/// rclpy `parameter_dict_from_yaml_file(path, use_wildcard)` (no target nodes: every node entry
/// of the file, the wildcard's first so that node entries override it), as the list of
/// parameters in the dict's order.
pub fn parameters_from_file(
    path: &str,
    use_wildcard: bool,
) -> Result<Vec<Parameter>, ParameterFileError> {
    let text = std::fs::read_to_string(path).map_err(|source| ParameterFileError::Read {
        path: path.to_owned(),
        source,
    })?;
    parameters_from_yaml(&text, use_wildcard)
}

/// [`parameters_from_file`] of a file's text.
pub fn parameters_from_yaml(
    text: &str,
    use_wildcard: bool,
) -> Result<Vec<Parameter>, ParameterFileError> {
    let file = pyobj::safe_load(text)?;
    let entries = match file {
        PyObj::Dict(entries) => entries,
        _ => Vec::new(),
    };
    let wildcard = PyObj::Str(WILDCARD.to_owned());
    let mut selected: Vec<&(PyObj, PyObj)> = Vec::new();
    if use_wildcard {
        selected.extend(entries.iter().filter(|(k, _)| *k == wildcard));
    }
    selected.extend(entries.iter().filter(|(k, _)| *k != wildcard));
    if selected.is_empty() {
        return Err(ParameterFileError::NothingSelected);
    }
    // `param_dict.update(value['ros__parameters'])`.
    let mut merged: Vec<(PyObj, PyObj)> = Vec::new();
    for (key, value) in selected {
        let params = match value {
            PyObj::Dict(items) => items
                .iter()
                .find(|(k, _)| *k == PyObj::Str("ros__parameters".into()))
                .map(|(_, v)| v),
            _ => None,
        };
        let Some(PyObj::Dict(params)) = params else {
            return Err(ParameterFileError::NotAParameterFile(pyobj::py_display(
                key,
            )));
        };
        for (k, v) in params {
            match merged.iter_mut().find(|(existing, _)| existing == k) {
                Some(entry) => entry.1 = v.clone(),
                None => merged.push((k.clone(), v.clone())),
            }
        }
    }
    let mut out: Vec<Parameter> = Vec::new();
    unpack("", &merged, &mut out)?;
    Ok(out)
}

/// rclpy `_unpack_parameter_dict`: nested mappings flattened to `a.b.c`; each value typed by
/// `get_parameter_value(str(value))`. A name seen again keeps its place and takes the new value.
fn unpack(
    namespace: &str,
    dict: &[(PyObj, PyObj)],
    out: &mut Vec<Parameter>,
) -> Result<(), ParameterFileError> {
    for (key, value) in dict {
        let name = format!("{namespace}{}", pyobj::py_display(key));
        if let PyObj::Dict(inner) = value {
            unpack(&format!("{name}."), inner, out)?;
            continue;
        }
        let value = pyobj::get_parameter_value(&pyobj::py_display(value))?;
        match out.iter_mut().find(|p| p.name == name) {
            Some(p) => p.value = value,
            None => out.push(Parameter { name, value }),
        }
    }
    Ok(())
}

/// Runs `param load`: one line per parameter, `Set parameter <name> successful` on stdout or
/// `Set parameter <name> failed` on stderr (with the node's reason when it gives one).
pub fn run(global: &Global, args: &LoadArgs) -> Result<(), CliError> {
    let (session, node) = open_node(global, &args.node)?;
    let mut set = client::<SetParameters>(&session, &node, "set_parameters")?;
    if !set.wait_for_service(super::SERVICE_WAIT) {
        return Err(CliError::new(super::wait_failed(&node)));
    }
    let parameters = parameters_from_file(&args.parameter_file, !args.no_use_wildcard)?;
    let names: Vec<String> = parameters.iter().map(|p| p.name.clone()).collect();
    let response = call(&mut set, &node, SetParametersRequest { parameters })?;
    if response.results.len() != names.len() {
        return Err(CliError::new("AssertionError: Not all parameters set"));
    }
    if global.json {
        let results: Vec<Value> = names
            .iter()
            .zip(&response.results)
            .map(|(n, r)| json!({"name": n, "successful": r.successful, "reason": r.reason}))
            .collect();
        return names::print_json(&json!({"node": node, "results": results}));
    }
    for (name, result) in names.iter().zip(&response.results) {
        let verdict = if result.successful {
            "successful"
        } else {
            "failed"
        };
        super::print_result(&format!("Set parameter {name} {verdict}"), result);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_msgs::rcl_interfaces::msg::ParameterType as T;

    #[test]
    fn files_are_read_as_rclpy_reads_them() {
        let text = "/**:\n  ros__parameters:\n    a: 1\n    s: x\n/n:\n  ros__parameters:\n    \
                    a: 2\n    nested:\n      d: 1.5\n      l: ['a', 'b']\n    q: '5'\n";
        let p = parameters_from_yaml(text, true).expect("loads");
        let got: Vec<(&str, u8)> = p
            .iter()
            .map(|p| (p.name.as_str(), p.value.r#type))
            .collect();
        assert_eq!(
            got,
            [
                ("a", T::PARAMETER_INTEGER),
                ("s", T::PARAMETER_STRING),
                ("nested.d", T::PARAMETER_DOUBLE),
                ("nested.l", T::PARAMETER_STRING_ARRAY),
                // str('5') is typed again: an integer, as rclpy does.
                ("q", T::PARAMETER_INTEGER),
            ]
        );
        assert_eq!(p[0].value.integer_value, 2);
        let p = parameters_from_yaml(text, false).expect("loads");
        assert_eq!(p.len(), 4);
        assert!(matches!(
            parameters_from_yaml("/**:\n  ros__parameters: {a: 1}\n", false),
            Err(ParameterFileError::NothingSelected)
        ));
        assert!(matches!(
            parameters_from_yaml("/n:\n  x: 1\n", true),
            Err(ParameterFileError::NotAParameterFile(n)) if n == "/n"
        ));
    }
}
