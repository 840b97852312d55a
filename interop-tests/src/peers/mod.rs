//! Real ROS 2 Jazzy as a peer: rclpy 7.1.6 on rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5, the
//! PyPI wheels `scripts/setup` installs into the test environment (their rcl is linked to
//! rmw_fastrtps_cpp). A peer is one rclpy node, `peers/jazzy_node.py`, given a JSON spec of its
//! servers, clients, publishers, subscriptions and parameters ([`RclpyPeer`]); it can print
//! rclpy's own view of the graph, which [`wait_for_same_view`] compares with ours. [`wheels`]
//! reads the type descriptions and hashes the wheels install; [`clients`] starts rounds of real
//! service clients together on any of the three RMWs.

pub mod cdr;
pub mod clients;
mod peer;
mod view;
pub mod wheels;

pub use peer::RclpyPeer;
pub use view::{
    announced, difference, gid_in, lists, our_view, service_endpoint_text, service_topics,
    wait_for_same_view, Us,
};
