//! `horus-ros topic …`: ros2cli's `ros2 topic` query verbs.

pub mod info;
pub mod list;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `topic` verbs.
#[derive(Debug, Subcommand)]
pub enum TopicCommand {
    /// Output a list of available topics.
    List(list::ListArgs),
    /// Print information about a topic.
    Info(info::InfoArgs),
}

/// Runs a `topic` verb.
pub fn run(global: &Global, command: TopicCommand) -> Result<(), CliError> {
    match command {
        TopicCommand::List(a) => list::run(global, &a),
        TopicCommand::Info(a) => info::run(global, &a),
    }
}
