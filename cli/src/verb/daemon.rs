//! `horus-ros daemon start|stop|status` (ros2cli `verb/daemon/{start,stop,status}.py`, Jazzy):
//! the daemon that keeps the graph discovered for the query verbs (see `crate::daemon`).

use std::time::{Duration, Instant};

use clap::Subcommand;
use serde_json::json;

use crate::daemon::client::{self, ClientError};
use crate::daemon::protocol::{Request, Response, Status};
use crate::daemon::spawn::{spawn, Spawned};
use crate::daemon::{server, DaemonKey, DEFAULT_IDLE_TIMEOUT, START_STOP_TIMEOUT};
use crate::verb::names;
use crate::{CliError, Global};

/// The `daemon` verbs.
#[derive(Debug, Subcommand)]
#[command(after_help = "\
One daemon runs per user, domain, backend and discovery settings (ROS_AUTOMATIC_DISCOVERY_RANGE,
ROS_STATIC_PEERS, ROS_LOCALHOST_ONLY, CYCLONEDDS_URI on Cyclone DDS): `start`, `stop` and
`status` act on the one these options and this environment name. `node list|info`,
`topic list|info`, `service list|type|find|info` and `graph` answer from its graph, and start it
when it does not run, as ros2cli does (--no-daemon: neither; discover directly). It stops by
itself after --idle-timeout seconds without such a query.")]
pub enum DaemonCommand {
    /// Start the daemon if it isn't running.
    Start(StartArgs),
    /// Stop the daemon if it is running.
    Stop,
    /// Output the status of the daemon.
    Status,
    /// The daemon process itself (what `daemon start` starts).
    #[command(name = "_run", hide = true)]
    Run(RunArgs),
}

/// Arguments of `daemon start`.
#[derive(Debug, clap::Args)]
pub struct StartArgs {
    /// Print debug messages (the daemon's log goes to this terminal's stderr, at level info
    /// unless RUST_LOG says otherwise).
    #[arg(short, long)]
    pub debug: bool,
    /// Shutdown the daemon after N seconds of inactivity (no query answered).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_IDLE_TIMEOUT.as_secs())]
    pub idle_timeout: u64,
}

/// Arguments of `daemon _run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Shutdown after N seconds of inactivity.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_IDLE_TIMEOUT.as_secs())]
    pub idle_timeout: u64,
}

/// Runs a `daemon` verb.
pub fn run(global: &Global, command: DaemonCommand) -> Result<(), CliError> {
    match command {
        DaemonCommand::Start(args) => start(global, &args),
        DaemonCommand::Stop => stop(global),
        DaemonCommand::Status => status(global),
        DaemonCommand::Run(args) => server::run(global, Duration::from_secs(args.idle_timeout)),
    }
}

/// The daemon's status as `--json` prints it.
fn status_json(status: &Status) -> serde_json::Value {
    json!({
        "running": true,
        "socket": status.key.socket_name(),
        "pid": status.pid,
        "node_name": status.node_name,
        "domain_id": status.key.domain_id,
        "backend": status.key.backend,
        "discovery_range": status.key.discovery_range,
        "static_peers": status.key.static_peers,
        "backend_environment": status.key.backend_environment,
        "idle_timeout_s": status.idle_timeout_s,
        "uptime_s": status.uptime_s,
    })
}

/// An error of a daemon that holds the socket but cannot be used.
fn unusable(e: ClientError) -> CliError {
    CliError::new(format!("{e}"))
}

/// `daemon status`: whether the daemon runs (with `--json`: its settings too).
fn status(global: &Global) -> Result<(), CliError> {
    let key = DaemonKey::of(global)?;
    match client::status(&key).map_err(unusable)? {
        Some(status) if global.json => names::print_json(&status_json(&status)),
        Some(_) => {
            println!("The daemon is running");
            Ok(())
        }
        None if global.json => names::print_json(&json!({
            "running": false,
            "socket": key.socket_name(),
        })),
        None => {
            println!("The daemon is not running");
            Ok(())
        }
    }
}

/// `daemon stop`: asks the daemon to stop and waits until it has exited.
fn stop(global: &Global) -> Result<(), CliError> {
    let key = DaemonKey::of(global)?;
    let stopped = match client::connect(&key).map_err(unusable)? {
        None => false,
        Some(mut connection) => {
            let deadline = Instant::now() + START_STOP_TIMEOUT;
            match connection
                .ask(&key, Request::Shutdown, deadline)
                .map_err(unusable)?
            {
                Response::ShuttingDown => {}
                _ => {
                    return Err(unusable(ClientError::Unexpected {
                        pid: connection.pid,
                    }))
                }
            }
            if !connection.wait_gone(deadline) {
                return Err(CliError::new(format!(
                    "Timed out waiting for daemon to shutdown (pid {})",
                    connection.pid
                )));
            }
            true
        }
    };
    if global.json {
        return names::print_json(&json!({ "stopped": stopped }));
    }
    println!(
        "{}",
        if stopped {
            "The daemon has been stopped"
        } else {
            "The daemon is not running"
        }
    );
    Ok(())
}

/// `daemon start`: starts the daemon unless it runs, and waits until it serves.
fn start(global: &Global, args: &StartArgs) -> Result<(), CliError> {
    let key = DaemonKey::of(global)?;
    let (started, pid) = match client::status(&key).map_err(unusable)? {
        Some(status) => (false, status.pid),
        None => match spawn(&key, Duration::from_secs(args.idle_timeout), args.debug)
            .map_err(|e| CliError::new(e.to_string()))?
        {
            Spawned::Ready(pid) => (true, pid),
            // Another `daemon start` won the socket meanwhile.
            Spawned::AlreadyRunning => match client::status(&key).map_err(unusable)? {
                Some(status) => (false, status.pid),
                None => return Err(CliError::new("The daemon stopped as it was started")),
            },
        },
    };
    if global.json {
        return names::print_json(&json!({ "started": started, "pid": pid }));
    }
    println!(
        "{}",
        if started {
            "The daemon has been started"
        } else {
            "The daemon is already running"
        }
    );
    Ok(())
}
