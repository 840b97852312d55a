//! `horus-ros topic type` (ros2topic jazzy `verb/type.py`).

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `topic type`.
#[derive(Debug, clap::Args)]
pub struct TypeArgs {
    /// Name of the ROS topic to get type (e.g. '/chatter').
    pub topic_name: String,
    /// Consider hidden topics as well (ros2cli's `ros2 topic --include-hidden-topics`).
    #[arg(long)]
    pub include_hidden_topics: bool,
}

/// Runs `topic type`: each type of the topic on its own line. An unknown topic prints nothing
/// and exits 1, as ros2cli does (its verb returns 1 without a message).
pub fn run(global: &Global, args: &TypeArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let topics = source.read(|c| c.topic_names_and_types(args.include_hidden_topics));
    let Some(types) = names::find_types(&topics, &args.topic_name) else {
        return Err(CliError::new(""));
    };
    if global.json {
        return names::print_json(&names::entry_json(&args.topic_name, &types));
    }
    for ty in &types {
        println!("{ty}");
    }
    Ok(())
}
