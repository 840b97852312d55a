//! `horus-ros topic info` (ros2topic `verb/info.py`).

use horus_ros_graph::{GraphCache, TopicEndpointInfo};
use serde_json::json;

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `topic info`.
#[derive(Debug, clap::Args)]
pub struct InfoArgs {
    /// Name of the ROS topic to get info (e.g. '/chatter').
    pub topic_name: String,
    /// Prints detailed information like the node name, node namespace, topic type, GUID and QoS
    /// Profile of the publishers and subscribers to this topic.
    #[arg(short = 'v', long)]
    pub verbose: bool,
}

/// Everything `topic info` shows, read from the graph at once.
struct TopicInfo {
    types: Vec<String>,
    publisher_count: usize,
    subscription_count: usize,
    publishers: Vec<TopicEndpointInfo>,
    subscriptions: Vec<TopicEndpointInfo>,
}

/// The topic's details; `None` when no topic has that exact name (hidden topics included, as
/// ros2cli looks them up).
fn read(cache: &GraphCache, topic: &str) -> Option<TopicInfo> {
    let types = names::find_types(&cache.topic_names_and_types(true), topic)?;
    Some(TopicInfo {
        types,
        publisher_count: cache.count_publishers(topic),
        subscription_count: cache.count_subscribers(topic),
        publishers: cache.publishers_info_by_topic(topic, false),
        subscriptions: cache.subscriptions_info_by_topic(topic, false),
    })
}

/// Runs `topic info`.
pub fn run(global: &Global, args: &InfoArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let topic = &args.topic_name;
    let info = source
        .read(|c| read(c, topic))
        .ok_or_else(|| CliError::new(format!("Unknown topic '{topic}'")))?;
    if global.json {
        return names::print_json(&json!({
            "name": topic,
            "types": info.types,
            "publisher_count": info.publisher_count,
            "subscription_count": info.subscription_count,
            "publishers": info.publishers.iter().map(names::topic_endpoint_json).collect::<Vec<_>>(),
            "subscriptions": info.subscriptions.iter().map(names::topic_endpoint_json).collect::<Vec<_>>(),
        }));
    }
    print!("{}", render(&info, args.verbose));
    Ok(())
}

/// ros2cli's text: `Type:`, `Publisher count:`, `Subscription count:`; with `-v` every line
/// ends with a blank line and each publisher (then each subscription) follows its count as an
/// rclpy `TopicEndpointInfo` block.
fn render(info: &TopicInfo, verbose: bool) -> String {
    let end = if verbose { "\n\n" } else { "\n" };
    let mut out = format!("Type: {}{end}", names::type_str(&info.types));
    out.push_str(&format!("Publisher count: {}{end}", info.publisher_count));
    if verbose {
        for p in &info.publishers {
            out.push_str(&format!("{p}{end}"));
        }
    }
    out.push_str(&format!(
        "Subscription count: {}{end}",
        info.subscription_count
    ));
    if verbose {
        for s in &info.subscriptions {
            out.push_str(&format!("{s}{end}"));
        }
    }
    out
}
