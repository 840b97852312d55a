//! `horus-ros graph`: the whole graph in one document, or (`--watch`) a live, timestamped diff
//! of the nodes and endpoints appearing and vanishing; `graph check`: what makes the graph fail
//! silently. Formats: `docs/cli-json.md`.
//!
//! [`document`] builds the one-shot document, [`watch`] the live diff, [`check`] the findings.

mod check;
mod document;
mod watch;

use std::io::Write;

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};
use document::GraphDoc;
use watch::watch;

/// Arguments of `graph`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Without --watch: one document of every node (with its publishers, subscribers, servers and
clients), every topic (types, publishers and subscriptions with GIDs and QoS) and every service
(types, servers and clients). With --json it is one JSON document (docs/cli-json.md).

With --watch: first the current graph as `+` lines (after discovery settles), then one
timestamped line per change, until Ctrl+C (or SIGTERM), exit status 0:
  2026-11-22T01:23:45.678Z + node /ns/talker
  2026-11-22T01:23:45.679Z + publisher /ns/chatter [std_msgs/msg/String] gid 01.0f.…
  2026-11-22T01:23:47.012Z - service server /add_two_ints [example_interfaces/srv/AddTwoInts] request reader gid 01.0f.…
With --json, one JSON object per line instead.")]
#[command(args_conflicts_with_subcommands = true)]
pub struct GraphArgs {
    /// `graph check`.
    #[command(subcommand)]
    pub command: Option<GraphCommand>,
    /// Print a live, timestamped diff of nodes and endpoints appearing and vanishing until Ctrl+C.
    #[arg(long)]
    pub watch: bool,
    /// Include hidden nodes, topics and services (a name token starting with `_`).
    #[arg(short = 'a', long)]
    pub all: bool,
}

/// The subcommands of `graph`.
#[derive(Debug, clap::Subcommand)]
pub enum GraphCommand {
    /// Find what makes the graph fail silently (QoS and type mismatches, service conventions
    /// that cannot talk, duplicate node names, endpoints of no node, clients with no server);
    /// exit status 1 when anything is found.
    Check(check::CheckArgs),
}

/// Runs `graph`.
pub fn run(global: &Global, args: &GraphArgs) -> Result<(), CliError> {
    if let Some(GraphCommand::Check(check_args)) = &args.command {
        return check::run(global, check_args);
    }
    if args.watch {
        return watch(global, args);
    }
    let source = GraphSource::open(global)?;
    let doc = source.read(|c| GraphDoc::read(c, args.all));
    let domain_id = source.domain_id();
    if global.json {
        names::print_json(&doc.to_json(domain_id))
    } else {
        let mut out = std::io::stdout().lock();
        match out
            .write_all(doc.render(domain_id).as_bytes())
            .and_then(|()| out.flush())
        {
            // A reader that stopped early (`| head`) is not an error.
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                Err(CliError::new(format!("could not write the graph: {e}")))
            }
            _ => Ok(()),
        }
    }
}
