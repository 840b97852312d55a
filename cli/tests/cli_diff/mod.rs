//! The live comparison of `horus-ros ARGS` with ros2cli 0.32.2's `ros2 ARGS` on one graph (see
//! `tests/cli_diff.rs`): the cases ([`cases`]), the graph they run against ([`graph`]), how
//! each case is run and compared, and the table of verbs that reports it.

pub mod cases;
pub mod graph;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::process::Stdio;
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

use graph::{batched_command, tool_command, LiveGraph, Tool};
use horus_ros_test_support::jazzy::Rmw;
use regex::Regex;

/// The longest one command may take (discovery, a type look-up, a goal's feedback).
pub const RUN_LIMIT: Duration = Duration::from_secs(30);

/// What is taken out of, or replaced in, both tools' output before they are compared: each is
/// something that changes from one run of the same program to the next. Applied to stdout and
/// stderr of both alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Norm {
    /// `topic echo`: the report of messages lost (`A message was lost!!!` and its two count
    /// lines) — a reader that matches a publisher while it publishes may be told of samples
    /// sent before the match (Fast DDS reports them lost), depending on when it matched.
    LostMessages,
    /// `service call`: `waiting for service to become available...`, printed once per second
    /// that the new client has not yet matched the server (ros2service's `wait_for_service(1.0)`
    /// loop) — how long matching takes.
    WaitingForService,
    /// `topic pub`: `Waiting for at least N matching subscription(s)...`, printed once per second
    /// until the new publisher has matched — how long matching takes.
    WaitingForSubscriptions,
    /// `topic hz|bw|delay`: `WARNING: topic [/t] does not appear to be published yet`, which
    /// ros2topic prints when its new node looks for the topic's type (after its 0.5 s spin)
    /// before discovery has brought the publisher — how long discovery takes.
    NotYetPublished,
    /// horus-ros's `WARNING: discovery incomplete after …`: its discovery wait reached its
    /// bound (4.6 s) before a participant that was starting or leaving at that moment — here,
    /// one of the `ros2` runs started beside it — had announced its nodes or endpoints (ros2cli
    /// waits a fixed 0.5 s and says nothing). The report counts these lines.
    DiscoveryIncomplete,
    /// `action send_goal`: the goal id (`uuid.uuid4()`: random per goal).
    GoalId,
    /// `topic hz|bw|delay`: every number (rates, sizes, delays, window sizes, counts): measured,
    /// so only the shape of the output is compared.
    Numbers,
    /// `topic echo -i`: the message info's timestamps and publication sequence number (when the
    /// message was sent and received, and how many the publisher had sent by then).
    MessageInfo,
    /// An rcl log line (`[WARN] [<time>] [<node>]: …`): its time stamp, and the name of the
    /// command's own hidden node, which carries the process id (`_ros2cli_<pid>`,
    /// `_horus_ros_<pid>`).
    LogLine,
    /// `interface package`: ros2cli prints a Python `set`, whose order follows each process's
    /// randomized string hashes (`PYTHONHASHSEED`); the lines are compared sorted.
    SetOrder,
    /// Zenoh's own warnings, which depend on which sessions come and go meanwhile and how
    /// fast: `Unable to connect to any locator of scouted peer` (a session learnt, through the
    /// router's gossip, of another command's session that has ended since), `Scouting delay
    /// elapsed before start conditions are met` (the session's start took longer than its
    /// scouting delay), `Received ResponseFinal for unknown Request` (a reply's final message
    /// reached a session that had already dropped the query: ros2cli closes its node right
    /// after the reply), `Received Data for unknown expr_id` (a sample for a declaration the
    /// closing session has already dropped), rmw_zenoh_cpp's own `SubscriberCallback triggered
    /// over <key>` (a sample whose callback ran while ros2cli's subscription was going, as its
    /// `--timeout` ended it). Applied to every case (they come on rmw_zenoh_cpp only).
    ZenohLog,
}

impl Norm {
    fn apply(self, text: &str) -> String {
        fn re(pattern: &str) -> Regex {
            Regex::new(pattern).expect("a valid pattern")
        }
        let keep = |drop: &dyn Fn(&str) -> bool| -> String {
            text.split_inclusive('\n').filter(|l| !drop(l)).collect()
        };
        match self {
            Norm::LostMessages => keep(&|l| {
                l == "A message was lost!!!\n"
                    || l.starts_with("\ttotal count change:")
                    || (l.starts_with("\ttotal count: ") && l.ends_with("---\n"))
            }),
            Norm::WaitingForService => {
                keep(&|l| l == "waiting for service to become available...\n")
            }
            Norm::WaitingForSubscriptions => keep(&|l| {
                l.starts_with("Waiting for at least ")
                    && l.ends_with(" matching subscription(s)...\n")
            }),
            Norm::NotYetPublished => keep(&|l| {
                l.starts_with("WARNING: topic [")
                    && l.ends_with("] does not appear to be published yet\n")
            }),
            Norm::DiscoveryIncomplete => keep(&|l| {
                l.starts_with("WARNING: discovery incomplete after ")
                    && l.ends_with("the answer may be incomplete (raise --spin-time)\n")
            }),
            Norm::GoalId => re("Goal accepted with ID: [0-9a-f]{32}")
                .replace_all(text, "Goal accepted with ID: <random>")
                .into_owned(),
            Norm::Numbers => re(r"-?[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?")
                .replace_all(text, "<n>")
                .into_owned(),
            Norm::MessageInfo => re(
                r"(?m)^(publication_sequence_number|received_timestamp|source_timestamp): [0-9]+$",
            )
            .replace_all(text, "$1: <n>")
            .into_owned(),
            Norm::LogLine => {
                re(r"(?m)^\[(\w+)\] \[[0-9]+\.[0-9]+\] \[(_ros2cli|_horus_ros)_[0-9]+\]: ")
                    .replace_all(text, "[$1] [<time>] [<the command's node>]: ")
                    .into_owned()
            }
            Norm::SetOrder => {
                let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
                lines.sort_unstable();
                lines.concat()
            }
            Norm::ZenohLog => keep(&|l| {
                (l.contains(" WARN") || l.contains("ERROR"))
                    && [
                        "Unable to connect to any locator of scouted peer",
                        "Scouting delay elapsed before start conditions are met",
                        "Received ResponseFinal for unknown Request",
                        "Received Data for unknown expr_id",
                        "] [rmw_zenoh_cpp]: SubscriberCallback triggered over ",
                    ]
                    .iter()
                    .any(|m| l.contains(m))
            }),
        }
    }
}

/// A difference that is not timing and is kept, with the reason; the comparison then checks
/// what the reason says instead of equality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Known {
    /// ros2cli crashes: an uncaught Python exception, printed as a traceback on stderr, exit
    /// status 1. horus-ros prints one line saying what is wrong instead; stdout and exit status
    /// must still be equal.
    Ros2Traceback,
}

/// One comparison: `horus-ros ARGS` and `ros2 ARGS`.
#[derive(Debug, Clone)]
pub struct Case {
    /// The arguments both tools get.
    pub args: Vec<String>,
    /// What depends on timing, taken out of both outputs.
    pub norms: Vec<Norm>,
    /// Stream verbs (`hz`, `bw`, `delay`): stop (SIGINT) after this many lines of stdout, and
    /// compare those lines, stderr and the exit status.
    pub stream: Option<usize>,
    /// Standard input (otherwise none).
    pub stdin: Option<String>,
    /// Commands to the peer before each tool's run (`peers/jazzy_live_graph.py`): a case
    /// that changes the graph's state starts both runs from the same state.
    pub setup: Vec<String>,
    /// Commands to the peer after each tool's run, back to the state before `setup`.
    pub teardown: Vec<String>,
    /// Variables removed from horus-ros's environment only (e.g. `AMENT_PREFIX_PATH`: a type
    /// that horus-ros must take from the publisher's node, where ros2cli needs its files).
    pub horus_env_remove: Vec<&'static str>,
    /// A difference kept, with its reason.
    pub known: Option<Known>,
    /// Run with nothing else at once (it creates nodes other cases could see).
    pub alone: bool,
}

impl Case {
    /// The verb: the first two arguments (`topic echo`).
    pub fn verb(&self) -> String {
        self.args
            .iter()
            .take(2)
            .map(String::as_str)
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The command line, quoted as a shell would need it.
    pub fn command_line(&self) -> String {
        self.args
            .iter()
            .map(|a| {
                if a.is_empty() || a.contains([' ', '"', '\'', '{', '[', '*', '$']) {
                    format!("'{}'", a.replace('\'', r"'\''"))
                } else {
                    a.clone()
                }
            })
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn stateful(&self) -> bool {
        !self.setup.is_empty() || !self.teardown.is_empty()
    }

    /// Whether it may run beside other cases ([`batch_key`]): it needs no setup, and adds no
    /// node another case lists.
    fn parallel(&self) -> bool {
        !self.alone && !self.stateful()
    }
}

/// `text` with the normalisations of every case, then the case's `norms`, applied.
fn normalise(norms: &[Norm], text: &str) -> String {
    [Norm::DiscoveryIncomplete, Norm::ZenohLog]
        .iter()
        .chain(norms)
        .fold(text.to_owned(), |t, n| n.apply(&t))
}

/// What one tool printed and how it ended.
#[derive(Debug, Clone)]
pub struct Printed {
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
    /// Exit code (`None`: killed at [`RUN_LIMIT`], or by a signal).
    pub code: Option<i32>,
    /// How long it ran (reported, never compared).
    pub took: Duration,
}

impl Printed {
    fn normalised(&self, norms: &[Norm]) -> Printed {
        let apply = |text: &str| normalise(norms, text);
        Printed {
            stdout: apply(&self.stdout),
            stderr: apply(&self.stderr),
            code: self.code,
            took: self.took,
        }
    }
}

/// How a case came out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// Equal after the case's normalisation.
    Equal,
    /// A kept difference, checked as its reason says.
    Explained(&'static str),
    /// Different: the diff (ros2 `-`, horus-ros `+`).
    Different(String),
}

/// A case run: both outputs and the verdict.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The case.
    pub case: Case,
    /// horus-ros's output.
    pub horus: Printed,
    /// ros2's output.
    pub ros2: Printed,
    /// The verdict.
    pub verdict: Verdict,
}

/// Runs `tool` for `case` ([`run_once`]); a `ros2` run that failed on its own is run once
/// more: one still going at [`RUN_LIMIT`] (ros2cli hangs now and then on a loaded machine — a
/// service reply lost by its new client on Fast DDS, a query to its daemon never answered on
/// rmw_cyclonedds_cpp), or one whose rmw_zenoh_cpp session did not close in time (zenoh-c's
/// `close operation timed out!`, then `Failed to close the session`, exit status 1). Neither
/// is what is compared; a horus-ros run is never repeated.
fn run_tool(rmw: Rmw, tool: Tool, case: &Case) -> Printed {
    let printed = run_once(rmw, tool, case);
    let hung = printed.code.is_none() && case.stream.is_none();
    let not_closed = printed
        .stderr
        .contains("Failed to close the session(Error code: ");
    if tool == Tool::Ros2 && (hung || not_closed) {
        eprintln!(
            "ros2 {} {}: once more",
            case.command_line(),
            if hung {
                "was still going at the time limit"
            } else {
                "failed to close its Zenoh session"
            }
        );
        return run_once(rmw, tool, case);
    }
    printed
}

/// Runs `tool` for `case` to its end, or for a stream case until its lines came.
fn run_once(rmw: Rmw, tool: Tool, case: &Case) -> Printed {
    let mut command = if case.alone {
        tool_command(rmw, tool, &case.args)
    } else {
        batched_command(rmw, tool, &case.args)
    };
    if tool == Tool::Horus {
        for var in &case.horus_env_remove {
            command.env_remove(var);
        }
    }
    command
        .stdin(if case.stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let started = Instant::now();
    let mut child = command
        .spawn()
        .unwrap_or_else(|e| panic!("start {}: {e}", tool.name()));
    if let Some(input) = &case.stdin {
        let mut stdin = child.stdin.take().expect("piped stdin");
        stdin
            .write_all(input.as_bytes())
            .expect("write the command's stdin");
    }
    let Some(lines) = case.stream else {
        let out = horus_ros_test_support::wait_with_output(&mut child, RUN_LIMIT)
            .unwrap_or_else(|e| panic!("{}: {e}", tool.name()));
        let code = out.code();
        return Printed {
            stdout: out.stdout,
            stderr: out.stderr,
            code,
            took: started.elapsed(),
        };
    };
    let stdout = horus_ros_test_support::line_reader(child.stdout.take().expect("piped"));
    let stderr = horus_ros_test_support::read_all(child.stderr.take().expect("piped"));
    let mut printed = String::new();
    let deadline = Instant::now() + RUN_LIMIT;
    // The first `lines` lines that the case's normalisation keeps.
    let mut kept = 0;
    while kept < lines {
        match stdout.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(line) => {
                let line = format!("{line}\n");
                if !normalise(&case.norms, &line).is_empty() {
                    kept += 1;
                }
                printed.push_str(&line);
            }
            Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => break,
        }
    }
    // Ctrl-C, as a user stops them.
    if let Ok(pid) = i32::try_from(child.id()) {
        let _ = nix::sys::signal::kill(
            nix::unistd::Pid::from_raw(pid),
            nix::sys::signal::Signal::SIGINT,
        );
    }
    let status = horus_ros_test_support::wait_exit(&mut child, RUN_LIMIT)
        .unwrap_or_else(|e| panic!("{}: {e}", tool.name()));
    Printed {
        stdout: printed,
        stderr: stderr
            .recv_timeout(Duration::from_secs(5))
            .unwrap_or_default(),
        code: status.and_then(|s| s.code()),
        took: started.elapsed(),
    }
}

/// Runs one case with both tools: one after the other, each between the case's setup and
/// teardown, when it changes the graph's state; else at once.
pub fn run_case(graph: &mut LiveGraph, case: &Case) -> Outcome {
    if !case.stateful() {
        return run_pair(graph.rmw, case);
    }
    let mut one = |tool| {
        for command in &case.setup {
            graph.peer_command(command);
        }
        let printed = run_tool(graph.rmw, tool, case);
        for command in &case.teardown {
            graph.peer_command(command);
        }
        printed
    };
    let horus = one(Tool::Horus);
    let ros2 = one(Tool::Ros2);
    let verdict = compare(case, &horus, &ros2);
    Outcome {
        case: case.clone(),
        horus,
        ros2,
        verdict,
    }
}

/// How many cases run at once: their `ros2` runs start together (ros2cli's waits — its node's
/// 0.5 s spin, discovery, a message, a reply — overlap), while their `horus-ros` runs go one
/// after another beside them. One horus-ros at a time: on rustdds, a horus-ros process that
/// starts or ends while another waits for discovery can hold that wait to its bound (4.6 s,
/// with a warning), which would be the comparison's doing, not a difference.
pub const BATCH: usize = 4;

/// Which cases may share a batch: `None` for a case that runs alone, else its verb. What each
/// case of a verb prints does not depend on the others of its verb (`param set` of the same
/// value twice answers the same twice), what the next verb prints may depend on them all
/// (`param dump` after `param set`). Batches of one verb also keep the ros2cli processes that
/// start beside a horus-ros run few and alike: a participant that starts while horus-ros waits
/// for discovery and has not announced its nodes within the wait's bound makes horus-ros warn
/// (Norm::DiscoveryIncomplete); batches across verbs did so in 13 of 185 cases on
/// rmw_fastrtps_cpp, batches of one verb in none.
fn batch_key(case: &Case) -> Option<String> {
    case.parallel().then(|| case.verb())
}

/// Runs every case, in order: consecutive cases of one [`batch_key`] in batches of [`BATCH`],
/// the others one at a time; the outcomes in the cases' order.
pub fn run_all(graph: &mut LiveGraph, cases: &[Case]) -> Vec<Outcome> {
    let mut outcomes = Vec::with_capacity(cases.len());
    let mut i = 0;
    while i < cases.len() {
        let key = batch_key(&cases[i]);
        let mut end = i + 1;
        if key.is_some() {
            while end < cases.len() && end - i < BATCH && batch_key(&cases[end]) == key {
                end += 1;
            }
        }
        if end == i + 1 {
            outcomes.push(run_case(graph, &cases[i]));
        } else {
            outcomes.extend(run_batch(graph.rmw, &cases[i..end]));
        }
        i = end;
    }
    outcomes
}

/// Runs cases that change nothing: every `ros2` run at once, the `horus-ros` runs in turn.
fn run_batch(rmw: Rmw, batch: &[Case]) -> Vec<Outcome> {
    let (horus, ros2): (Vec<Printed>, Vec<Printed>) = std::thread::scope(|s| {
        let ros2: Vec<_> = batch
            .iter()
            .map(|case| s.spawn(move || run_tool(rmw, Tool::Ros2, case)))
            .collect();
        let horus = batch
            .iter()
            .map(|case| run_tool(rmw, Tool::Horus, case))
            .collect();
        let ros2 = ros2
            .into_iter()
            .map(|r| r.join().expect("a ros2 run"))
            .collect();
        (horus, ros2)
    });
    batch
        .iter()
        .zip(horus.into_iter().zip(ros2))
        .map(|(case, (horus, ros2))| Outcome {
            verdict: compare(case, &horus, &ros2),
            case: case.clone(),
            horus,
            ros2,
        })
        .collect()
}

/// Runs a case that changes nothing: both tools at once.
fn run_pair(rmw: Rmw, case: &Case) -> Outcome {
    run_batch(rmw, std::slice::from_ref(case))
        .pop()
        .expect("one outcome")
}

fn compare(case: &Case, horus: &Printed, ros2: &Printed) -> Verdict {
    let (h, r) = (horus.normalised(&case.norms), ros2.normalised(&case.norms));
    let same =
        |a: &Printed, b: &Printed| (&a.stdout, &a.stderr, a.code) == (&b.stdout, &b.stderr, b.code);
    match case.known {
        None if same(&h, &r) => Verdict::Equal,
        Some(Known::Ros2Traceback)
            if h.stdout == r.stdout
                && h.code == r.code
                && r.stderr.starts_with("Traceback (most recent call last):\n")
                && h.stderr.lines().count() == 1 =>
        {
            Verdict::Explained("ros2cli crashes (a Python traceback); horus-ros prints one line")
        }
        None if case.stream.is_some() && shut_down_twice(&r, &h) => Verdict::Explained(
            "ros2cli's own shutdown came after its SIGINT handler's (timing): it says so, status 1",
        ),
        _ => Verdict::Different(diff_printed(&r, &h)),
    }
}

/// Whether `ros2`'s run of a stream verb, stopped by SIGINT, differs from horus-ros's only by
/// rclpy's `failed to shutdown: rcl_shutdown already called on the given context` and exit
/// status 1 instead of 2: rclpy's SIGINT handler shuts the context down while ros2cli's
/// `KeyboardInterrupt` path is on its way to its own `rclpy.shutdown()`, and which comes first
/// is timing (seen on rmw_zenoh_cpp, whose shutdown takes longer).
fn shut_down_twice(ros2: &Printed, horus: &Printed) -> bool {
    const TWICE: &str = "failed to shutdown: rcl_shutdown already called on the given context";
    let rest: String = ros2
        .stderr
        .split_inclusive('\n')
        .filter(|l| !l.starts_with(TWICE))
        .collect();
    ros2.stderr != rest
        && (&ros2.stdout, &rest, ros2.code) == (&horus.stdout, &horus.stderr, Some(1))
        && horus.code == Some(2)
}

/// The differences of two outputs: stdout, stderr and exit status, each as a line diff.
fn diff_printed(ros2: &Printed, horus: &Printed) -> String {
    let mut out = String::new();
    for (name, r, h) in [
        ("stdout", &ros2.stdout, &horus.stdout),
        ("stderr", &ros2.stderr, &horus.stderr),
    ] {
        if r != h {
            let _ = writeln!(out, "  {name} (- ros2, + horus-ros):");
            out.push_str(&line_diff(r, h));
        }
    }
    if ros2.code != horus.code {
        let _ = writeln!(
            out,
            "  exit status: ros2 {:?}, horus-ros {:?}",
            ros2.code, horus.code
        );
    }
    out
}

/// A line diff (longest common subsequence), lines prefixed `-`, `+` or ` `.
fn line_diff(a: &str, b: &str) -> String {
    let a: Vec<&str> = a.lines().collect();
    let b: Vec<&str> = b.lines().collect();
    let mut lcs = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for i in (0..a.len()).rev() {
        for j in (0..b.len()).rev() {
            lcs[i][j] = if a[i] == b[j] {
                lcs[i + 1][j + 1] + 1
            } else {
                lcs[i + 1][j].max(lcs[i][j + 1])
            };
        }
    }
    let (mut i, mut j, mut out) = (0, 0, String::new());
    while i < a.len() || j < b.len() {
        if i < a.len() && j < b.len() && a[i] == b[j] {
            let _ = writeln!(out, "     {}", a[i]);
            i += 1;
            j += 1;
        } else if j < b.len() && (i == a.len() || lcs[i][j + 1] >= lcs[i + 1][j]) {
            let _ = writeln!(out, "    +{}", b[j]);
            j += 1;
        } else {
            let _ = writeln!(out, "    -{}", a[i]);
            i += 1;
        }
    }
    out
}

/// The report of a run: one row per verb (`equal`, `equal, N explained`, or `DIFFERENT`), the
/// machine-readable lines `scripts/cli-diff` collects (`cli-diff<TAB>rmw<TAB>verb<TAB>result`),
/// then every explained and every different case with its diff.
pub fn report(rmw: &str, outcomes: &[Outcome], took: Duration) -> String {
    let mut verbs: BTreeMap<String, (usize, usize, usize, Duration, Duration)> = BTreeMap::new();
    for o in outcomes {
        let row = verbs.entry(o.case.verb()).or_default();
        row.0 += 1;
        row.3 += o.horus.took;
        row.4 += o.ros2.took;
        match o.verdict {
            Verdict::Equal => {}
            Verdict::Explained(_) => row.1 += 1,
            Verdict::Different(_) => row.2 += 1,
        }
    }
    let mut out = format!(
        "horus-ros vs ros2cli 0.32.2 on {rmw}: {} cases in {:.0} s\n",
        outcomes.len(),
        took.as_secs_f64()
    );
    for (verb, (cases, explained, different, horus, ros2)) in &verbs {
        let result = match (explained, different) {
            (0, 0) => "equal".to_owned(),
            (e, 0) => format!("equal, {e} explained"),
            (_, d) => format!("DIFFERENT in {d} of {cases}"),
        };
        let _ = writeln!(
            out,
            "cli-diff\t{rmw}\t{verb}\t{result}\t({cases} cases; horus-ros {:.1} s, ros2 {:.1} s)",
            horus.as_secs_f64(),
            ros2.as_secs_f64()
        );
    }
    let mut slowest: Vec<&Outcome> = outcomes.iter().collect();
    slowest.sort_by_key(|o| std::cmp::Reverse(o.horus.took.max(o.ros2.took)));
    out.push_str("slowest cases (horus-ros, ros2):\n");
    for o in slowest.iter().take(8) {
        let _ = writeln!(
            out,
            "  {:.1} s, {:.1} s: {}",
            o.horus.took.as_secs_f64(),
            o.ros2.took.as_secs_f64(),
            o.case.command_line()
        );
    }
    let warned = outcomes
        .iter()
        .filter(|o| {
            o.horus
                .stderr
                .contains("WARNING: discovery incomplete after ")
        })
        .count();
    let _ = writeln!(
        out,
        "horus-ros's discovery wait reached its bound (a warning: Norm::DiscoveryIncomplete) in \
         {warned} of {} cases",
        outcomes.len()
    );
    let total =
        |f: fn(&Outcome) -> Duration| outcomes.iter().map(f).sum::<Duration>().as_secs_f64();
    let _ = writeln!(
        out,
        "time in all: horus-ros {:.0} s, ros2 {:.0} s",
        total(|o| o.horus.took),
        total(|o| o.ros2.took)
    );
    for o in outcomes {
        match &o.verdict {
            Verdict::Equal => {}
            Verdict::Explained(why) => {
                let _ = writeln!(out, "explained: {} — {why}", o.case.command_line());
            }
            Verdict::Different(diff) => {
                let _ = writeln!(out, "DIFFERENT: {}\n{diff}", o.case.command_line());
            }
        }
    }
    out
}
