//! Where a type's definition comes from, in this order: its interface file in a package on
//! `AMENT_PREFIX_PATH`, else the types compiled into horus-ros, or (`--from-graph`) the
//! description a running node gives through its `~/get_type_description` service.

use std::path::PathBuf;
use std::time::Duration;

use horus_ros_codegen::ament::InterfaceKind;
use horus_ros_codegen::{DescribeError, TypeRegistry};
use horus_ros_msgs::description::{REQUEST_SUFFIX, RESPONSE_SUFFIX};
use horus_ros_msgs::TypeDescription;

use super::catalog::Catalog;
use crate::dynamic::compiled::compiled_type;
use crate::dynamic::Schema;
use crate::session::Session;
use crate::verb::service::call::describe;
use crate::{CliError, Global};

/// Where a [`Definition`] came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// An interface file of an installed package.
    File,
    /// A type compiled into horus-ros.
    Compiled,
    /// A running node's `~/get_type_description`.
    Graph,
}

impl Origin {
    /// The word `--json` uses.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::File => "file",
            Self::Compiled => "compiled",
            Self::Graph => "graph",
        }
    }
}

/// A type's definition.
pub enum Definition {
    /// An interface file.
    File {
        /// The package (context of the file's unqualified type names).
        package: String,
        /// The file.
        path: PathBuf,
    },
    /// A type description: its structs, and the parts of the type (a message: itself; a
    /// service: its request and response).
    Described {
        /// The structs.
        schema: Schema,
        /// `pkg/msg/Name`, or `pkg/srv/Name_Request` and `pkg/srv/Name_Response`.
        parts: Vec<String>,
        /// Compiled or from the graph.
        origin: Origin,
    },
}

impl Definition {
    /// Where it came from.
    pub fn origin(&self) -> Origin {
        match self {
            Self::File { .. } => Origin::File,
            Self::Described { origin, .. } => *origin,
        }
    }
}

/// `pkg/ns/Name` split in three, or ros2cli's `Invalid name` error.
pub fn split_type(type_name: &str) -> Result<(&str, &str, &str), CliError> {
    match type_name.split('/').collect::<Vec<_>>()[..] {
        [package, namespace, name] => Ok((package, namespace, name)),
        _ => Err(CliError::new(format!(
            "Invalid name '{type_name}'. Expected three parts separated by '/'"
        ))),
    }
}

/// The definition of `type_name` (`pkg/msg/Name`, `pkg/srv/Name`, `pkg/action/Name`): its file,
/// else the compiled type; the file lookup's error (rosidl_runtime_py's message) when neither.
pub fn resolve(catalog: &Catalog, type_name: &str) -> Result<Definition, CliError> {
    let (package, _, _) = split_type(type_name)?;
    match catalog.index.find_interface(type_name) {
        Ok(path) => Ok(Definition::File {
            package: package.to_owned(),
            path,
        }),
        Err(e) => compiled(type_name).ok_or_else(|| CliError::new(e.to_string())),
    }
}

/// The compiled type `type_name`, as a [`Definition::Described`].
pub fn compiled(type_name: &str) -> Option<Definition> {
    let t = compiled_type(type_name)?;
    let description = (t.describe)();
    let schema = Schema::from_description(&description).ok()?;
    let parts = if t.is_service() {
        vec![
            format!("{type_name}{REQUEST_SUFFIX}"),
            format!("{type_name}{RESPONSE_SUFFIX}"),
        ]
    } else {
        vec![type_name.to_owned()]
    };
    Some(Definition::Described {
        schema,
        parts,
        origin: Origin::Compiled,
    })
}

/// `--from-graph` and its `--timeout`, as `show` and `proto` take them.
#[derive(Debug, clap::Args)]
pub struct TypeSource {
    /// Read the type off a running node (its ~/get_type_description service) instead of the
    /// installed and compiled interfaces: a message type from a node that publishes or
    /// subscribes to it, a service type from a node that serves it.
    #[arg(long)]
    pub from_graph: bool,
    /// With --from-graph: longest wait for each node's answer, in seconds.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 10.0,
        allow_negative_numbers = true,
        value_parser = crate::args::seconds
    )]
    pub timeout: f64,
}

impl TypeSource {
    /// The definition of `type_name`, from the graph or else from `catalog`.
    pub fn definition(
        &self,
        global: &Global,
        catalog: &Catalog,
        type_name: &str,
    ) -> Result<Definition, CliError> {
        if self.from_graph {
            from_graph(global, type_name, Duration::from_secs_f64(self.timeout))
        } else {
            resolve(catalog, type_name)
        }
    }
}

/// The definition of `type_name` as a node in the graph describes it: a message type by a node
/// that publishes or subscribes to it, a service type by a node that serves it.
pub fn from_graph(
    global: &Global,
    type_name: &str,
    timeout: Duration,
) -> Result<Definition, CliError> {
    let (_, namespace, _) = split_type(type_name)?;
    let kind = InterfaceKind::from_namespace(namespace);
    let session = Session::open(global)?;
    let failed = |why: String| CliError::new(format!("Cannot describe '{type_name}': {why}"));
    match kind {
        Some(InterfaceKind::Message) => {
            let description =
                describe::fetch_message(&session.node, &session.graph, type_name, timeout)
                    .map_err(failed)?;
            let schema = Schema::from_description(&description)
                .map_err(|e| failed(format!("its description is not usable: {e}")))?;
            Ok(Definition::Described {
                schema,
                parts: vec![type_name.to_owned()],
                origin: Origin::Graph,
            })
        }
        Some(InterfaceKind::Service) => {
            let services: Vec<String> = session.graph.read(|c| {
                c.service_names_and_types(true)
                    .into_iter()
                    .filter(|(_, types)| types.iter().any(|t| t == type_name))
                    .map(|(name, _)| name)
                    .collect()
            });
            if services.is_empty() {
                return Err(failed("no service in the graph has this type".to_owned()));
            }
            let mut reasons = Vec::new();
            for service in services {
                match describe::fetch(&session.node, &session.graph, &service, type_name, timeout) {
                    Ok(info) => {
                        return Ok(Definition::Described {
                            schema: info.schema().clone(),
                            parts: vec![
                                info.request_type().to_owned(),
                                info.response_type().to_owned(),
                            ],
                            origin: Origin::Graph,
                        })
                    }
                    Err(e) => reasons.push(e),
                }
            }
            Err(failed(reasons.join("; ")))
        }
        _ => Err(failed(
            "only message and service types can be read off the graph".to_owned(),
        )),
    }
}

/// The full description of `root` (a message, or a service's request, or an action's goal)
/// from interface files: the file of each type parsed as it is needed (rosidl_adapter's
/// grammar, [`horus_ros_codegen::msg`]), a type without a file taken from the compiled types.
pub fn describe_files(
    catalog: &Catalog,
    package: &str,
    path: &std::path::Path,
    root: &str,
) -> Result<TypeDescription, CliError> {
    let mut registry = TypeRegistry::new();
    let interface = horus_ros_codegen::msg::parse_file(package, path)
        .map_err(|e| CliError::new(e.to_string()))?;
    registry.add(&interface);
    // Each round loads one more referenced type; a type is loaded at most once.
    let mut loaded = std::collections::BTreeSet::new();
    loop {
        match registry.describe(root) {
            Ok(d) => return Ok(d),
            Err(DescribeError::UnknownReference { referenced, user }) => {
                if !loaded.insert(referenced.clone()) {
                    return Err(CliError::new(format!(
                        "Cannot describe '{root}': type '{referenced}', used by '{user}', is \
                         unknown"
                    )));
                }
                load(catalog, &mut registry, &referenced).map_err(|e| {
                    CliError::new(format!(
                        "Cannot describe '{root}': type '{referenced}', used by '{user}': {}",
                        e.message
                    ))
                })?;
            }
            Err(e) => return Err(CliError::new(format!("Cannot describe '{root}': {e}"))),
        }
    }
}

/// Adds the type `type_name` (`pkg/msg/Name`) to `registry`: its file, else its compiled
/// description.
fn load(catalog: &Catalog, registry: &mut TypeRegistry, type_name: &str) -> Result<(), CliError> {
    let (package, _, _) = split_type(type_name)?;
    match catalog.index.find_interface(type_name) {
        Ok(path) => {
            let interface = horus_ros_codegen::msg::parse_file(package, &path)
                .map_err(|e| CliError::new(e.to_string()))?;
            registry.add(&interface);
            Ok(())
        }
        Err(e) => {
            let t = compiled_type(type_name).ok_or_else(|| CliError::new(e.to_string()))?;
            registry.add_description(&(t.describe)());
            Ok(())
        }
    }
}
