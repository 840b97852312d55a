//! `horus-ros service find` (ros2service `verb/find.py`).

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `service find`.
#[derive(Debug, clap::Args)]
pub struct FindArgs {
    /// Name of the ROS service type to filter for (e.g. 'rcl_interfaces/srv/ListParameters').
    pub service_type: String,
    /// Only display the number of services discovered.
    #[arg(short = 'c', long)]
    pub count_services: bool,
    /// Consider hidden services as well.
    #[arg(long)]
    pub include_hidden_services: bool,
}

/// Runs `service find`: the services having the type (one of their types equal to it), sorted.
pub fn run(global: &Global, args: &FindArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let mut services = source.read(|c| c.service_names_and_types(args.include_hidden_services));
    services.retain(|_, types| types.contains(&args.service_type));
    if global.json {
        return names::print_json(&if args.count_services {
            names::count_json(services.len())
        } else {
            names::names_and_types_json(&services)
        });
    }
    if args.count_services {
        println!("{}", services.len());
    } else {
        for name in services.keys() {
            println!("{name}");
        }
    }
    Ok(())
}
