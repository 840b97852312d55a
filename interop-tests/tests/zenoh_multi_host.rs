//! Two hosts on one machine on the Zenoh backend, as rmw_zenoh users join two sites: each host
//! (a network namespace made by the test, `common::hosts`, joined to the other by a veth pair)
//! runs its own router (`horus_zenoh_router`, what `horus-ros router` runs: rmw_zenoh's router
//! configuration), host A's router also connecting to host B's
//! (`ZENOH_CONFIG_OVERRIDE='connect/endpoints=["tcp/<B>:7447"]'`). A horus-ros AddTwoInts server
//! process runs in host A and a client process (`horus_add_two_ints_caller`) in host B, each a
//! peer of its own host's router (rmw_zenoh's session configuration: `tcp/localhost:7447`).
//! The graph (liveliness tokens) and the calls (queries) cross the routers' link.
//!
//! What a cut of the link does depends on Zenoh's lease (rmw_zenoh: `transport/link/tx/lease`
//! 60 s, `keep_alive` 2: a keep-alive every 30 s), and the tests assert each side of it:
//!
//! - a cut shorter than the lease loses no session: nothing is closed (the TCP connections just
//!   stop carrying packets, the kernel resends them once the link is back), so the server stays
//!   in the caller's graph and the client still counts it ready while no call gets through (the
//!   caller's timeout, bounded, is what it reports); once the link is back the calls resume, and
//!   the request sent during the cut may still reach the server late, once;
//! - a cut longer than the lease (a lease of 3 s set by `ZENOH_CONFIG_OVERRIDE` on every process,
//!   so that the test stays short) closes the sessions across the link: the server leaves the
//!   caller's graph and a call made then is never handled; when the link is back, host A's
//!   router connects again (a router retries its `connect/endpoints`, at most 4 s apart), the
//!   server comes back into the graph and the calls resume.
//!
//! The client is ready (the server's liveliness tokens have reached the caller) a moment before
//! the routers can route its queries: they route queries along trees they compute 100 ms after
//! their link changes (zenoh 1.8 `net/routing/hat/mod.rs` `TREES_COMPUTATION_DELAY_MS`; until
//! then `hat/router/queries.rs` finds no route: "Tree for node … not yet ready") and drop a query
//! with no route, unhandled. So the first call after the routers link, at the start and after a
//! reconnection, is retried with a short timeout and a new request each time. In both tests no
//! request is handled twice. Every wait is on a child's output line, bounded: no sleep. Needs
//! root and iproute2, as `scripts/isolated`, which the suite runs in.

#[allow(dead_code)]
mod common;

use std::collections::BTreeMap;
use std::time::Instant;

use common::hosts::{times_handled, Hosts, Running};

const ROUTER: &str = env!("CARGO_BIN_EXE_horus_zenoh_router");
const SERVER: &str = env!("CARGO_BIN_EXE_horus_add_two_ints_server");
const CALLER: &str = env!("CARGO_BIN_EXE_horus_add_two_ints_caller");

/// The server node's full name (`horus_add_two_ints_server`).
const SERVER_NODE: &str = "/doomed_server";

/// Waits for a router's ready line.
fn assert_ready(router: &mut Running) {
    let ready = router.next_line();
    assert!(ready.starts_with("ready "), "{ready}");
}

/// A router, a server and a caller on two hosts, all on the Zenoh backend, and the calls that
/// got their answers.
struct Sites {
    hosts: Hosts,
    routers: [Running; 2],
    server: Running,
    caller: Running,
    answered: Vec<i64>,
}

impl Sites {
    /// Starts B's router, then A's connecting to it, the server in A and the caller in B, waits
    /// until the caller's graph has the server, and makes the first call. `overrides` go into
    /// every process's `ZENOH_CONFIG_OVERRIDE` (`key=value;…`).
    fn start(net: u8, domain: &str, overrides: &str) -> Self {
        let hosts = Hosts::new(net);
        let backend = ("HORUS_ROS_BACKEND", "zenoh");
        let mut router_b = Running::start(
            &hosts,
            1,
            ROUTER,
            &[],
            &[("ZENOH_CONFIG_OVERRIDE", overrides)],
        );
        assert_ready(&mut router_b);
        // A router opens once it has connected to every endpoint of `connect/endpoints`
        // (`connect/timeout_ms` -1 for routers): B's listens already.
        let joined = format!(
            "connect/endpoints=[\"tcp/{}:7447\"];{overrides}",
            hosts.address(1)
        );
        let mut router_a = Running::start(
            &hosts,
            0,
            ROUTER,
            &[],
            &[("ZENOH_CONFIG_OVERRIDE", &joined)],
        );
        assert_ready(&mut router_a);
        let routers = [router_a, router_b];
        let mut server = Running::start(
            &hosts,
            0,
            SERVER,
            &[domain, "/add_two_ints", "0"],
            &[backend, ("ZENOH_CONFIG_OVERRIDE", overrides)],
        );
        assert_eq!(server.next_line(), "ready");
        let mut caller = Running::start(
            &hosts,
            1,
            CALLER,
            &[domain, "/add_two_ints"],
            &[backend, ("ZENOH_CONFIG_OVERRIDE", overrides)],
        );
        assert_eq!(caller.next_line(), "ready");
        let mut sites = Self {
            hosts,
            routers,
            server,
            caller,
            answered: Vec::new(),
        };
        sites.server_seen();
        sites.first_call_answered(1);
        sites
    }

    /// Waits until the graph crosses: host B's graph has host A's node and its server (`node`),
    /// and the client is ready (`wait`).
    fn server_seen(&mut self) {
        assert_eq!(
            self.caller.ask(&format!("node {SERVER_NODE} 20000")),
            format!("node {SERVER_NODE} seen")
        );
        assert_eq!(self.caller.ask("wait 20000"), "found");
    }

    /// One call `a + 100`, at most `timeout_ms`: its answer line.
    fn call(&mut self, a: i64, timeout_ms: u32) -> String {
        let answer = self.caller.ask(&format!("call {a} 100 {timeout_ms}"));
        if answer.starts_with("sum ") {
            assert_eq!(answer, format!("sum {a} {}", a + 100));
            self.answered.push(a);
        }
        answer
    }

    /// Asserts that the calls `a + 100` for each `a` get their answers.
    fn calls_answered(&mut self, calls: impl IntoIterator<Item = i64>) {
        for a in calls {
            let answer = self.call(a, 15_000);
            assert!(
                answer.starts_with("sum "),
                "{answer}; the server printed {:#?}",
                self.server.lines_so_far()
            );
        }
    }

    /// The first call once the graph has the server: `a`, else `a + 1`, … at most five calls of
    /// 3 s each, until one gets its answer. Zenoh's routers route a query along trees they
    /// compute 100 ms after their link changes (`TREES_COMPUTATION_DELAY_MS`), while the
    /// liveliness tokens reach the caller at once: a query sent in between is dropped (never
    /// handled), so the client is ready before the route is, and the caller retries, as a user
    /// would, with a new request each time. Every later call gets its answer at once.
    fn first_call_answered(&mut self, a: i64) {
        for a in a..a + 5 {
            let answer = self.call(a, 3_000);
            if answer.starts_with("sum ") {
                return;
            }
            assert!(
                answer.starts_with(&format!("failed {a} ")) && answer.contains("timed out"),
                "{answer}"
            );
            eprintln!("the first call went unanswered ({answer}): calling again");
        }
        panic!(
            "no answer to five calls; the server printed {:#?}",
            self.server.lines_so_far()
        );
    }

    /// Ends every process (each ends on its closed standard input), asserts that each answered
    /// call was handled once and no request twice, and returns how many times the server
    /// handled each request.
    fn finish(self) -> BTreeMap<String, usize> {
        let calls = self.caller.finish();
        let handled = self.server.finish();
        for router in self.routers {
            router.finish();
        }
        drop(self.hosts);
        assert_eq!(
            calls.iter().filter(|l| l.starts_with("sum ")).count(),
            self.answered.len(),
            "{calls:#?}"
        );
        let times = times_handled(&handled);
        assert!(times.values().all(|&n| n == 1), "{handled:#?}");
        for a in &self.answered {
            assert_eq!(times.get(a.to_string().as_str()), Some(&1), "{handled:#?}");
        }
        times.into_iter().map(|(a, n)| (a.to_owned(), n)).collect()
    }
}

#[test]
fn calls_cross_two_routers_and_resume_after_a_cut_shorter_than_the_lease() {
    let mut sites = Sites::start(4, "147", "");
    sites.calls_answered(6..=7);

    // Cut, for less than the 60-s lease: a call gets no answer within its timeout, ...
    sites.hosts.link(false);
    let cut = sites.call(10, 1500);
    assert!(
        cut.starts_with("failed 10 ") && cut.contains("timed out"),
        "{cut}"
    );
    // ... but no session was lost: the server is still in host B's graph, still ready.
    assert_eq!(
        sites.caller.ask(&format!("node {SERVER_NODE} 0")),
        format!("node {SERVER_NODE} seen")
    );
    assert_eq!(sites.caller.ask("wait 0"), "found");

    // Restored: the same sessions carry the calls again (the routes never changed).
    sites.hosts.link(true);
    sites.calls_answered(11..=13);

    // The request sent during the cut may be handled once, late (its reply is dropped by the
    // client).
    let times = sites.finish();
    eprintln!(
        "during the cut: {cut}; after it, request 10 was handled {} time(s)",
        times.get("10").copied().unwrap_or(0)
    );
}

#[test]
fn a_cut_longer_than_the_lease_loses_the_server_until_the_routers_reconnect() {
    // A lease of 3 s (a keep-alive every second) on every process, instead of rmw_zenoh's 60 s.
    let mut sites = Sites::start(
        5,
        "148",
        "transport/link/tx/lease=3000;transport/link/tx/keep_alive=3",
    );
    sites.calls_answered(6..=7);

    // Cut until the lease expires: the sessions across the link close, and host B's graph loses
    // the server's node and its server (their liveliness tokens go with the sessions, one event
    // each: `gone` waits for both).
    sites.hosts.link(false);
    let cut_at = Instant::now();
    assert_eq!(
        sites.caller.ask(&format!("gone {SERVER_NODE} 20000")),
        format!("node {SERVER_NODE} gone")
    );
    let lost_after = cut_at.elapsed();
    // A call now has no server to reach.
    let cut = sites.call(10, 1500);
    assert!(
        cut.starts_with("failed 10 ") && cut.contains("no server"),
        "{cut}"
    );

    // Restored: host A's router connects to host B's again, the server is back in the graph and
    // the calls resume (the first once the routers have their routes again).
    sites.hosts.link(true);
    let restored_at = Instant::now();
    sites.server_seen();
    let back_after = restored_at.elapsed();
    sites.first_call_answered(11);
    sites.calls_answered(16..=17);

    // The request of the cut went nowhere: it is never handled, not even late.
    let times = sites.finish();
    assert_eq!(times.get("10"), None, "{times:?}");
    eprintln!(
        "the server left host B's graph {lost_after:?} after the cut and was back {back_after:?} \
         after the link; during the cut: {cut}"
    );
}
