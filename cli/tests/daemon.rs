//! `horus-ros daemon`: its lifecycle and messages (ros2cli's), answers through it equal to direct
//! discovery's, a Fast DDS node answered at once, nodes leaving, the idle timeout, the daemon's
//! settings keeping it to its own graph, and the fallback to direct discovery when the daemon is
//! dead or does not answer.
//!
//! Every daemon a test starts becomes a child of the test process (it is made the reaper of
//! orphans), is found by its command line and guarded: it is killed by its pid and reaped when
//! the guard drops, whatever the test's outcome. Each test has its own DDS domain. Run inside the
//! private network namespace: `scripts/isolated cargo test -p horus-ros-cli --test daemon`.

mod common;

use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::sync::Once;
use std::time::{Duration, Instant};

use common::{expect, horus, Peer, Run, LINGER, RUN_LIMIT, SETTLE};
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::example_interfaces::srv::AddTwoInts;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::Context;
use horus_ros_services::ServiceServerBuilder;
use horus_ros_test_support::wait_with_output;
use interop_tests::rclpy::RclpyPeer;
use nix::sys::signal::{kill, Signal};
use nix::sys::wait::{waitpid, WaitStatus};
use nix::unistd::Pid;
use serde_json::Value;

/// How long a daemon may take to exit once it should.
const EXIT_LIMIT: Duration = Duration::from_secs(20);
/// How long a daemon's graph may take to show a Fast DDS peer's node.
const FAST_DDS_WARM_UP: Duration = Duration::from_secs(20);

/// Makes this process the reaper of its descendants' orphans, so that a daemon (left by
/// `daemon start` when it exits) becomes its child: it can then be waited for and reaped, and
/// its pid cannot be reused while the guard holds it.
fn adopt_orphans() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        nix::sys::prctl::set_child_subreaper(true).expect("PR_SET_CHILD_SUBREAPER");
    });
}

/// A daemon process of this test: killed (SIGKILL, by pid) and reaped when dropped, unless it
/// has exited and been reaped already.
struct DaemonGuard {
    pid: u32,
    exit: Receiver<WaitStatus>,
    reaped: Option<WaitStatus>,
}

impl DaemonGuard {
    /// The daemon of `domain` among this process's children (there must be exactly one).
    fn adopt(domain: u32) -> Self {
        let pids = daemon_children(domain);
        assert_eq!(
            pids.len(),
            1,
            "daemons of domain {domain} among our children: {pids:?}"
        );
        let pid = pids[0];
        let (tx, exit) = mpsc::channel();
        std::thread::spawn(move || loop {
            match waitpid(Pid::from_raw(pid as i32), None) {
                Ok(status @ (WaitStatus::Exited(..) | WaitStatus::Signaled(..))) => {
                    let _ = tx.send(status);
                    return;
                }
                Ok(_) | Err(nix::errno::Errno::EINTR) => {}
                Err(_) => return,
            }
        });
        Self {
            pid,
            exit,
            reaped: None,
        }
    }

    /// Waits at most `limit` for the daemon to exit; its exit status if it did.
    fn wait_exit(&mut self, limit: Duration) -> Option<WaitStatus> {
        if self.reaped.is_none() {
            self.reaped = self.exit.recv_timeout(limit).ok();
        }
        self.reaped
    }

    /// Sends `signal` to the daemon (it must not have been reaped).
    fn signal(&self, signal: Signal) {
        assert!(self.reaped.is_none(), "the daemon was reaped already");
        kill(Pid::from_raw(self.pid as i32), signal).expect("signal the daemon");
    }
}

impl Drop for DaemonGuard {
    fn drop(&mut self) {
        if self.reaped.is_none() {
            let pid = Pid::from_raw(self.pid as i32);
            // Not reaped, so the pid is still this daemon (a zombie at worst).
            let _ = kill(pid, Signal::SIGKILL);
            let _ = kill(pid, Signal::SIGCONT);
            let _ = self.exit.recv_timeout(EXIT_LIMIT);
        }
    }
}

/// The pids of this process's children that are `horus-ros … daemon _run` of `domain`.
fn daemon_children(domain: u32) -> Vec<u32> {
    let me = std::process::id();
    let domain = domain.to_string();
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").expect("/proc").flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
            continue;
        };
        // `pid (comm) state ppid …`: the command may hold spaces and parentheses.
        let Some((_, rest)) = stat.rsplit_once(')') else {
            continue;
        };
        let ppid = rest.split_whitespace().nth(1).and_then(|p| p.parse().ok());
        if ppid != Some(me) {
            continue;
        }
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<String> = cmdline
            .split(|b| *b == 0)
            .map(|a| String::from_utf8_lossy(a).into_owned())
            .collect();
        let is_run = args.windows(2).any(|w| w[0] == "daemon" && w[1] == "_run");
        let in_domain = args
            .windows(2)
            .any(|w| w[0] == "--domain-id" && w[1] == domain);
        if is_run && in_domain {
            found.push(pid);
        }
    }
    found
}

/// `horus-ros --domain-id <domain> <args…>` with `env` added.
fn horus_env(domain: u32, env: &[(&str, &str)], args: &[&str]) -> Run {
    let mut command = Command::new(env!("CARGO_BIN_EXE_horus-ros"));
    command
        .arg("--domain-id")
        .arg(domain.to_string())
        .args(args)
        .env_remove("ROS_DOMAIN_ID")
        .env("RUST_LOG", "error")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in env {
        command.env(k, v);
    }
    let mut child = command.spawn().expect("start horus-ros");
    let pid = child.id();
    let out = wait_with_output(&mut child, RUN_LIMIT).expect("horus-ros output");
    Run {
        code: out.code(),
        stdout: out.stdout,
        stderr: out.stderr,
        pid,
    }
}

/// Runs `daemon start <args…>` (with `env`), asserts its message, and guards the daemon.
fn start_daemon(domain: u32, env: &[(&str, &str)], args: &[&str]) -> DaemonGuard {
    adopt_orphans();
    let mut start = vec!["daemon", "start"];
    start.extend_from_slice(args);
    let run = horus_env(domain, env, &start);
    // Guarded first, so that it is stopped even if the message is wrong.
    let guard = (run.code == Some(0)).then(|| DaemonGuard::adopt(domain));
    assert_eq!(
        (run.code, run.stdout.as_str(), run.stderr.as_str()),
        (Some(0), "The daemon has been started\n", ""),
        "daemon start"
    );
    guard.expect("guarded")
}

/// `--json daemon status`, parsed.
fn status_json(domain: u32, env: &[(&str, &str)]) -> Value {
    let run = horus_env(domain, env, &["--json", "daemon", "status"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{e}: {run:?}"))
}

fn context(domain: u32) -> Context {
    Context::builder()
        .domain_id(domain)
        .build()
        .expect("context")
}

/// Runs `args` until stdout has a line equal to `line`, at most `limit`; returns the last run.
fn until_line(domain: u32, args: &[&str], line: &str, limit: Duration) -> Run {
    let deadline = Instant::now() + limit;
    loop {
        let run = horus(domain, args);
        if run.stdout.lines().any(|l| l == line) || Instant::now() >= deadline {
            return run;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn lifecycle_and_messages() {
    const D: u32 = 181;
    let plain = |args: &[&str], want: &str| {
        let run = horus(D, args);
        assert_eq!(
            (run.code, run.stdout.as_str(), run.stderr.as_str()),
            (Some(0), want, ""),
            "{args:?}"
        );
    };
    plain(&["daemon", "status"], "The daemon is not running\n");
    plain(&["daemon", "stop"], "The daemon is not running\n");
    let not_running = status_json(D, &[]);
    assert_eq!(not_running["running"], Value::Bool(false), "{not_running}");

    let mut daemon = start_daemon(D, &[], &[]);
    plain(&["daemon", "start"], "The daemon is already running\n");
    plain(&["daemon", "status"], "The daemon is running\n");
    let status = status_json(D, &[]);
    assert_eq!(status["running"], Value::Bool(true), "{status}");
    assert_eq!(status["pid"], Value::from(daemon.pid), "{status}");
    assert_eq!(status["domain_id"], Value::from(D), "{status}");
    // ros2cli's default: two hours.
    assert_eq!(status["idle_timeout_s"], Value::from(7200), "{status}");
    assert_eq!(status["socket"], not_running["socket"], "{status}");
    let backend = std::env::var("HORUS_ROS_BACKEND")
        .ok()
        .filter(|b| !b.is_empty())
        .unwrap_or_else(|| "rustdds".to_owned());
    assert_eq!(status["backend"], Value::from(backend), "{status}");
    let node = status["node_name"].as_str().expect("node_name").to_owned();
    assert!(
        node.starts_with(&format!("_horus_ros_daemon_{D}_")),
        "{node}"
    );
    let already = horus(D, &["--json", "daemon", "start"]);
    let already: Value = serde_json::from_str(&already.stdout).expect("json");
    assert_eq!(
        already,
        serde_json::json!({"started": false, "pid": daemon.pid})
    );

    // The daemon's own hidden node is what `node list -a` shows through it (no node of the
    // command's own, as with ros2cli's daemon).
    let run = until_line(D, &["node", "list", "-a"], &format!("/{node}"), SETTLE);
    assert_eq!(run.stdout, format!("/{node}\n"), "{run:?}");

    plain(&["daemon", "stop"], "The daemon has been stopped\n");
    // `stop` returns once the daemon has exited.
    assert_eq!(
        daemon.wait_exit(Duration::from_secs(2)),
        Some(WaitStatus::Exited(Pid::from_raw(daemon.pid as i32), 0))
    );
    plain(&["daemon", "status"], "The daemon is not running\n");
    let stopped = horus(D, &["--json", "daemon", "stop"]);
    assert_eq!(stopped.stdout, "{\n  \"stopped\": false\n}\n");

    // Started again, it is a new process.
    let second = start_daemon(D, &[], &["--idle-timeout", "60"]);
    assert_ne!(second.pid, daemon.pid);
    assert_eq!(status_json(D, &[])["idle_timeout_s"], Value::from(60));
    let stopped = horus(D, &["--json", "daemon", "stop"]);
    assert_eq!(stopped.stdout, "{\n  \"stopped\": true\n}\n");
}

#[test]
fn answers_equal_direct_discovery() {
    const D: u32 = 182;
    let d = D.to_string();
    let hash = Time::type_hash().to_string();
    let _peer = Peer::start(
        "cyclone_ros_participant.py",
        &[&d, "/peer_ns", "cyclone_node", &hash, LINGER, "/peer_add"],
    );
    let _server = Peer::start(
        "cyclone_add_two_ints_server.py",
        &[&d, "/add_two_ints", LINGER],
    );
    let ctx = context(D);
    let node = ctx.create_node("horus_node", "/ours").expect("node");
    let _publisher = node
        .create_publisher::<Time>("stamps", &Qos::default())
        .expect("publisher");
    let _daemon = start_daemon(D, &[], &[]);

    let nodes = "/add_two_ints_server\n/ours/horus_node\n/peer_ns/cyclone_node\n";
    let through_daemon = expect(D, &["node", "list"], nodes);
    assert_eq!(through_daemon.stderr, "");
    for args in [
        &["node", "list"][..],
        &["node", "list", "-c"],
        &["node", "info", "/peer_ns/cyclone_node"],
        &["node", "info", "/ours/horus_node"],
        &["topic", "list", "-t"],
        &["topic", "list", "-v"],
        &["topic", "info", "/peer_ns/chatter", "-v"],
        &["topic", "info", "/ours/stamps", "-v"],
        &["service", "list", "-t"],
        &["service", "type", "/add_two_ints"],
        &["service", "find", "example_interfaces/srv/AddTwoInts"],
        &["service", "info", "/add_two_ints", "-v"],
        &["service", "info", "/peer_add", "-v"],
        &["graph"],
        &["--json", "node", "list"],
        &["--json", "graph"],
    ] {
        let mut direct_args = vec!["--no-daemon"];
        direct_args.extend_from_slice(args);
        // Direct discovery may need a few tries to see everything; the daemon's answer must then
        // be the same. The direct runs' own participants come and go in the daemon's graph: one
        // that has not announced its nodes yet (or is leaving) makes the daemon's answer honestly
        // incomplete (one line on stderr), so that too is tried again until the deadline.
        let deadline = Instant::now() + SETTLE;
        loop {
            let daemon = horus(D, args);
            let direct = horus(D, &direct_args);
            assert_eq!(daemon.code, Some(0), "{args:?}: {daemon:?}");
            if daemon.stderr.is_empty() && daemon.stdout == direct.stdout {
                assert!(!daemon.stdout.is_empty(), "{args:?}");
                break;
            }
            assert!(
                Instant::now() < deadline,
                "`horus-ros {}` differs through the daemon\n--- daemon:\n{}{}\n--- direct:\n{}\n{}",
                args.join(" "),
                daemon.stdout,
                daemon.stderr,
                direct.stdout,
                direct.stderr
            );
        }
    }
    // The domain is the daemon's.
    assert!(horus(D, &["graph"])
        .stdout
        .starts_with(&format!("Domain {D}: 3 nodes")));
}

#[test]
fn fast_dds_node_is_answered_at_once() {
    const D: u32 = 183;
    let mut peer = RclpyPeer::start(&serde_json::json!({
        "domain": D, "namespace": "/fast_ns", "name": "fast_node",
        "servers": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
        "clients": [{"service": "/fast_ns/set", "type": "std_srvs/srv/SetBool"}],
    }))
    .expect("start the rclpy peer");
    peer.ready(Duration::from_secs(20))
        .expect("the rclpy node is up");
    let _daemon = start_daemon(D, &[], &[]);
    // The daemon's graph warms up: Fast DDS answers a new participant's discovery slowly (a
    // reader matched just after one of its heartbeats gets ros_discovery_info at the next).
    let run = until_line(D, &["node", "list"], "/fast_ns/fast_node", FAST_DDS_WARM_UP);
    assert_eq!(run.stdout, "/fast_ns/fast_node\n", "{run:?}");
    // Warm, every query answers completely at once, with the default --spin-time: no warning.
    for _ in 0..3 {
        let run = horus(D, &["node", "list"]);
        assert_eq!(
            (run.code, run.stdout.as_str(), run.stderr.as_str()),
            (Some(0), "/fast_ns/fast_node\n", "")
        );
    }
    let info = horus(D, &["node", "info", "/fast_ns/fast_node"]);
    assert_eq!(info.stderr, "");
    assert!(
        info.stdout
            .contains("  Service Servers:\n    /fast_ns/fast_node/describe_parameters: "),
        "{info:?}"
    );
    assert!(
        info.stdout.contains("    /fast_ns/set: std_srvs/srv/SetBool\n  Service Clients:\n    /fast_ns/set: std_srvs/srv/SetBool\n"),
        "{info:?}"
    );
    let servers = horus(D, &["service", "info", "/fast_ns/set"]);
    assert_eq!(
        servers.stdout,
        "Type: std_srvs/srv/SetBool\nClients count: 1\nServices count: 1\n"
    );
}

#[test]
fn node_that_leaves_is_gone() {
    const D: u32 = 184;
    let _daemon = start_daemon(D, &[], &[]);
    let ctx = context(D);
    let staying = ctx.create_node("staying", "/").expect("node");
    let leaving = ctx.create_node("leaving", "/").expect("node");
    let _server = ServiceServerBuilder::<AddTwoInts>::new()
        .node(&leaving)
        .name("/leaving_add")
        .on_request(|r| {
            Ok(horus_ros_msgs::example_interfaces::srv::AddTwoIntsResponse { sum: r.a + r.b })
        })
        .build()
        .expect("server");
    expect(D, &["node", "list"], "/leaving\n/staying\n");
    expect(D, &["service", "list"], "/leaving_add\n");
    drop(_server);
    drop(leaving);
    expect(D, &["node", "list"], "/staying\n");
    expect(D, &["service", "list"], "");
    // A whole participant leaving.
    drop(staying);
    drop(ctx);
    expect(D, &["node", "list"], "");
}

#[test]
fn idle_timeout_ends_it() {
    const D: u32 = 185;
    let mut daemon = start_daemon(D, &[], &["--idle-timeout", "2"]);
    assert_eq!(status_json(D, &[])["idle_timeout_s"], Value::from(2));
    // A query is activity.
    let run = horus(D, &["node", "list"]);
    assert_eq!((run.code, run.stderr.as_str()), (Some(0), ""));
    // Then nothing: it exits by itself, cleanly.
    assert_eq!(
        daemon.wait_exit(EXIT_LIMIT),
        Some(WaitStatus::Exited(Pid::from_raw(daemon.pid as i32), 0)),
        "the daemon did not exit after its idle timeout"
    );
    let run = horus(D, &["daemon", "status"]);
    assert_eq!(run.stdout, "The daemon is not running\n");
}

#[test]
fn killed_daemon_means_direct_discovery() {
    const D: u32 = 186;
    let ctx = context(D);
    let _node = ctx.create_node("here", "/").expect("node");
    let mut daemon = start_daemon(D, &[], &[]);
    expect(D, &["node", "list"], "/here\n");
    daemon.signal(Signal::SIGKILL);
    assert!(matches!(
        daemon.wait_exit(EXIT_LIMIT),
        Some(WaitStatus::Signaled(_, Signal::SIGKILL, _))
    ));
    // Its socket went with it: the daemon is simply not running, as if never started.
    let run = horus(D, &["node", "list", "-a"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    assert_eq!(run.stderr, "", "{run:?}");
    // Our own node in the list: this answer is our own discovery's.
    assert!(
        run.stdout
            .lines()
            .any(|l| l == format!("/_horus_ros_{}", run.pid)),
        "{run:?}"
    );
    assert_eq!(
        horus(D, &["daemon", "status"]).stdout,
        "The daemon is not running\n"
    );
    // And a new one can start.
    let _again = start_daemon(D, &[], &[]);
    assert_eq!(
        horus(D, &["daemon", "stop"]).stdout,
        "The daemon has been stopped\n"
    );
}

/// The one warning line of a daemon that did not answer, then the direct answer.
fn assert_fell_back(run: &Run, pid: u32) {
    assert_eq!(run.code, Some(0), "{run:?}");
    let prefix = format!("WARNING: the daemon (pid {pid}) did not answer: ");
    assert!(
        run.stderr.starts_with(&prefix)
            && run.stderr.ends_with("; discovering the graph directly\n")
            && run.stderr.lines().count() == 1,
        "{run:?}"
    );
    assert!(
        run.stdout
            .lines()
            .any(|l| l == format!("/_horus_ros_{}", run.pid)),
        "not the direct answer: {run:?}"
    );
}

#[test]
fn stopped_daemon_means_a_warning_and_direct_discovery() {
    const D: u32 = 187;
    let ctx = context(D);
    let _node = ctx.create_node("here", "/").expect("node");
    let daemon = start_daemon(D, &[], &[]);
    expect(D, &["node", "list"], "/here\n");
    daemon.signal(Signal::SIGSTOP);
    let run = horus(D, &["--spin-time", "0.3", "node", "list", "-a"]);
    assert_fell_back(&run, daemon.pid);
    assert!(run.stdout.lines().any(|l| l == "/here"), "{run:?}");
    // The verbs that need the daemon say what is wrong, and fail.
    for verb in ["status", "start"] {
        let run = horus(D, &["daemon", verb]);
        assert_eq!(run.code, Some(1), "{verb}: {run:?}");
        assert!(
            run.stderr
                .starts_with(&format!("the daemon (pid {}) did not answer", daemon.pid)),
            "{verb}: {run:?}"
        );
    }
    daemon.signal(Signal::SIGCONT);
    let run = horus(D, &["daemon", "stop"]);
    assert_eq!(run.stdout, "The daemon has been stopped\n", "{run:?}");
}

#[test]
fn socket_held_by_something_else_means_a_warning_and_direct_discovery() {
    const D: u32 = 188;
    use std::os::linux::net::SocketAddrExt;
    let ctx = context(D);
    let _node = ctx.create_node("here", "/").expect("node");
    // Something that is not a daemon holds the daemon's socket name and never answers.
    let name = status_json(D, &[])["socket"]
        .as_str()
        .expect("socket name")
        .to_owned();
    let address = std::os::unix::net::SocketAddr::from_abstract_name(name.as_bytes())
        .expect("abstract address");
    let squatter = std::os::unix::net::UnixListener::bind_addr(&address).expect("bind");
    let run = horus(D, &["--spin-time", "0.3", "node", "list", "-a"]);
    assert_fell_back(&run, std::process::id());
    assert!(run.stdout.lines().any(|l| l == "/here"), "{run:?}");
    // `--no-daemon` does not even try (no warning). Retried while discovery settles: on a loaded
    // machine our participant can take longer than the CLI's shortest wait to be discovered.
    let run = expect(D, &["--no-daemon", "node", "list"], "/here\n");
    assert_eq!(run.stderr, "", "{run:?}");
    drop(squatter);
    let run = horus(D, &["daemon", "status"]);
    assert_eq!(run.stdout, "The daemon is not running\n");
}

#[test]
fn daemon_serves_only_its_discovery_settings() {
    const D: u32 = 189;
    // Whatever range the environment sets (scripts/test may set LOCALHOST), static peers make
    // another graph.
    let peers = [("ROS_STATIC_PEERS", "127.0.0.1")];
    let _daemon = start_daemon(D, &peers, &[]);
    let status = status_json(D, &peers);
    assert_eq!(
        status["static_peers"],
        serde_json::json!(["127.0.0.1"]),
        "{status}"
    );
    // Other discovery settings are another graph: that daemon is not this command's.
    let run = horus(D, &["daemon", "status"]);
    assert_eq!(run.stdout, "The daemon is not running\n");
    let run = horus(D, &["node", "list", "-a"]);
    assert_eq!(run.stderr, "", "{run:?}");
    assert!(
        run.stdout
            .lines()
            .any(|l| l == format!("/_horus_ros_{}", run.pid)),
        "not answered by its own discovery: {run:?}"
    );
    // The same settings use it.
    let node = status["node_name"].as_str().expect("node_name").to_owned();
    // The direct run above has left; the daemon may hear of it (its participant's dispose) a
    // little after this command asks.
    let want = format!("/{node}\n");
    let deadline = Instant::now() + SETTLE;
    let run = loop {
        let run = horus_env(D, &peers, &["node", "list", "-a"]);
        if run.stdout == want || Instant::now() >= deadline {
            break run;
        }
    };
    assert_eq!(run.stdout, want, "{run:?}");
    let run = horus_env(D, &peers, &["daemon", "stop"]);
    assert_eq!(run.stdout, "The daemon has been stopped\n");
}

/// A DDS participant that never announces nodes (a bare Cyclone DDS application).
struct BareParticipant(Child);

impl Drop for BareParticipant {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn incomplete_daemon_graph_gives_the_same_warning() {
    const D: u32 = 180;
    let _daemon = start_daemon(D, &[], &[]);
    // It reads ros_discovery_info but publishes none, so the graph cannot become consistent.
    let _bare = BareParticipant(
        Command::new(common::python())
            .arg(common::peer_script("cyclone_discovery_info.py"))
            .args([&D.to_string(), "/", "never_there", "0", "0", "60"])
            .env("CYCLONEDDS_URI", common::cyclone_config())
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("start the bare participant"),
    );
    let deadline = Instant::now() + SETTLE;
    let run = loop {
        let run = horus(D, &["--spin-time", "0.2", "node", "list"]);
        if !run.stderr.is_empty() || Instant::now() >= deadline {
            break run;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(
        run.stderr
            .starts_with("WARNING: discovery incomplete after --spin-time 0.2 s: participant ")
            && run.stderr.ends_with(
                " has not announced its nodes (ros_discovery_info); the answer may be \
                 incomplete (raise --spin-time)\n"
            ),
        "{run:?}"
    );
}
