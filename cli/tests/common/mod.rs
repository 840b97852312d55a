//! Helpers for the CLI's output tests: the `horus-ros` binary, independent Cyclone DDS peers
//! (the Python programs of `interop-tests/peers/`), and retries until discovery has settled.
//!
//! Run these tests inside the private network namespace (`scripts/isolated`).

#![allow(dead_code)]

pub mod daemon;
pub mod fibonacci;
pub mod streaming;

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
pub use streaming::Streaming;

/// How long a peer may take to start and print its JSON line (Python start-up included).
pub const PEER_START: Duration = Duration::from_secs(8);
/// How long a command's output may take to reach the expected text (discovery settling).
pub const SETTLE: Duration = Duration::from_secs(6);
/// How long peers stay up unless the test ends first (they are killed when dropped).
pub const LINGER: &str = "30";

/// The Python interpreter with the `cyclonedds` package (as interop-tests: the
/// `HORUS_ROS_INTEROP_PYTHON` variable, else the workspace's venv, else `python3`).
pub fn python() -> PathBuf {
    horus_ros_test_support::jazzy::python()
}

/// The install prefix of the Jazzy wheels, the venv of [`python`]: an `AMENT_PREFIX_PATH` with
/// every Jazzy message package (their interface files under `share/`).
pub fn jazzy_prefix() -> PathBuf {
    let share = horus_ros_test_support::jazzy::share_dir().unwrap_or_else(|e| panic!("{e}"));
    let prefix = share.parent().map(PathBuf::from).unwrap_or_default();
    assert!(
        prefix
            .join("share/ament_index/resource_index/rosidl_interfaces")
            .is_dir(),
        "no Jazzy install under {} (scripts/setup installs it)",
        prefix.display()
    );
    prefix
}

/// `interop-tests/peers/<name>`.
pub fn peer_script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../interop-tests/peers")
        .join(name)
}

/// `cli/tests/peers/<name>`: the CLI's own peers (a real rclpy node, bare DDS participants).
pub fn cli_peer_script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/peers")
        .join(name)
}

/// Cyclone DDS configuration for the peers: loopback only, with multicast.
pub fn cyclone_config() -> String {
    interop_tests::cyclone_config()
}

/// A running peer (a Python program) and the JSON line it printed at start (its GIDs); its stdin
/// is a pipe held open while it runs; killed when dropped.
pub struct Peer {
    process: Streaming,
    stdin: Option<std::process::ChildStdin>,
    /// The peer's first line, parsed.
    pub created: Value,
}

impl Peer {
    /// Starts `interop-tests/peers/<script>` with `args` and waits for its first JSON line.
    pub fn start(script: &str, args: &[&str]) -> Self {
        Self::start_path(&peer_script(script), args, PEER_START)
    }

    /// Starts the Python program at `path` with `args` and waits at most `limit` for its first
    /// JSON line.
    pub fn start_path(path: &std::path::Path, args: &[&str], limit: Duration) -> Self {
        let script = path.display();
        let mut process = Streaming::spawn(
            Command::new(python())
                .arg(path)
                .args(args)
                .env("CYCLONEDDS_URI", cyclone_config())
                .stdin(Stdio::piped())
                .stderr(Stdio::inherit()),
        )
        .unwrap_or_else(|e| panic!("start {script} with {:?}: {e}", python()));
        let stdin = process.child().stdin.take();
        let Some(line) = process.next_line(limit) else {
            panic!("{script} printed nothing within {limit:?}");
        };
        let created = serde_json::from_str(line.trim())
            .unwrap_or_else(|e| panic!("{script} printed {line:?}: {e}"));
        Self {
            process,
            stdin,
            created,
        }
    }

    /// The next `n` lines the peer prints, each within `timeout`.
    pub fn lines(&mut self, n: usize, timeout: Duration) -> Vec<String> {
        (0..n)
            .map(|i| {
                self.process
                    .next_line(timeout)
                    .unwrap_or_else(|| panic!("peer line {i} of {n} did not come"))
            })
            .collect()
    }

    /// The next line the peer prints, if one comes by `deadline`.
    pub fn line_by(&mut self, deadline: Instant) -> Option<String> {
        self.process
            .next_line(deadline.saturating_duration_since(Instant::now()))
    }

    /// Writes `line` and a newline to the peer's stdin (a request, for the peers that take them).
    pub fn send(&mut self, line: &str) {
        use std::io::Write;
        let stdin = self.stdin.as_mut().expect("the peer's stdin");
        writeln!(stdin, "{line}")
            .and_then(|()| stdin.flush())
            .expect("write to the peer's stdin");
    }

    /// A string field of the start line, by JSON pointer (e.g. `/server/request_reader`).
    pub fn field(&self, pointer: &str) -> String {
        self.created
            .pointer(pointer)
            .and_then(Value::as_str)
            .unwrap_or_else(|| panic!("no {pointer} in {}", self.created))
            .to_owned()
    }
}

/// One run of the CLI.
#[derive(Debug, Clone)]
pub struct Run {
    /// What it printed on stdout.
    pub stdout: String,
    /// What it printed on stderr.
    pub stderr: String,
    /// Its exit code (`None`: killed by a signal, or at [`RUN_LIMIT`]).
    pub code: Option<i32>,
    /// Its process id (its hidden node is `_horus_ros_<pid>`).
    pub pid: u32,
}

/// The longest a [`horus`] run may take before it is killed (its exit code is then `None`):
/// far above any `--spin-time` or `--timeout` the tests give.
pub const RUN_LIMIT: Duration = Duration::from_secs(120);

/// Runs `horus-ros --domain-id <domain> --no-daemon <args…>` (inside the test's namespace), at
/// most [`RUN_LIMIT`]: a command that discovers the graph itself and neither uses nor starts a
/// daemon (what a query did before queries started the daemon).
pub fn horus(domain: u32, args: &[&str]) -> Run {
    let mut all = vec!["--no-daemon"];
    all.extend_from_slice(args);
    horus_as_typed(domain, &all)
}

/// Runs `horus-ros --domain-id <domain> <args…>` as a user types it: a query uses the daemon of
/// its graph and starts one when none runs (guard it: [`daemon::DaemonGuard`]). At most
/// [`RUN_LIMIT`].
pub fn horus_as_typed(domain: u32, args: &[&str]) -> Run {
    horus_with_env(domain, &[], args)
}

/// [`horus_as_typed`] with the variables `env` set.
pub fn horus_with_env(domain: u32, env: &[(&str, &str)], args: &[&str]) -> Run {
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
    let out =
        horus_ros_test_support::wait_with_output(&mut child, RUN_LIMIT).expect("horus-ros output");
    Run {
        code: out.code(),
        stdout: out.stdout,
        stderr: out.stderr,
        pid,
    }
}

/// Runs the command until its stdout is `expected(run)` (the graph may still be settling),
/// at most [`SETTLE`]; then asserts it line for line and returns the run.
pub fn expect_stdout(domain: u32, args: &[&str], expected: impl Fn(&Run) -> String) -> Run {
    expect_stdout_of(horus, domain, args, expected)
}

/// [`expect_stdout`] with the command run by `run` ([`horus`] or [`horus_as_typed`]).
pub fn expect_stdout_of(
    run: fn(u32, &[&str]) -> Run,
    domain: u32,
    args: &[&str],
    expected: impl Fn(&Run) -> String,
) -> Run {
    let command = run;
    let deadline = Instant::now() + SETTLE;
    loop {
        let run = command(domain, args);
        let want = expected(&run);
        if run.stdout == want || Instant::now() >= deadline {
            assert_lines(&run, &want, args);
            return run;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Like [`expect_stdout`] with a fixed text.
pub fn expect(domain: u32, args: &[&str], expected: &str) -> Run {
    expect_stdout(domain, args, |_| expected.to_owned())
}

/// Like [`expect`], the command run as typed ([`horus_as_typed`]: through the daemon).
pub fn expect_as_typed(domain: u32, args: &[&str], expected: &str) -> Run {
    expect_stdout_of(horus_as_typed, domain, args, |_| expected.to_owned())
}

/// Asserts stdout equals `want`, line by line, with a readable failure.
pub fn assert_lines(run: &Run, want: &str, args: &[&str]) {
    let got: Vec<&str> = run.stdout.split('\n').collect();
    let exp: Vec<&str> = want.split('\n').collect();
    for (i, (g, e)) in got.iter().zip(&exp).enumerate() {
        assert_eq!(
            g,
            e,
            "`horus-ros {}` line {} differs\n--- got:\n{}\n--- expected:\n{}\n--- stderr:\n{}",
            args.join(" "),
            i + 1,
            run.stdout,
            want,
            run.stderr
        );
    }
    assert_eq!(
        run.stdout,
        want,
        "`horus-ros {}`: different line count\n--- stderr:\n{}",
        args.join(" "),
        run.stderr
    );
}

/// Runs a command that must fail: exit 1, nothing on stdout, `stderr` exactly.
pub fn expect_failure(domain: u32, args: &[&str], stderr: &str) {
    let run = horus(domain, args);
    assert_eq!(run.code, Some(1), "`horus-ros {}`: {run:?}", args.join(" "));
    assert_eq!(run.stdout, "", "`horus-ros {}`", args.join(" "));
    assert_eq!(run.stderr, stderr, "`horus-ros {}`", args.join(" "));
}

/// Runs a `--json` command until it succeeds, its output parses and `check` accepts it, at
/// most [`SETTLE`]; returns the document. A fresh process may not have discovered what it is
/// asked about yet (it then fails, e.g. with "Unknown service"), as with [`expect_stdout`].
pub fn expect_json(domain: u32, args: &[&str], check: impl Fn(&Value) -> bool) -> Value {
    let deadline = Instant::now() + SETTLE;
    loop {
        let run = horus(domain, args);
        if run.code != Some(0) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(100));
            continue;
        }
        assert_eq!(run.code, Some(0), "`horus-ros {}`: {run:?}", args.join(" "));
        let doc: Value = serde_json::from_str(&run.stdout).unwrap_or_else(|e| {
            panic!(
                "`horus-ros {}` printed invalid JSON ({e}):\n{}",
                args.join(" "),
                run.stdout
            )
        });
        if check(&doc) {
            return doc;
        }
        assert!(
            Instant::now() < deadline,
            "`horus-ros {}`: unexpected document\n{}",
            args.join(" "),
            run.stdout
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The seven QoS lines of an rclpy `TopicEndpointInfo` block (two spaces of indent).
pub fn topic_qos(reliability: &str, history: &str, durability: &str) -> String {
    format!(
        "QoS profile:\n  Reliability: {reliability}\n  History (Depth): {history}\n  \
         Durability: {durability}\n  Lifespan: Infinite\n  Deadline: Infinite\n  \
         Liveliness: AUTOMATIC\n  Liveliness lease duration: Infinite\n"
    )
}

/// The seven QoS lines of one endpoint in an rclpy `ServiceEndpointInfo` block (six spaces).
pub fn service_qos(reliability: &str, history: &str, durability: &str) -> String {
    format!(
        "      Reliability: {reliability}\n      History (Depth): {history}\n      \
         Durability: {durability}\n      Lifespan: Infinite\n      Deadline: Infinite\n      \
         Liveliness: AUTOMATIC\n      Liveliness lease duration: Infinite\n"
    )
}
