//! A Zenoh router in a process of its own, for tests that put one on each (simulated) host: what
//! `horus-ros router` runs (rmw_zenoh's `rmw_zenohd`), the zenoh crate in router mode with the
//! configuration `horus_ros_rmw::zenoh::config` makes for a router (rmw_zenoh's default router
//! configuration, or the file `ZENOH_ROUTER_CONFIG_URI` names, then `ZENOH_CONFIG_OVERRIDE`).
//! It prints `ready <zid>` once the router runs, and ends when its standard input closes.
//!
//! usage: horus_zenoh_router

use std::io::{Read, Write};

use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use zenoh::Wait;

fn main() -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let config = config::config(ConfigKind::Router, |k| std::env::var(k).ok())?;
    let router = zenoh::open(config).wait()?;
    let mut out = std::io::stdout();
    writeln!(out, "ready {}", router.zid())?;
    out.flush()?;
    // Routes until its standard input closes (or it is killed).
    let _ = std::io::stdin().read(&mut [0u8; 1]);
    router.close().wait()?;
    Ok(())
}
