//! `horus-ros topic …`: ros2cli's `ros2 topic` query verbs.

pub mod find;
pub mod info;
pub mod list;
pub mod pub_;
pub mod publish;
pub mod type_;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `topic` verbs.
#[derive(Debug, Subcommand)]
pub enum TopicCommand {
    /// Output a list of available topics.
    List(list::ListArgs),
    /// Print information about a topic.
    Info(info::InfoArgs),
    /// Publish a message to a topic.
    #[command(name = "pub")]
    Pub(Box<pub_::PubArgs>),
    /// Print a topic's type.
    Type(type_::TypeArgs),
    /// Output a list of available topics of a given type.
    Find(find::FindArgs),
}

/// Runs a `topic` verb.
pub fn run(global: &Global, command: TopicCommand) -> Result<(), CliError> {
    match command {
        TopicCommand::List(a) => list::run(global, &a),
        TopicCommand::Info(a) => info::run(global, &a),
        TopicCommand::Pub(a) => pub_::run(global, &a),
        TopicCommand::Type(a) => type_::run(global, &a),
        TopicCommand::Find(a) => find::run(global, &a),
    }
}
