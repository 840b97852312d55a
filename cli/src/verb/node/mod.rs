//! `horus-ros node …`: ros2cli's `ros2 node` verbs.

pub mod info;
pub mod list;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `node` verbs.
#[derive(Debug, Subcommand)]
pub enum NodeCommand {
    /// Output a list of available nodes.
    List(list::ListArgs),
    /// Output information about a node.
    Info(info::InfoArgs),
}

/// Runs a `node` verb.
pub fn run(global: &Global, command: NodeCommand) -> Result<(), CliError> {
    match command {
        NodeCommand::List(a) => list::run(global, &a),
        NodeCommand::Info(a) => info::run(global, &a),
    }
}
