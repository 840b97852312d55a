//! `horus-ros router`: a Zenoh router, as rmw_zenoh_cpp's `rmw_zenohd` (rmw_zenoh 0.2.10
//! `src/zenohd/main.cpp`): the zenoh crate in router mode with rmw_zenoh's default router
//! configuration (`config/DEFAULT_RMW_ZENOH_ROUTER_CONFIG.json5`: listen on `tcp/[::]:7447`,
//! multicast scouting off, gossip on), or the file `ZENOH_ROUTER_CONFIG_URI` names, with
//! `ZENOH_CONFIG_OVERRIDE` applied. Prints one ready line, then runs until SIGINT or SIGTERM.
//!
//! Shared memory is off, as in rmw_zenohd's configuration; the sessions' switch turns it on
//! here too (`ZENOH_CONFIG_OVERRIDE='transport/shared_memory/enabled=true'`): messages of
//! same-host sessions that cross the router then stay in shared memory (zenoh negotiates it per
//! link; sessions linked directly need not cross it), and go as bytes if the router leaves it
//! off (horus-ros-rmw's `tests/zenoh_shm.rs`).

use std::sync::mpsc;

use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use zenoh::Wait;

use crate::CliError;

/// `horus-ros router` takes no arguments: the environment configures it, as rmw_zenohd.
#[derive(Debug, clap::Args)]
pub struct RouterArgs {}

/// Runs the router until SIGINT or SIGTERM.
pub fn run(_args: &RouterArgs) -> Result<(), CliError> {
    let get = |k: &str| std::env::var(k).ok();
    let config =
        config::config(ConfigKind::Router, get).map_err(|e| CliError::new(e.to_string()))?;
    let listen = config
        .get_json("listen/endpoints")
        .unwrap_or_else(|_| "[]".to_owned());
    let (stop_tx, stop_rx) = mpsc::channel();
    ctrlc::set_handler(move || {
        let _ = stop_tx.send(());
    })
    .map_err(|e| CliError::new(format!("router: could not handle SIGINT/SIGTERM: {e}")))?;
    let session = zenoh::open(config)
        .wait()
        .map_err(|e| CliError::new(format!("router: could not start the Zenoh router: {e}")))?;
    // rmw_zenohd prints "Started Zenoh router with id <zid>."
    println!(
        "Started Zenoh router with id {} (listening on {listen}).",
        session.zid()
    );
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let _ = stop_rx.recv();
    if let Err(e) = session.close().wait() {
        tracing::debug!("router: closing: {e}");
    }
    Ok(())
}
