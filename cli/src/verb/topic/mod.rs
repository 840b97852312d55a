//! `horus-ros topic …`: ros2cli's `ros2 topic` query verbs.

pub mod bw;
pub mod delay;
pub mod echo;
pub mod find;
pub mod hz;
pub mod info;
pub mod list;
pub mod lost;
pub mod message_type;
pub mod pub_;
pub mod publish;
pub mod qos;
pub mod subscribe;
pub mod type_;
pub mod window;

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
        TopicCommand::Echo(a) => echo::run(global, &a),
        TopicCommand::Hz(a) => hz::run(global, &a),
        TopicCommand::Bw(a) => bw::run(global, &a),
        TopicCommand::Delay(a) => delay::run(global, &a),
        TopicCommand::Pub(a) => pub_::run(global, &a),
        TopicCommand::Type(a) => type_::run(global, &a),
        TopicCommand::Find(a) => find::run(global, &a),
    }
}
