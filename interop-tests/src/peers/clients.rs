//! Rounds of real Jazzy service clients started together (`peers/jazzy_service_clients.py`:
//! rclpy clients that `wait_for_service`, then call), each process on the RMW given, and what
//! they got.

use std::process::{Child, Command, Stdio};
use std::time::Duration;

use horus_ros_msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsResponse};
use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolResponse};
use horus_ros_services::prelude::{Context, Node, ServiceServer};
use horus_ros_services::EndpointBuilder;
use horus_ros_test_support::jazzy::Rmw;
use serde_json::Value;

/// The service the clients of these rounds call, and its type.
pub const ADD_TWO_INTS: (&str, &str) = ("/add_two_ints", "example_interfaces/srv/AddTwoInts");

/// Our AddTwoInts server on [`ADD_TWO_INTS`], from a node `node_name` of `context`.
pub fn add_two_ints_server(context: &Context, node_name: &str) -> ServiceServer<AddTwoInts> {
    let node = context.create_node(node_name, "/").expect("node");
    ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name(ADD_TWO_INTS.0)
        .on_request(|r| {
            Ok(AddTwoIntsResponse {
                sum: r.a.wrapping_add(r.b),
            })
        })
        .build()
        .expect("server")
}

/// What each peer process gives itself from start to its last reply: a "did not hang" limit.
pub const PEER_TIMEOUT_S: u64 = 60;
/// How long a round waits for a process beyond its own limit.
const PEER_SLACK: Duration = Duration::from_secs(30);

/// One round: `processes` started at once, each with `clients` clients.
#[derive(Debug, Clone)]
pub struct Round {
    /// Processes started together.
    pub processes: usize,
    /// Clients in each process (one node).
    pub clients: usize,
    /// Calls each client makes, one after the other.
    pub calls: u64,
    /// Clients of each process created (and answered) before the others.
    pub lead: usize,
    /// History depth of the clients' endpoints (rmw_qos_profile_services_default: 10).
    pub depth: usize,
}

impl Round {
    /// `processes` processes of one client each, making `calls` calls with the default depth.
    pub fn single_clients(processes: usize, calls: u64) -> Self {
        Self {
            processes,
            clients: 1,
            calls,
            lead: 0,
            depth: 10,
        }
    }

    /// Clients in the round, all processes together.
    pub fn total_clients(&self) -> usize {
        self.processes * self.clients
    }

    /// Calls in the round, all clients together.
    pub fn total_calls(&self) -> u64 {
        self.total_clients() as u64 * self.calls
    }
}

/// What the clients of a round got.
#[derive(Debug, Default)]
pub struct Tally {
    /// Clients whose first call was answered.
    pub first_replies: usize,
    /// Calls answered, all clients together.
    pub replies: u64,
    /// Processes in which a client got no first reply (its output).
    pub missed_first: Vec<String>,
    /// Processes in which a client missed any reply (its output).
    pub missed_any: Vec<String>,
}

/// A peer process, killed if the round ends before it does.
struct PeerProcess(Child);

impl Drop for PeerProcess {
    fn drop(&mut self) {
        if matches!(self.0.try_wait(), Ok(None)) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// Our std_srvs/SetBool server on `service` of `node`: success is the data asked for.
pub fn set_bool_server(node: &Node, service: &str) -> ServiceServer<SetBool> {
    ServiceServer::<SetBool>::builder()
        .node(node)
        .name(service)
        .on_request(|r| {
            Ok(SetBoolResponse {
                success: r.data,
                message: String::new(),
            })
        })
        .build()
        .expect("server")
}

/// Starts `round.processes` processes of clients of `service` (`type_name`, e.g.
/// `example_interfaces/srv/AddTwoInts`) on `rmw` in `domain`, all at once, and waits for them.
pub fn run_round(rmw: Rmw, service: &str, type_name: &str, round: &Round, domain: u32) -> Tally {
    let peers: Vec<PeerProcess> = (0..round.processes)
        .map(|_| {
            let child = Command::new(crate::python())
                .arg(crate::peer_script("jazzy_service_clients.py"))
                .args([
                    service.to_owned(),
                    type_name.to_owned(),
                    round.clients.to_string(),
                    round.calls.to_string(),
                    PEER_TIMEOUT_S.to_string(),
                    round.lead.to_string(),
                    round.depth.to_string(),
                ])
                .env("RMW_IMPLEMENTATION", rmw.name())
                .env("CYCLONEDDS_URI", crate::cyclone_config())
                .env("ROS_DOMAIN_ID", domain.to_string())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap_or_else(|e| panic!("start jazzy_service_clients.py: {e}"));
            PeerProcess(child)
        })
        .collect();
    let mut tally = Tally::default();
    for mut peer in peers {
        let limit = Duration::from_secs(PEER_TIMEOUT_S) + PEER_SLACK;
        let out =
            horus_ros_test_support::wait_with_output(&mut peer.0, limit).expect("peer output");
        let lines: Vec<Value> = out
            .stdout
            .lines()
            .filter_map(|l| serde_json::from_str::<Value>(l).ok())
            .collect();
        let clients: Vec<&Value> = lines.iter().filter(|l| l.get("client").is_some()).collect();
        let first = clients.iter().filter(|l| l["first_reply"] == true).count();
        tally.first_replies += first;
        tally.replies += clients
            .iter()
            .filter_map(|l| l["replies"].as_u64())
            .sum::<u64>();
        let output = || format!("exit {:?}\n{}{}", out.code(), out.stdout, out.stderr);
        if clients.len() != round.clients || first != clients.len() {
            tally.missed_first.push(output());
        }
        if out.code() != Some(0) {
            tally.missed_any.push(output());
        }
    }
    tally
}
