//! Hosts on one machine for tests: two network namespaces made by the test (inside the test
//! network namespace of `scripts/isolated`, so nothing leaves the machine), joined by a veth
//! pair, and child processes run in them, read line by line. Used by `multi_host.rs` (DDS) and
//! `zenoh_multi_host.rs` (Zenoh, a router per host).
//!
//! Needs root and iproute2 (nftables for [`Hosts::lose`]), as `scripts/isolated`.

use std::collections::BTreeMap;
use std::io::Write;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

/// The longest wait for one line of a child.
pub const WAIT: Duration = Duration::from_secs(30);

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
pub struct Hosts {
    net: u8,
    namespaces: [String; 2],
    links: [String; 2],
}

impl Hosts {
    /// Makes the two hosts on `10.231.<net>.0/24` (a `net` of its own for each test of a run:
    /// the namespaces are named after the process, the addresses after `net`).
    pub fn new(net: u8) -> Self {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let id = format!(
            "{}{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let hosts = Self {
            net,
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

    /// The address of `host` (0: A, 1: B) on the link.
    pub fn address(&self, host: usize) -> String {
        format!("10.231.{}.{}", self.net, host + 1)
    }

    /// Drops `percent` % of the packets each host sends on the link, at random.
    pub fn lose(&self, percent: u32) {
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
    pub fn dropped(&self) -> u64 {
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
    pub fn link(&self, up: bool) {
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
pub struct Running {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: Receiver<String>,
    seen: Vec<String>,
}

impl Running {
    /// Starts `exe ARGS…` in `host` (0: A, 1: B) with `env` added and the test's own
    /// `CYCLONEDDS_URI` and Zenoh configuration variables removed (each host chooses its own
    /// interface, each Zenoh process gets its configuration from `env`).
    pub fn start(
        hosts: &Hosts,
        host: usize,
        exe: &str,
        args: &[&str],
        env: &[(&str, &str)],
    ) -> Self {
        let mut child = Command::new("ip")
            .args(["netns", "exec", &hosts.namespaces[host], exe])
            .args(args)
            .env_remove("CYCLONEDDS_URI")
            .env_remove("ZENOH_CONFIG_OVERRIDE")
            .env_remove("ZENOH_SESSION_CONFIG_URI")
            .env_remove("ZENOH_ROUTER_CONFIG_URI")
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
    pub fn next_line(&mut self) -> String {
        match self.lines.recv_timeout(WAIT) {
            Ok(line) => {
                self.seen.push(line.clone());
                line
            }
            Err(_) => panic!("no line within {WAIT:?}; saw {:#?}", self.seen),
        }
    }

    /// Every line it printed so far, without waiting (for a failure's message).
    pub fn lines_so_far(&mut self) -> &[String] {
        while let Ok(line) = self.lines.try_recv() {
            self.seen.push(line);
        }
        &self.seen
    }

    /// Sends one command line, not waiting for its answer.
    pub fn send(&mut self, command: &str) {
        let stdin = self.stdin.as_mut().expect("stdin open");
        writeln!(stdin, "{command}").expect("write a command");
        stdin.flush().expect("flush");
    }

    /// Sends one command line and returns the answer line.
    pub fn ask(&mut self, command: &str) -> String {
        self.send(command);
        self.next_line()
    }

    /// Closes its standard input (the caller and the server end on it) and returns every line
    /// it printed.
    pub fn finish(mut self) -> Vec<String> {
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

/// How many times a server (`horus_add_two_ints_server`) handled each request, by its `a`, from
/// the server's `handling <a>` lines.
pub fn times_handled(lines: &[String]) -> BTreeMap<&str, usize> {
    let mut times: BTreeMap<&str, usize> = BTreeMap::new();
    for line in lines {
        if let Some(a) = line.strip_prefix("handling ") {
            *times.entry(a).or_default() += 1;
        }
    }
    times
}
