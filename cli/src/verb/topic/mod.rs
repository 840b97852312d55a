//! `horus-ros topic …`: ros2cli's `ros2 topic` query verbs.

pub mod bw;
pub mod delay;
pub mod echo;
pub mod hz;
pub mod info;
pub mod list;
pub mod subscribe;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `topic` verbs.
#[derive(Debug, Subcommand)]
pub enum TopicCommand {
    /// Output a list of available topics.
    List(list::ListArgs),
    /// Print information about a topic.
    Info(info::InfoArgs),
    /// Output messages from a topic.
    Echo(Box<echo::EchoArgs>),
    /// Print the average publishing rate to screen.
    Hz(hz::HzArgs),
    /// Display bandwidth used by topic.
    Bw(bw::BwArgs),
    /// Display delay of topic from timestamp in header.
    Delay(delay::DelayArgs),
}

/// Runs a `topic` verb.
pub fn run(global: &Global, command: TopicCommand) -> Result<(), CliError> {
    match command {
        TopicCommand::List(a) => list::run(global, &a),
        TopicCommand::Info(a) => info::run(global, &a),
        TopicCommand::Echo(a) => echo::run(global, &a),
        TopicCommand::Hz(a) => hz::run(global, &a),
        TopicCommand::Bw(a) => bw::run(global, &a),
        TopicCommand::Delay(a) => delay::run(global, &a),
    }
}
