//! `horus-ros`: the ROS 2 graph from the shell — ros2cli's service, node and topic verbs with
//! the same output, plus what ros2cli lacks (`service info -v` on Jazzy graphs, `graph --watch`,
//! `--json` everywhere, service calls without the package installed).

mod args;
mod daemon;
mod error;
mod session;
mod settle;
mod verb;

use std::io::IsTerminal;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
// Types known at run time: the dynamic crate (its decoders are what the fuzz targets call).
use horus_ros_dynamic as dynamic;

use error::CliError;

const EXAMPLES: &str = "\
Examples:
  horus-ros service list -t
  horus-ros service info /add_two_ints -v
  horus-ros service call /add_two_ints example_interfaces/srv/AddTwoInts '{a: 2, b: 3}'
  horus-ros node list
  horus-ros node info /talker
  horus-ros topic info /chatter -v
  horus-ros interface show geometry_msgs/msg/PoseStamped
  horus-ros graph --watch
  horus-ros --json service list
  horus-ros daemon start

Every command joins the DDS domain (ROS_DOMAIN_ID, or --domain-id) as a hidden node and waits for
discovery until the graph is complete: every ROS node announced, with its endpoints. The query
commands (node/topic/service list and info, service type/find, graph) ask the daemon, a
background process that keeps the graph discovered, and start it when it is not running, as
ros2cli does: the next queries answer at once (--no-daemon: neither; discover directly;
`horus-ros daemon stop` ends it). Logs: RUST_LOG=debug.";

/// horus-ros: join a ROS 2 (Jazzy) graph over DDS and work with it from the shell.
#[derive(Debug, Parser)]
#[command(name = "horus-ros", version, about, after_help = EXAMPLES)]
pub struct Cli {
    #[command(flatten)]
    global: Global,

    #[command(subcommand)]
    command: Command,
}

/// Options every command takes.
#[derive(Debug, Clone, clap::Args)]
pub struct Global {
    /// DDS domain to join (default: ROS_DOMAIN_ID, else 0).
    #[arg(
        long,
        global = true,
        value_name = "ID",
        allow_negative_numbers = true,
        value_parser = args::domain_id
    )]
    pub domain_id: Option<u32>,

    /// Discovery wait, in seconds (as ros2cli's --spin-time): the answer comes once the graph is
    /// complete and quiet; while a ROS node or endpoint is known to be missing, the wait goes on
    /// up to what a real Fast DDS node needs (4.6 s), or this if longer. Through the daemon: the
    /// same wait on its graph.
    #[arg(
        long,
        global = true,
        value_name = "SECONDS",
        default_value_t = 0.5,
        allow_negative_numbers = true,
        value_parser = args::seconds
    )]
    pub spin_time: f64,

    /// Do not use nor start the daemon (`horus-ros daemon`): discover the graph directly.
    #[arg(long, global = true)]
    pub no_daemon: bool,

    /// Print the result as JSON (query and daemon commands).
    #[arg(long, global = true)]
    pub json: bool,

    /// DDS implementation to join with (default: HORUS_ROS_BACKEND, else as RMW_IMPLEMENTATION
    /// says).
    ///
    /// Without this option, HORUS_ROS_BACKEND chooses; when that is unset or empty too,
    /// RMW_IMPLEMENTATION does, as it does for rcl: rmw_cyclonedds_cpp means cyclone;
    /// rmw_fastrtps_cpp, rmw_fastrtps_dynamic_cpp, unset or empty (Jazzy's default is
    /// rmw_fastrtps_cpp) mean rustdds; rmw_zenoh_cpp means zenoh; any other rmw implementation
    /// is an error.
    #[arg(
        long,
        global = true,
        value_parser = BackendParser,
        ignore_case = true,
        value_name = "BACKEND",
        env = "HORUS_ROS_BACKEND"
    )]
    backend: Option<BackendChoice>,
}

impl Global {
    /// The backend `--backend` (or a non-blank HORUS_ROS_BACKEND) names; `None` leaves the choice
    /// to the environment, as the library makes it.
    pub fn backend(&self) -> Option<horus_ros_rmw::Backend> {
        self.backend.and_then(|c| c.0).map(Into::into)
    }
}

/// A parsed `--backend`: `None` for an empty or blank value (an empty HORUS_ROS_BACKEND, which
/// clap passes on as a value, means "unset" as it does for the library).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct BackendChoice(Option<BackendArg>);

/// Parses `--backend` as [`BackendArg`] (trimmed, case-insensitive), a blank value as
/// `BackendChoice(None)`.
#[derive(Debug, Clone, Copy)]
struct BackendParser;

impl clap::builder::TypedValueParser for BackendParser {
    type Value = BackendChoice;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<Self::Value, clap::Error> {
        let trimmed = value.to_str().map(str::trim);
        if trimmed == Some("") {
            return Ok(BackendChoice(None));
        }
        let value = trimmed.map_or(value, std::ffi::OsStr::new);
        clap::builder::EnumValueParser::<BackendArg>::new()
            .parse_ref(cmd, arg, value)
            .map(|b| BackendChoice(Some(b)))
    }

    fn possible_values(
        &self,
    ) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        use clap::ValueEnum;
        Some(Box::new(
            BackendArg::value_variants()
                .iter()
                .filter_map(ValueEnum::to_possible_value),
        ))
    }
}

/// The values of `--backend` (the names `HORUS_ROS_BACKEND` takes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BackendArg {
    /// RustDDS, pure Rust: calls and serves both rmw_fastrtps and rmw_cyclonedds services.
    Rustdds,
    /// Cyclone DDS, as rmw_cyclonedds_cpp (USER_DATA, ROS_STATIC_PEERS, CYCLONEDDS_URI); calls
    /// and serves rmw_cyclonedds services only.
    #[value(alias = "cyclonedds")]
    Cyclone,
    /// Zenoh, as rmw_zenoh_cpp (liveliness tokens, ZENOH_SESSION_CONFIG_URI,
    /// ZENOH_CONFIG_OVERRIDE); needs a router (`horus-ros router`); topics only so far.
    Zenoh,
}

impl From<BackendArg> for horus_ros_rmw::Backend {
    fn from(b: BackendArg) -> Self {
        match b {
            BackendArg::Rustdds => Self::RustDds,
            BackendArg::Cyclone => Self::Cyclone,
            BackendArg::Zenoh => Self::Zenoh,
        }
    }
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Inspect and call services.
    #[command(subcommand)]
    Service(verb::service::ServiceCommand),
    /// Inspect nodes.
    #[command(subcommand)]
    Node(verb::node::NodeCommand),
    /// Inspect topics.
    #[command(subcommand)]
    Topic(verb::topic::TopicCommand),
    /// Inspect actions and send goals.
    #[command(subcommand)]
    Action(verb::action::ActionCommand),
    /// Manage the lifecycle of managed nodes (`ros2 lifecycle`: nodes, list, get, set).
    #[command(subcommand)]
    Lifecycle(verb::lifecycle::LifecycleCommand),
    /// Get, set, list, describe, dump, load and delete a node's parameters.
    #[command(subcommand)]
    Param(verb::param::ParamCommand),
    /// Inspect the interfaces (message, service, action types) installed, compiled in, or
    /// used by a running node.
    #[command(subcommand)]
    Interface(verb::interface::InterfaceCommand),
    /// The whole graph in one document, or a live diff of it.
    Graph(verb::graph::GraphArgs),
    /// Start, stop or check the daemon that keeps the graph discovered for the query commands.
    #[command(subcommand)]
    Daemon(verb::daemon::DaemonCommand),
    /// Start an add_two_ints server node, show `service info -v` for it and call it once.
    Demo(verb::demo::DemoArgs),
    /// Print a shell completion script.
    Completions(verb::completions::CompletionsArgs),
    /// Run a Zenoh router, as rmw_zenoh's `rmw_zenohd` (for the zenoh backend).
    #[cfg(feature = "zenoh")]
    Router(verb::router::RouterArgs),
}

/// Set when stdout turned out to be a closed pipe.
static STDOUT_CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `println!` panics when stdout is a closed pipe: that panic is not an error of ours, so it is
/// not reported (any other panic is, as usual).
fn quiet_on_closed_stdout() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.contains("failed printing to stdout") && message.contains("Broken pipe") {
            STDOUT_CLOSED.store(true, std::sync::atomic::Ordering::SeqCst);
            return;
        }
        default(info);
    }));
}

/// The log filter: `RUST_LOG` (default `warn`), with rustdds' own lines (and zenoh's admin
/// space's) off unless `RUST_LOG` names it. rustdds 0.15 logs internal queue overflows as errors whenever a peer with more than
/// four endpoints leaves (`Cannot remove Reader GUID … TrySendError::Full`), which says nothing
/// to a CLI user and would mix into every answer's stderr.
fn log_filter() -> tracing_subscriber::EnvFilter {
    let spec = std::env::var("RUST_LOG").unwrap_or_default();
    let spec = if spec.trim().is_empty() {
        "warn".to_owned()
    } else {
        spec
    };
    let spec = if spec.contains("rustdds") {
        spec
    } else {
        format!("{spec},rustdds=off")
    };
    // zenoh 1.8 logs an error for every link that closes after its session did ("Unable to
    // publish transport event: session closed"): every CLI run on the zenoh backend ends so.
    let spec = if spec.contains("zenoh") {
        spec
    } else {
        format!("{spec},zenoh::api::admin=off")
    };
    tracing_subscriber::EnvFilter::try_new(spec).unwrap_or_else(|_| {
        tracing_subscriber::EnvFilter::new("warn,rustdds=off,zenoh::api::admin=off")
    })
}

fn main() -> ExitCode {
    // Colours only for a terminal: logs piped or redirected are plain text.
    tracing_subscriber::fmt()
        .with_ansi(std::io::stderr().is_terminal())
        .with_env_filter(log_filter())
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    quiet_on_closed_stdout();
    let result = std::panic::catch_unwind(move || match cli.command {
        Command::Service(c) => verb::service::run(&cli.global, c),
        Command::Node(c) => verb::node::run(&cli.global, c),
        Command::Topic(c) => verb::topic::run(&cli.global, c),
        Command::Param(c) => verb::param::run(&cli.global, c),
        Command::Action(c) => verb::action::run(&cli.global, c),
        Command::Lifecycle(c) => verb::lifecycle::run(&cli.global, c),
        Command::Interface(c) => verb::interface::run(&cli.global, c),
        Command::Graph(args) => verb::graph::run(&cli.global, &args),
        Command::Daemon(c) => verb::daemon::run(&cli.global, c),
        Command::Demo(args) => verb::demo::run(&cli.global, &args),
        Command::Completions(args) => verb::completions::run(&args),
        #[cfg(feature = "zenoh")]
        Command::Router(args) => verb::router::run(&args),
    });
    // The reader of our output went away (`horus-ros … | head`): stop quietly, as a shell tool does.
    let Ok(result) = result else {
        return if STDOUT_CLOSED.load(std::sync::atomic::Ordering::SeqCst) {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(101)
        };
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if !e.message.is_empty() {
                eprintln!("{}", e.message);
            }
            ExitCode::from(e.code)
        }
    }
}
