//! `horus-ros service …`: ros2cli's `ros2 service` verbs.

pub mod bench;
pub mod call;
pub mod echo;
pub mod find;
pub mod info;
pub mod list;
pub mod type_;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `service` verbs.
#[derive(Debug, Subcommand)]
pub enum ServiceCommand {
    /// Output a list of available services.
    List(list::ListArgs),
    /// Output a service's type.
    Type(type_::TypeArgs),
    /// Output a list of available services of a given type.
    Find(find::FindArgs),
    /// Print information about a service (with -v: every server and client, GIDs, QoS).
    Info(info::InfoArgs),
    /// Call a service.
    Call(call::CallArgs),
    /// Echo a service: print the events of servers and clients with introspection on (with
    /// --passive: its requests and replies, paired, without introspection).
    Echo(echo::EchoArgs),
    /// Measure a live server: round trip p50/p99/max and calls/s, with one or more clients.
    Bench(bench::BenchArgs),
}

/// Runs a `service` verb.
pub fn run(global: &Global, command: ServiceCommand) -> Result<(), CliError> {
    match command {
        ServiceCommand::List(a) => list::run(global, &a),
        ServiceCommand::Type(a) => type_::run(global, &a),
        ServiceCommand::Find(a) => find::run(global, &a),
        ServiceCommand::Info(a) => info::run(global, &a),
        ServiceCommand::Call(a) => call::run(global, &a),
        ServiceCommand::Echo(a) => echo::run(global, &a),
        ServiceCommand::Bench(a) => bench::run(global, &a),
    }
}
