//! `horus-ros action type` (ros2action `verb/type.py`).

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `action type`.
#[derive(Debug, clap::Args)]
pub struct TypeArgs {
    /// Name of the ROS action to get info (e.g. '/fibonacci').
    pub action_name: String,
}

/// Runs `action type`: each type of the action on its own line. An unknown action prints
/// nothing and exits 1, as ros2action's verb returns 1 without a message. The name is compared
/// as given, not expanded, as ros2action compares it.
pub fn run(global: &Global, args: &TypeArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let actions = source.read(|c| c.action_names_and_types());
    let Some(types) = names::find_types(&actions, &args.action_name) else {
        return Err(CliError::new(""));
    };
    if global.json {
        return names::print_json(&names::entry_json(&args.action_name, &types));
    }
    for ty in &types {
        println!("{ty}");
    }
    Ok(())
}
