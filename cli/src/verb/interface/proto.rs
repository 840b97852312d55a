//! `horus-ros interface proto` (ros2interface jazzy `verb/proto.py`, `api.interface_to_yaml`):
//! the YAML of a default-constructed message (a service's request, an action's goal), as
//! rosidl_runtime_py `message_to_yaml` writes it, between double quotes unless `--no-quotes`.

use horus_ros_codegen::ament::InterfaceKind;

use super::catalog::Catalog;
use super::definition::{self, split_type, Definition, TypeSource};
use crate::dynamic::convert::{to_ordereddict, ConvertOptions};
use crate::dynamic::{json, pyyaml, Schema};
use crate::verb::names::print_json;
use crate::{CliError, Global};

/// Arguments of `interface proto`.
#[derive(Debug, clap::Args)]
pub struct ProtoArgs {
    /// Show an interface definition (e.g. 'example_interfaces/msg/String').
    #[arg(value_name = "TYPE")]
    pub type_name: String,
    /// if true output has no outer quotes.
    #[arg(long)]
    pub no_quotes: bool,
    /// Where the type comes from.
    #[command(flatten)]
    pub source: TypeSource,
}

/// The type ros2cli instantiates for `type_name`: a message itself, a service's `_Request`, an
/// action's `_Goal`.
fn instance_type(type_name: &str) -> Result<String, CliError> {
    let (_, namespace, _) = split_type(type_name)?;
    Ok(match InterfaceKind::from_namespace(namespace) {
        Some(InterfaceKind::Service) => format!("{type_name}_Request"),
        Some(InterfaceKind::Action) => format!("{type_name}_Goal"),
        _ => type_name.to_owned(),
    })
}

/// Runs `interface proto`.
pub fn run(global: &Global, args: &ProtoArgs) -> Result<(), CliError> {
    let type_name = args.type_name.as_str();
    let root = instance_type(type_name)?;
    let catalog = Catalog::from_env();
    let definition = args.source.definition(global, &catalog, type_name)?;
    let schema = match definition {
        Definition::File { package, path } => {
            let description = definition::describe_files(&catalog, &package, &path, &root)?;
            Schema::from_description(&description)
                .map_err(|e| CliError::new(format!("Cannot describe '{type_name}': {e}")))?
        }
        Definition::Described { schema, .. } => schema,
    };
    let value = schema
        .default_value(&root)
        .map_err(|e| CliError::new(format!("Cannot describe '{type_name}': {e}")))?;
    if global.json {
        return print_json(&json::to_json(&schema, &root, &value));
    }
    let yaml = pyyaml::dump(
        &to_ordereddict(&schema, &root, &value, ConvertOptions::default()),
        false,
    );
    if args.no_quotes {
        println!("{yaml}");
    } else {
        println!("\"{yaml}\"");
    }
    Ok(())
}
