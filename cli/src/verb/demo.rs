//! `horus-ros demo`: the README's main job.

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::Message;
use horus_ros_rmw::{qos::Qos, Context};

/// Arguments of `horus-ros demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Name of the node to start.
    #[arg(long, default_value = "horus_demo")]
    pub node_name: String,
    /// Namespace of the node.
    #[arg(long, default_value = "/")]
    pub namespace: String,
    /// How long to stay on the graph after printing, so peers can discover the node (ms).
    #[arg(long, default_value_t = 500)]
    pub linger_ms: u64,
}

/// Starts a node with a publisher and a subscription, prints what its participant announces on
/// `ros_discovery_info`, and exits.
pub fn run(domain_id: Option<u32>, args: &DemoArgs) -> Result<(), String> {
    let mut builder = Context::builder();
    if let Some(d) = domain_id {
        builder = builder.domain_id(d);
    }
    let context = builder.build().map_err(|e| e.to_string())?;
    let node = context
        .create_node(&args.node_name, &args.namespace)
        .map_err(|e| e.to_string())?;
    let qos = Qos::default();
    let publisher = node
        .create_publisher::<Time>("~/clock", &qos)
        .map_err(|e| e.to_string())?;
    let subscription = node
        .create_subscription::<Time>("~/clock", &qos)
        .map_err(|e| e.to_string())?;
    let info = context.announced_entities();
    println!("domain: {}", context.domain_id());
    println!("discovery range: {}", context.discovery_options().range);
    println!("node: {}", node.fully_qualified_name());
    println!(
        "publisher:    {} [{}] gid {}",
        publisher.topic_name(),
        Time::TYPE_NAME,
        publisher.gid()
    );
    println!(
        "subscription: {} [{}] gid {}",
        subscription.topic_name(),
        Time::TYPE_NAME,
        subscription.gid()
    );
    println!("type hash of {}: {}", Time::TYPE_NAME, Time::type_hash());
    println!("ros_discovery_info from participant {}:", info.gid);
    for n in &info.node_entities_info_seq {
        println!("  node {} in namespace {}", n.node_name, n.node_namespace);
        for g in &n.reader_gid_seq {
            println!("    reader {g}");
        }
        for g in &n.writer_gid_seq {
            println!("    writer {g}");
        }
    }
    std::thread::sleep(std::time::Duration::from_millis(args.linger_ms));
    Ok(())
}
