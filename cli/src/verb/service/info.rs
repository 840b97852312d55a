//! `horus-ros service info` (ros2service `verb/info.py`; `-v` as Rolling's).

use horus_ros_graph::{GraphCache, ServiceEndpointInfo};
use serde_json::{json, Value};

use horus_ros_graph::Graph;

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `service info`.
#[derive(Debug, clap::Args)]
pub struct InfoArgs {
    /// Name of the ROS service to get info (e.g. '/add_two_ints').
    pub service_name: String,
    /// Prints detailed information like the node name, type, GIDs and QoS of every server and
    /// client.
    #[arg(short = 'v', long)]
    pub verbose: bool,
    /// Consider hidden services as well (ros2cli's `ros2 service --include-hidden-services`).
    #[arg(long)]
    pub include_hidden_services: bool,
}

/// Runs `service info`.
pub fn run(global: &Global, args: &InfoArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let info = source
        .read(|c| read(c, &args.service_name, args.include_hidden_services))
        .ok_or_else(|| unknown(&args.service_name))??;
    if global.json {
        return names::print_json(&info.to_json(&args.service_name));
    }
    print!("{}", info.render(args.verbose));
    Ok(())
}

/// What `service info` prints for `service` (an error for an unknown service): without
/// `verbose` Jazzy's three lines, with it Rolling's `-v` output. Hidden services are unknown,
/// as in ros2cli without `--include-hidden-services`.
pub fn render(graph: &Graph, service: &str, verbose: bool) -> Result<String, CliError> {
    let info = graph
        .read(|c| read(c, service, false))
        .ok_or_else(|| unknown(service))??;
    Ok(info.render(verbose))
}

fn unknown(service: &str) -> CliError {
    CliError::new(format!("Unknown service '{service}'"))
}

/// Everything `service info` shows, read from the graph at once.
struct ServiceInfo {
    types: Vec<String>,
    clients_count: usize,
    services_count: usize,
    clients: Vec<ServiceEndpointInfo>,
    servers: Vec<ServiceEndpointInfo>,
}

fn read(
    cache: &GraphCache,
    service: &str,
    include_hidden: bool,
) -> Option<Result<ServiceInfo, CliError>> {
    let types = names::find_types(&cache.service_names_and_types(include_hidden), service)?;
    let endpoints = cache
        .clients_info_by_service(service, false)
        .and_then(|clients| Ok((clients, cache.servers_info_by_service(service, false)?)));
    Some(
        endpoints
            .map(|(clients, servers)| ServiceInfo {
                types,
                clients_count: cache.count_clients(service),
                services_count: cache.count_services(service),
                clients,
                servers,
            })
            .map_err(CliError::from),
    )
}

impl ServiceInfo {
    /// ros2cli's text. With `verbose` every line after `Type:` ends with a blank line and each
    /// client (then each server) follows its count as an rclpy `ServiceEndpointInfo` block.
    fn render(&self, verbose: bool) -> String {
        let end = if verbose { "\n\n" } else { "\n" };
        let mut out = format!("Type: {}\n", names::type_str(&self.types));
        out.push_str(&format!("Clients count: {}{end}", self.clients_count));
        if verbose {
            for client in &self.clients {
                out.push_str(&format!("{client}{end}"));
            }
        }
        out.push_str(&format!("Services count: {}{end}", self.services_count));
        if verbose {
            for server in &self.servers {
                out.push_str(&format!("{server}{end}"));
            }
        }
        out
    }

    fn to_json(&self, service: &str) -> Value {
        json!({
            "name": service,
            "types": self.types,
            "clients_count": self.clients_count,
            "services_count": self.services_count,
            "clients": self.clients.iter().map(names::service_endpoint_json).collect::<Vec<_>>(),
            "servers": self.servers.iter().map(names::service_endpoint_json).collect::<Vec<_>>(),
        })
    }
}
