//! Runs the crate's examples as the programs they are (separate processes, inside the test
//! network namespace) and checks what they print and how they exit. `async_node` has a test of
//! its own (`async_example.rs`).

use std::process::{Command, Output, Stdio};
use std::sync::mpsc;
use std::time::Duration;

mod common;

/// The longest an example may run.
const LIMIT: Duration = Duration::from_secs(60);

/// Runs example `name` with `args` on `domain` to its end (killed after [`LIMIT`]); its
/// output, stdout and stderr together.
fn run(name: &str, args: &[&str], domain: u32) -> (Output, String) {
    let child = Command::new(common::example_path(name))
        .args(args)
        .env("ROS_DOMAIN_ID", domain.to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("spawn {name}: {e}"));
    let pid = child.id();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(child.wait_with_output());
    });
    let output = match rx.recv_timeout(LIMIT) {
        Ok(output) => output.unwrap_or_else(|e| panic!("{name}: {e}")),
        Err(_) => {
            // Ends the waiting thread too.
            let _ = Command::new("kill").arg(pid.to_string()).status();
            panic!("{name} still running after {LIMIT:?}");
        }
    };
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    (output, text)
}

fn assert_ran(name: &str, output: &Output, text: &str, lines: &[&str]) {
    assert!(
        output.status.success(),
        "{name} exited {}: {text}",
        output.status
    );
    for line in lines {
        assert!(text.contains(line), "{name} did not print {line:?}: {text}");
    }
}

#[test]
fn the_add_two_ints_client_gets_its_sum_from_the_add_two_ints_server() {
    let server = std::thread::spawn(|| run("add_two_ints_server", &["--count", "1"], 226));
    let (output, text) = run("add_two_ints_client", &["40", "2"], 226);
    assert_ran(
        "add_two_ints_client",
        &output,
        &text,
        &["Result of add_two_ints: 42"],
    );
    let (output, text) = server.join().expect("server thread");
    assert_ran("add_two_ints_server", &output, &text, &["a: 40 b: 2"]);
}

#[test]
fn async_client_loop_never_blocks_its_ticks() {
    let (output, text) = run("async_client_loop", &[], 229);
    assert_ran(
        "async_client_loop",
        &output,
        &text,
        &[
            "expired",
            "none blocked by a call",
            "awaited: 10 + 20 = 30, then 30 + 12 = 42",
            "wait(): 5 + 8 = 13",
        ],
    );
}
