//! `horus-ros service type` (ros2service `verb/type.py`).

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `service type`.
#[derive(Debug, clap::Args)]
pub struct TypeArgs {
    /// Name of the ROS service to get type (e.g. '/add_two_ints').
    pub service_name: String,
    /// Consider hidden services as well (ros2cli's `ros2 service --include-hidden-services`).
    #[arg(long)]
    pub include_hidden_services: bool,
}

/// Runs `service type`: each type of the service on its own line. An unknown service prints
/// nothing and exits 1, as ros2cli does (its verb returns 1 without a message).
pub fn run(global: &Global, args: &TypeArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let services = source.read(|c| c.service_names_and_types(args.include_hidden_services));
    let Some(types) = names::find_types(&services, &args.service_name) else {
        return Err(CliError::new(""));
    };
    if global.json {
        return names::print_json(&names::entry_json(&args.service_name, &types));
    }
    for ty in &types {
        println!("{ty}");
    }
    Ok(())
}
