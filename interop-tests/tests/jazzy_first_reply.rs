//! No lost first reply: ROS clients started together against our server, each calling the
//! moment its RMW lets it, every first call answered.
//!
//! - rmw_cyclonedds clients (`peers/cyclone_service_clients.py`: rmw_cyclonedds' endpoints,
//!   `clientid=` USER_DATA, request header and `rmw_service_server_is_available` check), several
//!   in one process (one participant, as the clients of an rclpy or rclcpp process) and several
//!   such processes at once, round after round of fresh processes; in half the rounds one client
//!   of each process is answered before the others are created, so the server must tell the
//!   clients of one participant apart by `clientid=`. With rmw_qos_profile_services_default
//!   (KEEP_LAST 10) a client's reply reader also receives every other client's reply (a server
//!   cannot address one Cyclone DDS reader) and loses its own once ten newer ones arrive before
//!   it takes it, whatever the server: those rounds keep to ten replies per reader. Clients
//!   created with a deeper history then make several calls each, more of them at once.
//! - real rclpy clients (rmw_fastrtps_cpp, `peers/jazzy_set_bool_clients.py`), four processes
//!   started together and four clients in one process, against a server on the rustdds backend
//!   (Fast DDS peers need it, as they need rmw_fastrtps).

use std::process::{Child, Command, Stdio};
use std::time::Duration;

use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolResponse};
use horus_ros_rmw::Backend;
use horus_ros_services::prelude::*;
use interop_tests::{cyclone_config, peer_script, python};
use serde_json::Value;

const SERVICE: &str = "/add_two_ints";
/// What each peer gives itself from start to its last reply: a "did not hang" limit.
const PEER_TIMEOUT_S: u64 = 30;
/// How long the test waits for a peer beyond its own limit.
const PEER_SLACK: Duration = Duration::from_secs(30);

/// One round: `processes` started at once, each with `clients` rmw_cyclonedds clients.
struct Round {
    processes: usize,
    clients: usize,
    /// Calls each client makes, one after the other.
    calls: u64,
    /// Clients of each process created (and answered) before the others.
    lead: usize,
    /// History depth of the clients' endpoints (rmw_qos_profile_services_default: 10).
    depth: usize,
}

/// A peer process, killed if the test ends before it does.
struct PeerProcess(Child);

impl Drop for PeerProcess {
    fn drop(&mut self) {
        if matches!(self.0.try_wait(), Ok(None)) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

fn spawn(script: &str, args: &[String], domain: u32) -> PeerProcess {
    let child = Command::new(python())
        .arg(peer_script(script))
        .args(args)
        .env("CYCLONEDDS_URI", cyclone_config())
        .env("ROS_DOMAIN_ID", domain.to_string())
        .env_remove("RMW_IMPLEMENTATION")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("start {script}: {e}"));
    PeerProcess(child)
}

/// Waits for every peer; the number of first replies its clients got, and the output of those
/// that failed.
fn collect(peers: Vec<PeerProcess>) -> (usize, Vec<String>) {
    let mut first_replies = 0;
    let mut failures = Vec::new();
    for mut peer in peers {
        let limit = Duration::from_secs(PEER_TIMEOUT_S) + PEER_SLACK;
        let out =
            horus_ros_test_support::wait_with_output(&mut peer.0, limit).expect("peer output");
        first_replies += out
            .stdout
            .lines()
            .filter_map(|l| serde_json::from_str::<Value>(l).ok())
            .filter(|l| l.get("client").is_some() && l["first_reply"] == true)
            .count();
        if out.code() != Some(0) {
            failures.push(format!(
                "exit {:?}\n{}{}",
                out.code(),
                out.stdout,
                out.stderr
            ));
        }
    }
    (first_replies, failures)
}

fn adder(context: &Context) -> ServiceServer<AddTwoInts> {
    let node = context.create_node("first_reply_adder", "/").expect("node");
    ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name(SERVICE)
        .on_request(|r| {
            Ok(AddTwoIntsResponse {
                sum: r.a.wrapping_add(r.b),
            })
        })
        .build()
        .expect("server")
}

/// Runs `rounds` one after the other against one server; every client of every round must get
/// every reply.
fn cyclone_rounds(domain: u32, rounds: &[Round]) {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let server = adder(&context);
    let mut expected = 0;
    for (n, round) in rounds.iter().enumerate() {
        let peers: Vec<PeerProcess> = (0..round.processes)
            .map(|_| {
                let args = [
                    domain.to_string(),
                    SERVICE.to_owned(),
                    round.clients.to_string(),
                    round.calls.to_string(),
                    PEER_TIMEOUT_S.to_string(),
                    round.lead.to_string(),
                    round.depth.to_string(),
                ];
                spawn("cyclone_service_clients.py", &args, domain)
            })
            .collect();
        let (first_replies, failures) = collect(peers);
        let clients = round.processes * round.clients;
        expected += clients as u64 * round.calls;
        assert!(
            failures.is_empty(),
            "{:?} backend, round {n}: {first_replies} of {clients} first calls answered, {} \
             requests served in all; failed processes:\n{}",
            context.backend(),
            server.served_count(),
            failures.join("\n")
        );
    }
    assert_eq!(server.served_count(), expected);
}

#[test]
fn every_first_call_of_rmw_cyclonedds_clients_started_together_is_answered() {
    let rounds: Vec<Round> = (0..16)
        .map(|n| Round {
            processes: 3,
            clients: 3,
            calls: 1,
            lead: n % 2,
            depth: 10,
        })
        .collect();
    cyclone_rounds(74, &rounds);
}

#[test]
fn rmw_cyclonedds_clients_with_a_deeper_history_started_together_get_every_reply() {
    let rounds: Vec<Round> = (0..4)
        .map(|n| Round {
            processes: 4,
            clients: 4,
            calls: 3,
            lead: n % 2,
            depth: 128,
        })
        .collect();
    cyclone_rounds(75, &rounds);
}

#[test]
fn every_first_call_of_rclpy_clients_started_together_is_answered() {
    const DOMAIN: u32 = 76;
    const CALLS: u64 = 3;
    let context = Context::builder()
        .domain_id(DOMAIN)
        .backend(Backend::RustDds)
        .build()
        .expect("context");
    let node = context
        .create_node("first_reply_setter", "/")
        .expect("node");
    let server = ServiceServer::<SetBool>::builder()
        .node(&node)
        .name("/set_bool")
        .on_request(|r| {
            Ok(SetBoolResponse {
                success: r.data,
                message: String::new(),
            })
        })
        .build()
        .expect("server");
    // Four processes of one client, then one process of four.
    for (processes, clients) in [(4, 1), (1, 4)] {
        let args = [
            "/set_bool".to_owned(),
            clients.to_string(),
            CALLS.to_string(),
            PEER_TIMEOUT_S.to_string(),
        ];
        let peers: Vec<PeerProcess> = (0..processes)
            .map(|_| spawn("jazzy_set_bool_clients.py", &args, DOMAIN))
            .collect();
        let (first_replies, failures) = collect(peers);
        assert!(
            failures.is_empty(),
            "{processes} process(es) of {clients} rclpy client(s): {first_replies} first calls \
             answered, {} requests served in all; failed processes:\n{}",
            server.served_count(),
            failures.join("\n")
        );
    }
    assert_eq!(server.served_count(), 2 * 4 * CALLS);
}
