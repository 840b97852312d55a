//! `horus-ros interface list`, `packages` and `package` (ros2interface jazzy `verb/list.py`,
//! `verb/packages.py`, `verb/package.py`).

use horus_ros_codegen::ament::InterfaceKind;
use serde_json::{json, Value};

use super::catalog::{ByPackage, Catalog};
use crate::verb::names::print_json;
use crate::{CliError, Global};

/// Arguments of `interface list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Print out only the message types.
    #[arg(short = 'm', long)]
    pub only_msgs: bool,
    /// Print out only the service types.
    #[arg(short = 's', long)]
    pub only_srvs: bool,
    /// Print out only the action types.
    #[arg(short = 'a', long)]
    pub only_actions: bool,
}

/// Arguments of `interface packages`.
#[derive(Debug, clap::Args)]
pub struct PackagesArgs {
    /// Only list packages that generate messages.
    #[arg(short = 'm', long)]
    pub only_msgs: bool,
    /// Only list packages that generate services.
    #[arg(short = 's', long)]
    pub only_srvs: bool,
    /// Only list packages that generate actions.
    #[arg(short = 'a', long)]
    pub only_actions: bool,
}

/// Arguments of `interface package`.
#[derive(Debug, clap::Args)]
pub struct PackageArgs {
    /// Print out only the message types.
    #[arg(short = 'm', long)]
    pub only_msgs: bool,
    /// Print out only the service types.
    #[arg(short = 's', long)]
    pub only_srvs: bool,
    /// Print out only the action types.
    #[arg(short = 'a', long)]
    pub only_actions: bool,
    /// Name of the ROS package (e.g. 'example_interfaces').
    pub package_name: String,
}

/// The kinds the flags ask for, in ros2cli's order (messages, services, actions); all three
/// when none is given.
fn kinds(msgs: bool, srvs: bool, actions: bool) -> Vec<InterfaceKind> {
    let picked: Vec<InterfaceKind> = [
        (msgs, InterfaceKind::Message),
        (srvs, InterfaceKind::Service),
        (actions, InterfaceKind::Action),
    ]
    .into_iter()
    .filter_map(|(on, k)| on.then_some(k))
    .collect();
    if picked.is_empty() {
        vec![
            InterfaceKind::Message,
            InterfaceKind::Service,
            InterfaceKind::Action,
        ]
    } else {
        picked
    }
}

/// The section title of a kind in `interface list`.
fn title(kind: InterfaceKind) -> &'static str {
    match kind {
        InterfaceKind::Message => "Messages",
        InterfaceKind::Service => "Services",
        InterfaceKind::Action => "Actions",
    }
}

/// The JSON key of a kind.
fn key(kind: InterfaceKind) -> &'static str {
    match kind {
        InterfaceKind::Message => "messages",
        InterfaceKind::Service => "services",
        InterfaceKind::Action => "actions",
    }
}

/// `pkg/msg/Name` for every interface, sorted by package then name (as `print_messages`).
fn full_names(by_package: &ByPackage) -> Vec<String> {
    by_package
        .iter()
        .flat_map(|(package, names)| names.iter().map(move |n| format!("{package}/{n}")))
        .collect()
}

/// ros2interface `print_messages` / `print_services` / `print_actions`: a title line, then
/// `    pkg/msg/Name` lines.
fn render_list(sections: &[(InterfaceKind, Vec<String>)]) -> String {
    let mut out = String::new();
    for (kind, names) in sections {
        out.push_str(title(*kind));
        out.push_str(":\n");
        for n in names {
            out.push_str("    ");
            out.push_str(n);
            out.push('\n');
        }
    }
    out
}

/// Runs `interface list`.
pub fn run_list(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    let catalog = Catalog::from_env();
    let sections: Vec<(InterfaceKind, Vec<String>)> =
        kinds(args.only_msgs, args.only_srvs, args.only_actions)
            .into_iter()
            .map(|k| (k, full_names(&catalog.of_kind(k))))
            .collect();
    if global.json {
        let map: serde_json::Map<String, Value> = sections
            .iter()
            .map(|(k, names)| (key(*k).to_owned(), json!(names)))
            .collect();
        return print_json(&Value::Object(map));
    }
    print!("{}", render_list(&sections));
    Ok(())
}

/// Runs `interface packages`: every package with interfaces; with `-m`, `-s` or `-a` (the
/// first given, as ros2cli's `if / elif`) those with messages, services or actions.
pub fn run_packages(global: &Global, args: &PackagesArgs) -> Result<(), CliError> {
    let catalog = Catalog::from_env();
    let packages: Vec<String> = if args.only_msgs {
        catalog
            .of_kind(InterfaceKind::Message)
            .into_keys()
            .collect()
    } else if args.only_srvs {
        catalog
            .of_kind(InterfaceKind::Service)
            .into_keys()
            .collect()
    } else if args.only_actions {
        catalog.of_kind(InterfaceKind::Action).into_keys().collect()
    } else {
        catalog.packages().into_iter().collect()
    };
    if global.json {
        return print_json(&json!(packages));
    }
    for p in packages {
        println!("{p}");
    }
    Ok(())
}

/// Runs `interface package`: `pkg/msg/Name` lines. ros2cli prints a package's interfaces in
/// the order of a Python set (hash order, which changes from run to run); they are sorted here.
/// With `-m`, `-s`, `-a`: the messages, then the services, then the actions asked for.
pub fn run_package(global: &Global, args: &PackageArgs) -> Result<(), CliError> {
    let catalog = Catalog::from_env();
    let picked = if args.only_msgs || args.only_srvs || args.only_actions {
        kinds(args.only_msgs, args.only_srvs, args.only_actions)
    } else {
        Vec::new()
    };
    let names: Vec<String> = catalog
        .package(&args.package_name, &picked)
        .map_err(|e| CliError::new(e.to_string()))?
        .into_iter()
        .map(|n| format!("{}/{n}", args.package_name))
        .collect();
    if global.json {
        return print_json(&json!(names));
    }
    for n in names {
        println!("{n}");
    }
    Ok(())
}
