//! Runs the `async_node` example as the program it is (a separate process) inside the test
//! network namespace: it follows the graph, calls `/add_two_ints` once this test serves it, and
//! answers `~/add_three` by awaiting `/add_two_ints` in its handler. `cargo test` builds it.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use horus_ros_services::prelude::*;

mod common;

const DOMAIN: u32 = 225;
const WAIT: Duration = Duration::from_secs(30);

struct Running {
    child: Child,
    lines: mpsc::Receiver<String>,
    seen: Vec<String>,
}

impl Running {
    fn start(name: &str) -> Self {
        let mut child = Command::new(common::example_path(name))
            .env("ROS_DOMAIN_ID", DOMAIN.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("spawn example");
        let stdout = child.stdout.take().expect("stdout");
        let (tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout)
                .lines()
                .map_while(std::io::Result::ok)
            {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Self {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Waits until a line containing each of `whats` was printed, in any order.
    fn expect_lines(&mut self, whats: &[&str]) {
        let end = Instant::now() + WAIT;
        while !whats
            .iter()
            .all(|w| self.seen.iter().any(|l| l.contains(w)))
        {
            match self
                .lines
                .recv_timeout(end.saturating_duration_since(Instant::now()))
            {
                Ok(line) => self.seen.push(line),
                Err(_) => panic!("no lines with {whats:?}; saw {:#?}", self.seen),
            }
        }
    }

    /// Waits for a line containing `what` (woken by each line; bounded).
    fn expect_line(&mut self, what: &str) -> String {
        let end = Instant::now() + WAIT;
        loop {
            match self
                .lines
                .recv_timeout(end.saturating_duration_since(Instant::now()))
            {
                Ok(line) => {
                    self.seen.push(line.clone());
                    if line.contains(what) {
                        return line;
                    }
                }
                Err(_) => panic!("no line with {what:?}; saw {:#?}", self.seen),
            }
        }
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

#[test]
fn the_async_node_serves_calls_and_follows_the_graph_in_one_runtime() {
    let mut example = Running::start("async_node");
    example.expect_line("serving /async_node/add_three");
    example.expect_line("waiting for /add_two_ints");

    // The other service appears: the example sees our node come and calls it.
    let context = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context");
    let node = context.create_node("test_adder", "/").expect("node");
    let adder = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name("/add_two_ints")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    // In either order: the call needs the server's endpoints, the node's name comes with
    // ros_discovery_info.
    example.expect_lines(&[
        "graph: node added /test_adder",
        "2 + 3 = 5 from /add_two_ints",
    ]);

    // Its service, whose handler awaits our /add_two_ints.
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/async_node/add_three")
        .build()
        .expect("client");
    assert!(client.wait_for_service(WAIT));
    for i in 0..5 {
        assert_eq!(
            client.call(
                AddTwoIntsRequest { a: i, b: 10 * i },
                10 * Duration::from_secs(1)
            ),
            Ok(AddTwoIntsResponse { sum: 11 * i + 3 })
        );
    }
    assert_eq!(adder.served_count(), 1 + 5);

    // Ctrl+C ends it cleanly.
    let status = Command::new("kill")
        .args(["-INT", &example.child.id().to_string()])
        .status()
        .expect("kill");
    assert!(status.success());
    example.expect_line("served 5 requests (0 failed); bye");
    let status = example.child.wait().expect("wait");
    assert!(status.success(), "{status}; output {:#?}", example.seen);
}
