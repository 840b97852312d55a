//! A program that never looks at shutdown: it serves `/plain_add` (AddTwoInts) on the process's
//! default node, then blocks for good. Stopped by SIGINT (Ctrl+C) or SIGTERM, the default signal
//! handling of its context still says goodbye — the DDS participant is deleted, so every peer's
//! graph loses the node at once — and the process then ends as signalled (exit status 130 / 143
//! in a shell), as it would have without horus-ros.
//!
//! With `--no-signal-handlers` it opts out (with
//! `signal_handler::set_default_signal_handler_options`, since the default node's context is built
//! inside the library; a context of its own would take `ContextBuilder::signal_handler`): a signal
//! then ends it the default way, and peers keep seeing the node until its DDS lease runs out.
//!
//! ```text
//! cargo run -p horus-ros-services --example plain_server [-- --no-signal-handlers]
//! ```
//!
//! It prints `serving /plain_add on <node>` once the server is up. The domain comes from
//! `ROS_DOMAIN_ID`.

use std::io::Write;

use horus_ros_rmw::signal_handler::{self, SignalHandlerOptions};
use horus_ros_services::prelude::*;

fn main() -> Result<()> {
    match std::env::args().nth(1).as_deref() {
        None => {}
        Some("--no-signal-handlers") => {
            signal_handler::set_default_signal_handler_options(SignalHandlerOptions::None);
        }
        Some(other) => {
            eprintln!("unexpected argument: {other}\nusage: plain_server [--no-signal-handlers]");
            std::process::exit(2);
        }
    }
    let server = ServiceServer::<AddTwoInts>::builder()
        .name("/plain_add")
        .on_request(|req| {
            Ok(AddTwoIntsResponse {
                sum: req.a.wrapping_add(req.b),
            })
        })
        .build()?;
    let node = horus_ros_services::default_node()?;
    println!(
        "serving {} on {}",
        server.name(),
        node.fully_qualified_name()
    );
    std::io::stdout().flush().ok();
    loop {
        std::thread::park();
    }
}
