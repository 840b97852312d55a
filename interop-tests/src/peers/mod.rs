//! Real ROS 2 Jazzy as a peer: rclpy 7.1.6 on the RMW of the run
//! (`horus_ros_test_support::jazzy::Rmw::of_peers`: rmw_fastrtps_cpp 8.4.3 / Fast DDS 2.14.5 by
//! default, or rmw_cyclonedds_cpp 2.2.2; or the RMW a test names, `RclpyPeer::start_on`), in the
//! environment `scripts/setup` installs. A peer is
//! one rclpy node, `peers/jazzy_node.py`, given a JSON spec of its
//! servers, clients, publishers, subscriptions and parameters ([`RclpyPeer`]); it can print
//! rclpy's own view of the graph, which [`wait_for_same_view`] compares with ours. [`wheels`]
//! reads the type descriptions and hashes the wheels install; [`request_ids`] says which request
//! ids a server on each RMW takes our requests with; [`clients`] starts rounds of real
//! service clients together on any of the three RMWs.

pub mod cdr;
pub mod clients;
mod peer;
pub mod request_ids;
mod view;
pub mod wheels;

pub use peer::RclpyPeer;
pub use view::{
    announced, as_compared, difference, gid_in, gid_of, lists, our_view, service_endpoint_text,
    service_topics, wait_for_same_view, Us,
};
