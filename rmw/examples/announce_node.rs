//! Starts a node with a publisher, prints what the participant announces on `ros_discovery_info`,
//! publishes a few messages and exits. Run it inside a private network namespace:
//! `cargo build --example announce_node && scripts/isolated target/debug/examples/announce_node`.

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::{qos::Qos, Context};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE and ROS_STATIC_PEERS are read as rcl reads them.
    let context = Context::from_env()?;
    let node = context.create_node("talker", "/demo")?;
    let publisher = node.create_publisher::<Time>("clock", &Qos::default())?;
    println!(
        "{} announced by participant {}",
        node.fully_qualified_name(),
        context.gid()
    );
    println!("{:#?}", context.announced_entities());
    for sec in 0..3 {
        publisher.publish(Time { sec, nanosec: 0 })?;
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    Ok(())
}
