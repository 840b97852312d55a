//! Runs a program under valgrind's leak check: no definite or indirect leak and no memory error
//! may be reported. Valgrind is required (scripts/setup installs it): without it the check fails
//! rather than skips.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::wait_with_output;

/// Runs `program` with `envs` under `valgrind --leak-check=full`, at most `limit`, and asserts
/// that valgrind found nothing and that the program printed `finished` (it did its work). Prints
/// valgrind's summary lines.
pub fn assert_no_leaks(program: &Path, envs: &[(&str, &str)], finished: &str, limit: Duration) {
    let version = Command::new("valgrind").arg("--version").output();
    assert!(
        matches!(&version, Ok(o) if o.status.success()),
        "valgrind is required for this test but could not be run ({version:?}); install it \
         (scripts/setup does)"
    );
    let mut child = Command::new("valgrind")
        .args([
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "--error-exitcode=9",
            "--num-callers=30",
        ])
        .arg(program)
        .envs(envs.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start valgrind");
    let out = wait_with_output(&mut child, limit).expect("wait for valgrind");
    let (stdout, stderr) = (&out.stdout, &out.stderr);
    let Some(status) = out.status else {
        panic!(
            "{} under valgrind did not finish within {limit:?}\n{stdout}\n{stderr}",
            program.display()
        );
    };
    assert!(
        status.success(),
        "valgrind reported errors or leaks (exit {status}; 9 = valgrind error)\n--- stdout\n\
         {stdout}\n--- stderr\n{stderr}"
    );
    assert!(
        stdout.contains(finished),
        "the program did not finish its work\n{stdout}\n{stderr}"
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
