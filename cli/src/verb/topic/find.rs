//! `horus-ros topic find` (ros2topic jazzy `verb/find.py`).

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `topic find`.
#[derive(Debug, clap::Args)]
pub struct FindArgs {
    /// Name of the ROS topic type to filter for (e.g. 'std_msg/msg/String').
    pub topic_type: String,
    /// Only display the number of topics discovered.
    #[arg(short = 'c', long)]
    pub count_topics: bool,
    /// Consider hidden topics as well.
    #[arg(long)]
    pub include_hidden_topics: bool,
}

/// Runs `topic find`: the topics having the type (one of their types equal to it, as ros2cli's
/// `args.topic_type in topic_type` compares), sorted by name.
pub fn run(global: &Global, args: &FindArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let mut topics = source.read(|c| c.topic_names_and_types(args.include_hidden_topics));
    topics.retain(|_, types| types.contains(&args.topic_type));
    if global.json {
        return names::print_json(&if args.count_topics {
            names::count_json(topics.len())
        } else {
            names::names_and_types_json(&topics)
        });
    }
    if args.count_topics {
        println!("{}", topics.len());
    } else {
        for name in topics.keys() {
            println!("{name}");
        }
    }
    Ok(())
}
