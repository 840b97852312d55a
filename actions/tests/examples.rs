//! Runs the tutorial examples together as the programs they are (separate processes, inside the
//! test network namespace): the client's goal is accepted, its feedback and result printed, and
//! the server logs as the tutorial does.

use std::process::{Command, Output, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// The longest an example may run.
const LIMIT: Duration = Duration::from_secs(90);

fn run(name: &str, args: &[&str], domain: u32) -> (Output, String) {
    run_on(name, args, domain, None)
}

/// [`run`] on `backend` (`HORUS_ROS_BACKEND`), or the test's own when `None`.
fn run_on(name: &str, args: &[&str], domain: u32, backend: Option<&str>) -> (Output, String) {
    let mut command = Command::new(horus_ros_test_support::built_example(name));
    if let Some(backend) = backend {
        command.env("HORUS_ROS_BACKEND", backend);
    }
    let child = command
        .args(args)
        .env("ROS_DOMAIN_ID", domain.to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("spawn {name}: {e}"));
    let (tx, rx) = mpsc::channel();
    let pid = child.id();
    std::thread::spawn(move || {
        let _ = tx.send(child.wait_with_output());
    });
    let output = match rx.recv_timeout(LIMIT) {
        Ok(output) => output.unwrap_or_else(|e| panic!("{name}: {e}")),
        Err(_) => {
            let _ = Command::new("kill").arg(pid.to_string()).status();
            panic!("{name} still running after {LIMIT:?}");
        }
    };
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        output.status.success(),
        "{name} exited {}: {text}",
        output.status
    );
    (output, text)
}

#[test]
fn the_tutorial_client_gets_its_result_from_the_tutorial_server() {
    let server = std::thread::spawn(|| {
        run(
            "fibonacci_action_server",
            &["--period-ms", "50", "--count", "1"],
            131,
        )
    });
    let (_, text) = run("fibonacci_action_client", &[], 131);
    for line in [
        "[fibonacci_action_client]: Goal accepted :)",
        "[fibonacci_action_client]: Received feedback: [0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55]",
        "[fibonacci_action_client]: Result: [0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55]",
    ] {
        assert!(text.contains(line), "client did not print {line:?}: {text}");
    }
    let (_, text) = server.join().expect("server thread");
    for line in [
        "[fibonacci_action_server]: Executing goal...",
        "[fibonacci_action_server]: Feedback: [0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55]",
        "[fibonacci_action_server]: Returning result: [0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55]",
    ] {
        assert!(text.contains(line), "server did not print {line:?}: {text}");
    }
}

/// The server and the client on different backends, each way: the server answers the client
/// in the client's convention (rmw_cyclonedds' request header for a Cyclone DDS client,
/// `related_sample_identity` for a rustdds one), and the feedback and status topics cross.
#[test]
fn the_tutorial_programs_talk_across_backends() {
    for (domain, server_backend, client_backend) in
        [(132, "rustdds", "cyclone"), (133, "cyclone", "rustdds")]
    {
        let server = std::thread::spawn(move || {
            run_on(
                "fibonacci_action_server",
                &["--period-ms", "50", "--count", "1"],
                domain,
                Some(server_backend),
            )
        });
        let (_, text) = run_on("fibonacci_action_client", &[], domain, Some(client_backend));
        let result = "[fibonacci_action_client]: Result: [0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55]";
        assert!(
            text.contains(result),
            "{client_backend} client of a {server_backend} server: {text}"
        );
        let (_, text) = server.join().expect("server thread");
        assert!(
            text.contains("[fibonacci_action_server]: Returning result"),
            "{server_backend} server: {text}"
        );
    }
}
