//! `horus-ros interface …`: ros2cli's `ros2 interface` verbs (ros2interface jazzy 0.32), over
//! the interfaces of the packages on `AMENT_PREFIX_PATH` and the types compiled into horus-ros
//! ([`catalog`]); `show` and `proto` also read a type off a running node (`--from-graph`).

pub mod catalog;
pub mod definition;
pub mod list;
pub mod proto;
pub mod show;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `interface` verbs.
#[derive(Debug, Subcommand)]
pub enum InterfaceCommand {
    /// List all interface types available.
    List(list::ListArgs),
    /// Output a list of packages that provide interfaces.
    Packages(list::PackagesArgs),
    /// Output a list of available interface types within one package.
    Package(list::PackageArgs),
    /// Output the interface definition.
    Show(show::ShowArgs),
    /// Output an interface prototype.
    Proto(proto::ProtoArgs),
}

/// Runs an `interface` verb.
pub fn run(global: &Global, command: InterfaceCommand) -> Result<(), CliError> {
    match command {
        InterfaceCommand::List(a) => list::run_list(global, &a),
        InterfaceCommand::Packages(a) => list::run_packages(global, &a),
        InterfaceCommand::Package(a) => list::run_package(global, &a),
        InterfaceCommand::Show(a) => show::run(global, &a),
        InterfaceCommand::Proto(a) => proto::run(global, &a),
    }
}
