//! The `managed_talker` example (a HORUS node wrapped in [`horus::Managed`]) run as the program
//! it is, driven through its lifecycle services by a [`LifecycleClient`] as `ros2 lifecycle set`
//! would: `configure` runs its `init` (its topic appears), it publishes only while `active`,
//! `shutdown` runs its `shutdown`; the numbering of its messages shows that its `tick` did not
//! run while inactive. Domain 151, on the backend the environment chooses. Run inside the
//! private network namespace: `scripts/isolated cargo test -p horus-ros-nodes --test managed`.

use std::process::{Child, Command, Stdio};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use horus::lifecycle::{LifecycleClient, Transition};
use horus::msgs::std_msgs::msg::String as StringMsg;
use horus::ros::{Context, Qos};
use horus_ros_graph::Graph;

const LIMIT: Duration = Duration::from_secs(30);
const CALL: Duration = Duration::from_secs(10);
/// How long the topic must stay silent to count as silent: 6 ticks at the example's 20 Hz.
const QUIET: Duration = Duration::from_millis(300);

struct Example {
    child: Child,
    lines: Receiver<String>,
    seen: Vec<String>,
}

impl Example {
    fn wait_line(&mut self, what: &str) {
        let deadline = Instant::now() + LIMIT;
        while !self.seen.iter().any(|l| l.contains(what)) {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => self.seen.push(line),
                Err(_) => panic!("no line with {what:?}; printed:\n{}", self.seen.join("\n")),
            }
        }
    }
}

impl Drop for Example {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The numbers of the messages that arrive until the topic has been silent for [`QUIET`].
fn until_quiet(heard: &mut horus_ros_rmw::Subscription<StringMsg>) -> Vec<u64> {
    let mut got = Vec::new();
    loop {
        while let Some(m) = heard.try_take().expect("take") {
            got.push(number(&m.data));
        }
        if !heard.wait(QUIET) {
            return got;
        }
    }
}

fn number(data: &str) -> u64 {
    data.strip_prefix("Hello World: ")
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("unexpected message {data:?}"))
}

/// The next `n` message numbers, each within [`LIMIT`].
fn next(heard: &mut horus_ros_rmw::Subscription<StringMsg>, n: usize) -> Vec<u64> {
    let mut got = Vec::new();
    while got.len() < n {
        match heard.try_take().expect("take") {
            Some(m) => got.push(number(&m.data)),
            None => assert!(heard.wait(LIMIT), "messages so far: {got:?}"),
        }
    }
    got
}

#[test]
fn a_managed_horus_node_follows_its_lifecycle() {
    let domain = 151;
    let mut child = Command::new(horus_ros_test_support::built_example("managed_talker"))
        .env("ROS_DOMAIN_ID", domain.to_string())
        .env("TALKER_RATE_HZ", "20")
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start the example");
    let lines = horus_ros_test_support::line_reader(child.stdout.take().expect("stdout"));
    let mut example = Example {
        child,
        lines,
        seen: Vec::new(),
    };
    example.wait_line("ready");

    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node("driver", "/").expect("node");
    let mut heard = node
        .create_subscription::<StringMsg>("/chatter", &Qos::default_profile())
        .expect("subscription");
    let mut client = LifecycleClient::builder()
        .node(&node)
        .target("/managed_talker")
        .build()
        .expect("client");
    assert!(client.wait_for_services(LIMIT).expect("clients"));
    let state = client.get_state(CALL).expect("get_state");
    assert_eq!((state.id, state.label.as_str()), (1, "unconfigured"));

    // configure: the node's init runs.
    assert!(client.change_state("configure", CALL).expect("configure"));
    example.wait_line("on_configure() is called.");
    let state = client.get_state(CALL).expect("get_state");
    assert_eq!((state.id, state.label.as_str()), (2, "inactive"));

    // activate: it ticks (its topic's writer comes with its first message).
    assert!(client
        .change_state(Transition::Activate, CALL)
        .expect("activate"));
    let graph = Graph::of(&context).expect("graph");
    let mut writer = None;
    assert!(graph.wait_until(LIMIT, |c| {
        writer = c
            .publishers_info_by_topic("/chatter", false)
            .first()
            .map(|i| i.endpoint_gid);
        writer.is_some()
    }));
    assert!(graph.wait_for_match(heard.gid(), writer.expect("found"), LIMIT));
    let first = next(&mut heard, 3);
    assert_eq!(first, [first[0], first[0] + 1, first[0] + 2]);

    // deactivate: silent; its count did not move while inactive.
    assert!(client.change_state("deactivate", CALL).expect("deactivate"));
    let mut before: Vec<u64> = vec![first[2]];
    before.extend(until_quiet(&mut heard));
    let last = *before.iter().max().expect("one at least");
    assert!(before.windows(2).all(|w| w[1] == w[0] + 1), "{before:?}");
    let state = client.get_state(CALL).expect("get_state");
    assert_eq!((state.id, state.label.as_str()), (2, "inactive"));
    assert!(client.change_state("activate", CALL).expect("activate"));
    assert_eq!(next(&mut heard, 2), [last + 1, last + 2]);

    // shutdown from active: the node's shutdown runs; finalized.
    assert!(client.change_state("shutdown", CALL).expect("shutdown"));
    example.wait_line("on_cleanup() is called.");
    let state = client.get_state(CALL).expect("get_state");
    assert_eq!((state.id, state.label.as_str()), (4, "finalized"));

    // Ctrl+C ends it cleanly.
    let pid = nix::unistd::Pid::from_raw(i32::try_from(example.child.id()).expect("pid"));
    nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGINT).expect("SIGINT");
    let status = horus_ros_test_support::wait_exit(&mut example.child, LIMIT).expect("wait");
    assert_eq!(status.and_then(|s| s.code()), Some(0));
}

/// What the in-process node's calls were, in order.
type Calls = std::sync::Arc<std::sync::Mutex<Vec<&'static str>>>;

/// A node whose `init` fails, then panics, then succeeds, and whose `shutdown` fails once.
struct Moody {
    inits: u32,
    shutdowns: u32,
    calls: Calls,
    ticked: std::sync::mpsc::Sender<()>,
}

impl horus::Node for Moody {
    fn name(&self) -> &str {
        "moody"
    }
    fn init(&mut self) -> horus::Result<()> {
        self.inits += 1;
        self.calls.lock().expect("lock").push("init");
        match self.inits {
            1 => Err(horus::Error::config("no device")),
            2 => panic!("init panicked on purpose"),
            _ => Ok(()),
        }
    }
    fn tick(&mut self) {
        let mut calls = self.calls.lock().expect("lock");
        if calls.last() != Some(&"tick") {
            calls.push("tick");
            let _ = self.ticked.send(());
        }
    }
    fn shutdown(&mut self) -> horus::Result<()> {
        self.shutdowns += 1;
        self.calls.lock().expect("lock").push("shutdown");
        if self.shutdowns == 1 {
            Err(horus::Error::msg("busy"))
        } else {
            Ok(())
        }
    }
}

/// In one process: `init`'s error is FAILURE (unconfigured), its panic ERROR (error processing,
/// unconfigured), a failing `shutdown` on cleanup FAILURE (inactive, still configured); `tick`
/// runs only while active; the scheduler's exit runs `shutdown` of a node still configured.
#[test]
fn transitions_run_init_and_shutdown_on_the_scheduler() {
    use horus::prelude::Units;
    let domain = 152;
    let calls = Calls::default();
    let (ticked, ticks) = std::sync::mpsc::channel();
    let mut sched = horus::Scheduler::new()
        .context(
            Context::builder()
                .domain_id(domain)
                .arguments(horus::ros::Arguments::default())
                .build()
                .expect("context"),
        )
        .tick_rate(50_u64.hz())
        .print_report(false);
    sched
        .add(horus::Managed::new(Moody {
            inits: 0,
            shutdowns: 0,
            calls: calls.clone(),
            ticked,
        }))
        .build()
        .expect("node");
    let stop = sched.stop_handle();
    let thread = std::thread::spawn(move || sched.run().map_err(|e| e.to_string()));

    let context = Context::builder()
        .domain_id(domain)
        .build()
        .expect("context");
    let node = context.create_node("driver", "/").expect("node");
    let mut client = LifecycleClient::builder()
        .node(&node)
        .target("/moody")
        .build()
        .expect("client");
    assert!(client.wait_for_services(LIMIT).expect("clients"));
    let state = |c: &mut LifecycleClient| c.get_state(CALL).expect("get_state").id;

    assert!(!client.change_state("configure", CALL).expect("call"));
    assert_eq!(state(&mut client), 1);
    assert!(!client.change_state("configure", CALL).expect("call"));
    assert_eq!(state(&mut client), 1);
    let third = client.change_state("configure", CALL).expect("call");
    assert!(
        third,
        "third configure: state {}, calls {:?}",
        state(&mut client),
        calls.lock().expect("lock")
    );
    assert_eq!(state(&mut client), 2);
    // Not ticked while inactive: the cleanup below is handled by a later tick of the
    // scheduler, and no tick of the node came between.
    assert!(!client.change_state("cleanup", CALL).expect("call"));
    assert_eq!(state(&mut client), 2);
    assert_eq!(
        *calls.lock().expect("lock"),
        ["init", "init", "init", "shutdown"]
    );
    // The failed cleanup left it inactive and configured; the next cleanup runs shutdown again.
    assert!(client.change_state("cleanup", CALL).expect("call"));
    assert!(client.change_state("configure", CALL).expect("call"));
    assert!(ticks.try_recv().is_err(), "ticked before activation");
    assert!(client.change_state("activate", CALL).expect("call"));
    assert!(ticks.recv_timeout(LIMIT).is_ok(), "no tick while active");
    assert!(client.change_state("deactivate", CALL).expect("call"));
    let seen = calls.lock().expect("lock").clone();
    assert_eq!(
        seen[..6],
        ["init", "init", "init", "shutdown", "shutdown", "init"]
    );
    assert_eq!(seen[6..], ["tick"], "ticked while active only");
    stop.stop();
    assert_eq!(thread.join().expect("scheduler thread"), Ok(()));
    assert_eq!(calls.lock().expect("lock").last(), Some(&"shutdown"));
}
