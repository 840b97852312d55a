//! `horus-ros action …`: ros2cli's `ros2 action` verbs (ros2action 0.32, Jazzy). Actions are
//! names the graph derives from their feedback topics (`horus_ros_graph`'s action queries, as
//! rcl_action's `graph.c`).

pub mod info;
pub mod list;
pub mod send_goal;
pub mod type_;

use clap::Subcommand;

use crate::{CliError, Global};

/// The `action` verbs.
#[derive(Debug, Subcommand)]
pub enum ActionCommand {
    /// Output a list of action names.
    List(list::ListArgs),
    /// Print information about an action.
    Info(info::InfoArgs),
    /// Print a action's type.
    Type(type_::TypeArgs),
    /// Send an action goal.
    #[command(name = "send_goal")]
    SendGoal(send_goal::SendGoalArgs),
}

/// Runs an `action` verb.
pub fn run(global: &Global, command: ActionCommand) -> Result<(), CliError> {
    match command {
        ActionCommand::List(a) => list::run(global, &a),
        ActionCommand::Info(a) => info::run(global, &a),
        ActionCommand::Type(a) => type_::run(global, &a),
        ActionCommand::SendGoal(a) => send_goal::run(global, &a),
    }
}
