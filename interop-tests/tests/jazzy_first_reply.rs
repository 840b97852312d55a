//! No lost first reply: real ROS 2 Jazzy clients (rclpy, `peers/jazzy_service_clients.py`)
//! started together against our server, each calling as soon as `wait_for_service` lets it,
//! every call answered.
//!
//! - Clients on the RMW that speaks to this run's backend (`HORUS_ROS_BACKEND`) against a server
//!   on it: rmw_cyclonedds_cpp clients for the DDS backends (rustdds or Cyclone), rmw_zenoh_cpp
//!   clients for Zenoh (beside the run's router). Three rounds of eight processes of one
//!   client making twenty calls each, every first call answered (the calls answered in all are
//!   printed; sixteen at once is the benchmark's, beside rclpy's own server); processes of
//!   several clients, in half of them one client answered before the others are created (the
//!   server must tell the clients of one participant or session apart: by their `clientid=` on
//!   Cyclone DDS, by the GID in each query's attachment on Zenoh); clients with a deeper history
//!   making more calls at once, every call answered.
//! - rmw_cyclonedds_cpp only: with rmw_qos_profile_services_default (KEEP_LAST 10) a client's
//!   reply reader also receives every other client's reply (a Cyclone DDS writer cannot address
//!   one reader; rmw_cyclonedds' `rmw_take_response` drops the others' as it takes) and loses its
//!   own when ten newer ones arrive before its process takes it, whatever the server: under CPU
//!   load about one call in a few hundred of the twenty-call rounds, so those rounds require
//!   every first call; the others keep to ten replies in flight per reader. rmw_zenoh clients
//!   get only the replies to their own queries (rmw_zenoh_cpp 0.2.10 `rmw_client_data.cpp`: one
//!   `get` per request), so on Zenoh every round requires every reply.
//! - rmw_fastrtps_cpp clients, four processes started together and four clients in one
//!   process, against a server on the rustdds backend (the backend for Fast DDS peers: Cyclone
//!   DDS cannot read the request id rmw_fastrtps sends as inline QoS), whatever the run's
//!   backend.

use horus_ros_rmw::Backend;
use horus_ros_services::prelude::*;
use horus_ros_test_support::jazzy::Rmw;
use interop_tests::peers::clients::{
    add_two_ints_server, run_round, set_bool_server, Round, ADD_TWO_INTS,
};

/// The RMW of the clients that speak to `context`'s backend: rmw_zenoh_cpp for Zenoh,
/// rmw_cyclonedds_cpp for both DDS backends.
fn clients_rmw(context: &Context) -> Rmw {
    if context.backend() == Some(Backend::Zenoh) {
        Rmw::Zenoh
    } else {
        Rmw::CycloneDds
    }
}

/// Runs `rounds` of clients (on [`clients_rmw`]) one after the other against one AddTwoInts
/// server on this run's backend; every client of every round must get its first reply and, if
/// `every_reply` or on Zenoh, every reply.
fn rounds_against_ours(domain: u32, rounds: &[Round], every_reply: bool) {
    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let rmw = clients_rmw(&context);
    let every_reply = every_reply || rmw == Rmw::Zenoh;
    let server = add_two_ints_server(&context, "first_reply_adder");
    for (n, round) in rounds.iter().enumerate() {
        let served_before = server.served_count();
        let (service, type_name) = ADD_TWO_INTS;
        let tally = run_round(rmw, service, type_name, round, domain);
        let (clients, calls) = (round.total_clients(), round.total_calls());
        eprintln!(
            "{:?} backend, {} clients, round {n} ({} processes of {} clients, {} calls each): {} \
             of {clients} first calls answered, {} of {calls} calls",
            context.backend(),
            rmw.name(),
            round.processes,
            round.clients,
            round.calls,
            tally.first_replies,
            tally.replies
        );
        let failed = if every_reply {
            &tally.missed_any
        } else {
            &tally.missed_first
        };
        assert!(
            failed.is_empty(),
            "{:?} backend, {} clients, round {n}: {} of {clients} first calls answered, {} of \
             {calls} calls, {} requests served in all; failed processes:\n{}",
            context.backend(),
            rmw.name(),
            tally.first_replies,
            tally.replies,
            server.served_count(),
            failed.join("\n")
        );
        if every_reply {
            assert_eq!(server.served_count() - served_before, calls, "round {n}");
        }
    }
}

#[test]
fn clients_started_together_get_every_first_reply() {
    // Three rounds of eight processes of one client, twenty calls each. Sixteen at once is
    // measured beside rclpy's own server in `benches/first_reply.rs`: there ten newer replies
    // can push a client's first one out of its KEEP_LAST 10 reader under load, whatever the
    // server (rclpy's own lost one in 40 there).
    let rounds = [8, 8, 8].map(|processes| Round::single_clients(processes, 20));
    rounds_against_ours(74, &rounds, false);
}

/// `count` rounds of `processes` processes of as many clients, making `calls` calls each with
/// history `depth`; in every other round one client per process is answered before the others
/// are created.
fn rounds_of_several(count: usize, processes: usize, calls: u64, depth: usize) -> Vec<Round> {
    (0..count)
        .map(|n| Round {
            processes,
            clients: processes,
            calls,
            lead: n % 2,
            depth,
        })
        .collect()
}

#[test]
fn clients_of_one_process_started_together_get_every_reply() {
    rounds_against_ours(75, &rounds_of_several(4, 3, 1, 10), true);
}

#[test]
fn clients_with_a_deeper_history_started_together_get_every_reply() {
    rounds_against_ours(77, &rounds_of_several(2, 4, 3, 128), true);
}

#[test]
fn every_call_of_rmw_fastrtps_clients_started_together_is_answered() {
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
    let server = set_bool_server(&node, "/set_bool");
    // Four processes of one client, then one process of four.
    for (processes, clients) in [(4, 1), (1, 4)] {
        let round = Round {
            processes,
            clients,
            calls: CALLS,
            lead: 0,
            depth: 10,
        };
        let tally = run_round(
            Rmw::FastRtps,
            "/set_bool",
            "std_srvs/srv/SetBool",
            &round,
            DOMAIN,
        );
        assert!(
            tally.missed_any.is_empty(),
            "{processes} process(es) of {clients} rclpy client(s): {} first calls answered, {} \
             requests served in all; failed processes:\n{}",
            tally.first_replies,
            server.served_count(),
            tally.missed_any.join("\n")
        );
    }
    assert_eq!(server.served_count(), 2 * 4 * CALLS);
}
