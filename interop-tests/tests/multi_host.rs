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
//! runs in.

use std::collections::BTreeMap;
use std::io::Write;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

/// The longest wait for one line of a child.
const WAIT: Duration = Duration::from_secs(30);

/// Runs `ip ARGS…`, panicking with its error output if it fails.
fn ip(args: &[&str]) {
    let out = Command::new("ip").args(args).output().expect("run ip");
    assert!(
        out.status.success(),
        "ip {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Two hosts, A (`10.231.<net>.1`) and B (`.2`), each a network namespace with loopback and
/// one end of a veth pair, multicast routed to the veth. Removed when dropped.
struct Hosts {
    namespaces: [String; 2],
    links: [String; 2],
}

impl Hosts {
    fn new(net: u8) -> Self {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let id = format!(
            "{}{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let hosts = Self {
            namespaces: [format!("hr{id}a"), format!("hr{id}b")],
            // Interface names have at most 15 characters.
            links: [format!("hv{id}a"), format!("hv{id}b")],
        };
        ip(&[
            "link",
            "add",
            &hosts.links[0],
            "type",
            "veth",
            "peer",
            "name",
            &hosts.links[1],
        ]);
        for (i, (ns, link)) in hosts.namespaces.iter().zip(&hosts.links).enumerate() {
            ip(&["netns", "add", ns]);
            ip(&["link", "set", link, "netns", ns]);
            let address = format!("10.231.{net}.{}/24", i + 1);
            ip(&["-n", ns, "link", "set", "lo", "up"]);
            ip(&["-n", ns, "addr", "add", &address, "dev", link]);
            ip(&["-n", ns, "link", "set", link, "up"]);
            ip(&["-n", ns, "route", "add", "224.0.0.0/4", "dev", link]);
        }
        hosts
    }

    /// Drops `percent` % of the packets each host sends on the link, at random.
    fn lose(&self, percent: u32) {
        for (ns, link) in self.namespaces.iter().zip(&self.links) {
            let rules = format!(
                "table inet loss {{\n  chain out {{\n    type filter hook output priority 0;\n    \
                 oifname \"{link}\" numgen random mod 100 < {percent} counter drop\n  }}\n}}\n"
            );
            let mut nft = Command::new("ip")
                .args(["netns", "exec", ns, "nft", "-f", "-"])
                .stdin(Stdio::piped())
                .spawn()
                .expect("run nft (scripts/setup installs nftables)");
            nft.stdin
                .take()
                .expect("stdin")
                .write_all(rules.as_bytes())
                .expect("write the rules");
            assert!(nft.wait().expect("nft").success(), "nft -f: {rules}");
        }
    }

    /// How many packets the loss rules dropped, both hosts together.
    fn dropped(&self) -> u64 {
        self.namespaces
            .iter()
            .map(|ns| {
                let out = Command::new("ip")
                    .args(["netns", "exec", ns, "nft", "list", "table", "inet", "loss"])
                    .output()
                    .expect("nft list");
                let text = String::from_utf8_lossy(&out.stdout);
                text.split_whitespace()
                    .skip_while(|w| *w != "packets")
                    .nth(1)
                    .and_then(|n| n.parse::<u64>().ok())
                    .unwrap_or_else(|| panic!("no counter in {text}"))
            })
            .sum()
    }

    /// Takes host A's end of the link down (`false`) or up again (`true`).
    fn link(&self, up: bool) {
        let state = if up { "up" } else { "down" };
        ip(&[
            "-n",
            &self.namespaces[0],
            "link",
            "set",
            &self.links[0],
            state,
        ]);
    }
}

impl Drop for Hosts {
    fn drop(&mut self) {
        for ns in &self.namespaces {
            let _ = Command::new("ip").args(["netns", "del", ns]).status();
        }
    }
}

/// A child process in one host, its stdout lines arriving on a channel. Killed when dropped.
struct Running {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: Receiver<String>,
    seen: Vec<String>,
}

impl Running {
    /// Starts `exe ARGS…` in `host` (0: A, 1: B) with `env` added and `CYCLONEDDS_URI` removed
    /// (each host chooses its own interface).
    fn start(hosts: &Hosts, host: usize, exe: &str, args: &[&str], env: &[(&str, &str)]) -> Self {
        let mut child = Command::new("ip")
            .args(["netns", "exec", &hosts.namespaces[host], exe])
            .args(args)
            .env_remove("CYCLONEDDS_URI")
            .envs(env.iter().copied())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("start a child in a host");
        let lines = interop_tests::line_reader(child.stdout.take().expect("stdout"));
        Self {
            stdin: child.stdin.take(),
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// The next line (at most [`WAIT`]).
    fn next_line(&mut self) -> String {
        match self.lines.recv_timeout(WAIT) {
            Ok(line) => {
                self.seen.push(line.clone());
                line
            }
            Err(_) => panic!("no line within {WAIT:?}; saw {:#?}", self.seen),
        }
    }

    /// Sends one command line and returns the answer line.
    fn ask(&mut self, command: &str) -> String {
        let stdin = self.stdin.as_mut().expect("stdin open");
        writeln!(stdin, "{command}").expect("write a command");
        stdin.flush().expect("flush");
        self.next_line()
    }

    /// Closes its standard input (the caller and the server end on it) and returns every line
    /// it printed.
    fn finish(mut self) -> Vec<String> {
        self.stdin = None;
        let end = Instant::now() + WAIT;
        while let Ok(line) = self
            .lines
            .recv_timeout(end.saturating_duration_since(Instant::now()))
        {
            self.seen.push(line);
        }
        let status = self.child.wait().expect("wait");
        assert!(status.success(), "{status}: {:#?}", self.seen);
        std::mem::take(&mut self.seen)
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

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
    let mut times: BTreeMap<&str, usize> = BTreeMap::new();
    for line in &handled {
        if let Some(a) = line.strip_prefix("handling ") {
            *times.entry(a).or_default() += 1;
        }
    }
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
        let stdin = caller.stdin.as_mut().expect("stdin");
        writeln!(stdin, "wait 3000").expect("write");
        stdin.flush().expect("flush");
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
    let mut times: BTreeMap<&str, usize> = BTreeMap::new();
    for line in &handled {
        if let Some(a) = line.strip_prefix("handling ") {
            *times.entry(a).or_default() += 1;
        }
    }
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
