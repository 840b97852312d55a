//! Runs `examples/cyclone_leakcheck.rs` (the Cyclone DDS backend: context, node, typed and raw
//! endpoints, discovery feed, samples, teardown) under valgrind: no definite or indirect leak
//! and no memory error may be reported. Valgrind is required (scripts/setup installs it):
//! without it this test fails rather than skips. Needs the feature `cyclone`. Domain 149; run
//! inside `scripts/isolated`.
use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Cyclone DDS on loopback, with multicast (the private namespace has no other interface).
const LOOPBACK: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>";

/// target/<profile>/examples/cyclone_leakcheck, next to this test's own binary in target/<profile>/deps
/// (`cargo test` builds the examples along with the tests).
fn example() -> PathBuf {
    let exe = std::env::current_exe().expect("current exe");
    let profile_dir = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>");
    let path = profile_dir.join("examples").join("cyclone_leakcheck");
    assert!(
        path.exists(),
        "{} not built: run `cargo test -p horus-ros-rmw --features cyclone` (which builds the examples) first",
        path.display()
    );
    path
}

#[test]
fn no_leaks_under_valgrind() {
    let version = Command::new("valgrind").arg("--version").output();
    assert!(
        matches!(&version, Ok(o) if o.status.success()),
        "valgrind is required for this test but could not be run ({version:?}); install it (scripts/setup does)"
    );
    let mut child = Command::new("valgrind")
        .args([
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "--error-exitcode=9",
            "--num-callers=30",
        ])
        .arg(example())
        .env("CYCLONEDDS_URI", LOOPBACK)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start valgrind");
    // Drain both pipes while it runs (a long leak report must not block it on a full pipe).
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = pipe.read_to_string(&mut s);
            s
        })
    };
    let stdout = drain(Box::new(child.stdout.take().expect("stdout")));
    let stderr = drain(Box::new(child.stderr.take().expect("stderr")));
    // Bounded: valgrind slows Cyclone down a lot, but not this much.
    let end = Instant::now() + Duration::from_secs(300);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if Instant::now() > end {
            let _ = child.kill();
            let _ = child.wait();
            panic!("leakcheck under valgrind did not finish within 300 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let stdout = stdout.join().expect("stdout reader");
    let stderr = stderr.join().expect("stderr reader");
    assert!(
        status.success(),
        "valgrind reported errors or leaks (exit {status}; 9 = valgrind error)\n--- stdout\n{stdout}\n--- stderr\n{stderr}"
    );
    assert!(
        stdout.contains("cyclone_leakcheck: ok"),
        "example did not finish its work\n{stdout}\n{stderr}"
    );
    assert!(stderr.contains("ERROR SUMMARY: 0 errors"), "{stderr}");
    eprintln!(
        "{}",
        stderr
            .lines()
            .filter(|l| l.contains("lost") || l.contains("SUMMARY"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}
