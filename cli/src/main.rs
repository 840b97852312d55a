//! `horus-ros`: the ROS 2 graph from the shell.

mod verb;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// horus-ros: join a ROS 2 (Jazzy) graph over DDS and work with it from the shell.
#[derive(Debug, Parser)]
#[command(name = "horus-ros", version, about, long_about = None)]
struct Cli {
    /// DDS domain to join (default: ROS_DOMAIN_ID, else 0).
    #[arg(long, global = true, value_name = "ID")]
    domain_id: Option<u32>,

    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Start a node, show what it announces on ros_discovery_info, and exit.
    Demo(verb::demo::DemoArgs),
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(args) => verb::demo::run(cli.domain_id, &args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}
