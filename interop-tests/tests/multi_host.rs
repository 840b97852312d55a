//! Several hosts on one machine: network namespaces made by the test (inside the test network
//! namespace of `scripts/isolated`, so nothing leaves the machine), joined by a veth pair with
//! addresses of their own. A horus-ros AddTwoInts server runs as a process in host A, a client
//! process (`horus_add_two_ints_caller`) in host B: discovery and calls cross the link, calls
//! resume after the link is cut and restored with nothing handled twice, and
//! `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST` keeps a host's nodes to that host, and every call
//! gets its one answer while each host drops 15 % of the packets it sends on the link at random
//! (an nftables `numgen random` rule: this kernel has no netem). On the backend of
//! `HORUS_ROS_BACKEND`; every wait is on a child's output line, bounded.
//!
//! Needs root, iproute2 and nftables (`scripts/setup`), as `scripts/isolated`, which the suite
//! runs in. The hosts and the children are `common::hosts`'s, shared with `zenoh_multi_host.rs`.

#[allow(dead_code)]
mod common;

use common::hosts::{times_handled, Hosts, Running};

const SERVER: &str = env!("CARGO_BIN_EXE_horus_add_two_ints_server");
const CALLER: &str = env!("CARGO_BIN_EXE_horus_add_two_ints_caller");

#[test]
fn calls_cross_hosts_and_resume_after_the_link_is_cut_and_restored() {
    let domain = "144";
    let hosts = Hosts::new(1);
    let mut server = Running::start(&hosts, 0, SERVER, &[domain, "/add_two_ints", "0"], &[]);
    assert_eq!(server.next_line(), "ready");
    let mut caller = Running::start(&hosts, 1, CALLER, &[domain, "/add_two_ints"], &[]);
    assert_eq!(caller.next_line(), "ready");
    assert_eq!(caller.ask("wait 20000"), "found");
    for a in 1..=3 {
        assert_eq!(
            caller.ask(&format!("call {a} 100 10000")),
            format!("sum {a} {}", a + 100)
        );
    }

    // Cut: a call cannot get through.
    hosts.link(false);
    let cut = caller.ask("call 10 100 1500");
    assert!(cut.starts_with("failed 10 "), "{cut}");
    // Restored: calls go through again.
    hosts.link(true);
    for a in 11..=13 {
        assert_eq!(
            caller.ask(&format!("call {a} 100 15000")),
            format!("sum {a} {}", a + 100)
        );
    }

    let calls = caller.finish();
    let handled = server.finish();
    // One answer per call, and no request handled twice (the one sent during the cut may be
    // handled once, late, after the link came back; its late reply is dropped by the client).
    assert_eq!(calls.iter().filter(|l| l.starts_with("sum ")).count(), 6);
    let times = times_handled(&handled);
    assert!(times.values().all(|&n| n == 1), "{handled:#?}");
    for a in ["1", "2", "3", "11", "12", "13"] {
        assert_eq!(times.get(a), Some(&1), "{handled:#?}");
    }
}

#[test]
fn localhost_discovery_range_keeps_a_hosts_nodes_to_that_host() {
    let domain = "145";
    let hosts = Hosts::new(2);
    let localhost = [("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")];
    let mut server = Running::start(
        &hosts,
        0,
        SERVER,
        &[domain, "/add_two_ints", "0"],
        &localhost,
    );
    assert_eq!(server.next_line(), "ready");
    // On the same host, a LOCALHOST client finds it and calls it.
    let mut same_host = Running::start(&hosts, 0, CALLER, &[domain, "/add_two_ints"], &localhost);
    assert_eq!(same_host.next_line(), "ready");
    assert_eq!(same_host.ask("wait 20000"), "found");
    assert_eq!(same_host.ask("call 1 2 10000"), "sum 1 3");
    // From host B, neither a LOCALHOST client nor a SUBNET one ever sees it (a bounded wait:
    // the absence of an event).
    let mut other_local = Running::start(&hosts, 1, CALLER, &[domain, "/add_two_ints"], &localhost);
    let mut other_subnet = Running::start(&hosts, 1, CALLER, &[domain, "/add_two_ints"], &[]);
    assert_eq!(other_local.next_line(), "ready");
    assert_eq!(other_subnet.next_line(), "ready");
    for caller in [&mut other_local, &mut other_subnet] {
        caller.send("wait 3000");
    }
    assert_eq!(other_local.next_line(), "not found");
    assert_eq!(other_subnet.next_line(), "not found");
    for caller in [same_host, other_local, other_subnet] {
        caller.finish();
    }
    server.finish();
}

#[test]
fn every_call_is_answered_once_at_15_percent_packet_loss() {
    const CALLS: i64 = 100;
    let domain = "146";
    let hosts = Hosts::new(3);
    hosts.lose(15);
    let mut server = Running::start(&hosts, 0, SERVER, &[domain, "/add_two_ints", "0"], &[]);
    assert_eq!(server.next_line(), "ready");
    let mut caller = Running::start(&hosts, 1, CALLER, &[domain, "/add_two_ints"], &[]);
    assert_eq!(caller.next_line(), "ready");
    assert_eq!(caller.ask("wait 25000"), "found");
    // Each call once, with a generous timeout, as a user would: the reliable transport resends
    // what is lost.
    for a in 1..=CALLS {
        assert_eq!(
            caller.ask(&format!("call {a} 1000 20000")),
            format!("sum {a} {}", a + 1000)
        );
    }
    let dropped = hosts.dropped();
    caller.finish();
    let handled = server.finish();
    let times = times_handled(&handled);
    assert_eq!(
        times.len(),
        usize::try_from(CALLS).expect("count"),
        "{handled:#?}"
    );
    assert!(times.values().all(|&n| n == 1), "{handled:#?}");
    // The loss was real.
    assert!(dropped > 0, "no packet was dropped");
    eprintln!("{CALLS} calls answered once each; {dropped} packets dropped on the link");
}
