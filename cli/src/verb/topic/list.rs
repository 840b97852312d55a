//! `horus-ros topic list` (ros2topic `verb/list.py`).

use horus_ros_graph::GraphCache;
use serde_json::{json, Value};

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `topic list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Additionally show the topic type.
    #[arg(short = 't', long)]
    pub show_types: bool,
    /// Only display the number of topics discovered.
    #[arg(short = 'c', long)]
    pub count_topics: bool,
    /// Consider hidden topics as well.
    #[arg(long)]
    pub include_hidden_topics: bool,
    /// List full details about each topic.
    #[arg(short = 'v', long)]
    pub verbose: bool,
}

/// One topic: name, types, publishers, subscriptions.
struct Topic {
    name: String,
    types: Vec<String>,
    publishers: usize,
    subscriptions: usize,
}

fn read(cache: &GraphCache, include_hidden: bool) -> Vec<Topic> {
    cache
        .topic_names_and_types(include_hidden)
        .into_iter()
        .map(|(name, types)| Topic {
            types: types.into_iter().collect(),
            publishers: cache.count_publishers(&name),
            subscriptions: cache.count_subscribers(&name),
            name,
        })
        .collect()
}

/// Runs `topic list`.
pub fn run(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let topics = source.read(|c| read(c, args.include_hidden_topics));
    if global.json {
        if args.count_topics {
            return names::print_json(&names::count_json(topics.len()));
        }
        let list: Vec<Value> = topics
            .iter()
            .map(|t| {
                json!({
                    "name": t.name,
                    "types": t.types,
                    "publisher_count": t.publishers,
                    "subscription_count": t.subscriptions,
                })
            })
            .collect();
        return names::print_json(&Value::Array(list));
    }
    print!("{}", render(&topics, args));
    Ok(())
}

/// ros2cli's `show_topic_info`: a title, then ` * /name [types] N publisher(s)` for each topic
/// with at least one, then an empty line (the message's own newline, then `print`'s).
fn section(topics: &[Topic], publishers: bool) -> String {
    let mut out = format!(
        "{} topics:\n",
        if publishers {
            "Published"
        } else {
            "Subscribed"
        }
    );
    for t in topics {
        let count = if publishers {
            t.publishers
        } else {
            t.subscriptions
        };
        if count > 0 {
            out.push_str(&format!(
                " * {} [{}] {count} {}{}\n",
                t.name,
                t.types.join(", "),
                if publishers {
                    "publisher"
                } else {
                    "subscriber"
                },
                if count > 1 { "s" } else { "" }
            ));
        }
    }
    out.push('\n');
    out
}

/// ros2cli's text: the count with `-c`; else with `-v` the published then subscribed
/// sections; else one topic a line, `/name [types]` with `-t`. Nothing when there is no topic.
fn render(topics: &[Topic], args: &ListArgs) -> String {
    if args.count_topics {
        return format!("{}\n", topics.len());
    }
    if topics.is_empty() {
        return String::new();
    }
    if args.verbose {
        return section(topics, true) + &section(topics, false);
    }
    let mut out = String::new();
    for t in topics {
        out.push_str(&t.name);
        if args.show_types {
            out.push_str(&format!(" [{}]", t.types.join(", ")));
        }
        out.push('\n');
    }
    out
}
