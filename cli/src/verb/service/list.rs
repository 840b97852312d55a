//! `horus-ros service list` (ros2service `verb/list.py`).

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `service list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Additionally show the service type.
    #[arg(short = 't', long)]
    pub show_types: bool,
    /// Only display the number of services discovered.
    #[arg(short = 'c', long)]
    pub count_services: bool,
    /// Consider hidden services as well.
    #[arg(long)]
    pub include_hidden_services: bool,
}

/// Runs `service list`.
pub fn run(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let services = source.read(|c| c.service_names_and_types(args.include_hidden_services));
    if global.json {
        return names::print_json(&if args.count_services {
            names::count_json(services.len())
        } else {
            names::names_and_types_json(&services)
        });
    }
    print!("{}", render(&services, args));
    Ok(())
}

/// ros2cli's text: the count with `-c`, else one service a line, `/name [types]` with `-t`.
fn render(services: &horus_ros_graph::NamesAndTypes, args: &ListArgs) -> String {
    if args.count_services {
        return format!("{}\n", services.len());
    }
    let mut out = String::new();
    for (name, types) in services {
        out.push_str(name);
        if args.show_types {
            let types: Vec<&str> = types.iter().map(String::as_str).collect();
            out.push_str(&format!(" [{}]", types.join(", ")));
        }
        out.push('\n');
    }
    out
}
