//! What the tests of several horus-ros crates share:
//! - waiting for a child process, bounded in time and woken by its exit (poll(2) on a pidfd),
//!   never by polling with sleeps, with its pipes read while it runs (a chatty child cannot
//!   block on a full pipe);
//! - finding the examples `cargo test` built;
//! - reading a child's output line by line as it is printed ([`line_reader`]);
//! - running a program under valgrind's leak check ([`valgrind`]);
//! - what the benchmarks share ([`bench`]).

pub mod bench;
pub mod fuzz;
pub mod jazzy;
pub mod valgrind;

use std::io::{self, Read};
use std::process::{Child, ExitStatus};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

use rustix::event::{poll, PollFd, PollFlags, Timespec};
use rustix::process::{pidfd_open, Pid, PidfdFlags};

/// A child's output, line by line as it is printed, read by a thread of its own (which ends at
/// the end of the output or when the receiver is dropped).
pub fn line_reader(output: impl Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in io::BufRead::lines(io::BufReader::new(output)) {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// Where `cargo test` put the example `name` of the crate under test: `target/<profile>/examples`,
/// beside the test binary's `target/<profile>/deps` (`cargo test` builds the examples with the
/// tests). Panics, saying how to build it, when it is not there.
pub fn built_example(name: &str) -> std::path::PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    let profile_dir = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>");
    let path = profile_dir.join("examples").join(name);
    assert!(
        path.exists(),
        "{} not built: `cargo test` of its crate builds the examples first",
        path.display()
    );
    path
}

/// Waits for `child` to exit, at most `limit`; past that it is killed (and reaped) and the
/// answer is `None`.
pub fn wait_exit(child: &mut Child, limit: Duration) -> io::Result<Option<ExitStatus>> {
    if let Some(status) = child.try_wait()? {
        return Ok(Some(status));
    }
    let raw = i32::try_from(child.id()).map_err(io::Error::other)?;
    let pid = Pid::from_raw(raw).ok_or_else(|| io::Error::other("pid 0"))?;
    // Not reaped yet, so the pid is still this child's (a zombie at worst).
    let pidfd = pidfd_open(pid, PidfdFlags::empty())?;
    let deadline = Instant::now() + limit;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        let timeout = Timespec::try_from(left).map_err(io::Error::other)?;
        let mut fds = [PollFd::new(&pidfd, PollFlags::IN)];
        match poll(&mut fds, Some(&timeout)) {
            // Readable: the child has exited.
            Ok(n) if n > 0 => return child.wait().map(Some),
            Ok(_) => {
                child.kill()?;
                child.wait()?;
                return Ok(None);
            }
            Err(rustix::io::Errno::INTR) => continue,
            Err(e) => return Err(e.into()),
        }
    }
}

/// Reads all of `pipe` on a thread of its own; the text comes when the pipe closes (the child
/// exited, or closed it).
pub fn read_all(mut pipe: impl Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = pipe.read_to_end(&mut bytes);
        let _ = tx.send(String::from_utf8_lossy(&bytes).into_owned());
    });
    rx
}

/// How a child ended, and what it printed.
#[derive(Debug)]
pub struct Output {
    /// Its exit status; `None` if it was killed at the limit.
    pub status: Option<ExitStatus>,
    /// Its standard output (empty if not piped).
    pub stdout: String,
    /// Its standard error (empty if not piped).
    pub stderr: String,
}

impl Output {
    /// The exit code; `None` if it was killed at the limit or died of a signal.
    pub fn code(&self) -> Option<i32> {
        self.status.and_then(|s| s.code())
    }
}

/// Waits for `child` as [`wait_exit`] does, reading its piped standard output and error while
/// it runs.
pub fn wait_with_output(child: &mut Child, limit: Duration) -> io::Result<Output> {
    let stdout = child.stdout.take().map(read_all);
    let stderr = child.stderr.take().map(read_all);
    let status = wait_exit(child, limit)?;
    // The pipes closed with the child (a grandchild holding one gets a short grace).
    let text = |rx: Option<Receiver<String>>| {
        rx.and_then(|rx| rx.recv_timeout(Duration::from_secs(5)).ok())
            .unwrap_or_default()
    };
    Ok(Output {
        status,
        stdout: text(stdout),
        stderr: text(stderr),
    })
}

#[cfg(test)]
mod tests {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};

    use super::{wait_exit, wait_with_output};

    #[test]
    fn an_exit_is_seen_at_once_with_its_output() {
        let mut child = Command::new("sh")
            .args(["-c", "echo out; echo err >&2; exit 3"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("sh");
        let out = wait_with_output(&mut child, Duration::from_secs(30)).expect("wait");
        assert_eq!(out.code(), Some(3));
        assert_eq!(
            (out.stdout.as_str(), out.stderr.as_str()),
            ("out\n", "err\n")
        );
    }

    #[test]
    fn a_child_past_its_limit_is_killed() {
        let mut child = Command::new("sleep").arg("600").spawn().expect("sleep");
        let start = Instant::now();
        let status = wait_exit(&mut child, Duration::from_millis(200)).expect("wait");
        assert_eq!(status, None);
        assert!(start.elapsed() < Duration::from_secs(60));
        assert!(child.try_wait().expect("reaped").is_some());
    }

    #[test]
    fn more_output_than_a_pipe_holds_does_not_block_the_child() {
        // 1 MiB: far more than a pipe's 64 KiB buffer.
        let mut child = Command::new("head")
            .args(["-c", "1048576", "/dev/zero"])
            .stdout(Stdio::piped())
            .spawn()
            .expect("head");
        let out = wait_with_output(&mut child, Duration::from_secs(60)).expect("wait");
        assert_eq!(out.code(), Some(0));
        assert_eq!(out.stdout.len(), 1 << 20);
    }
}
