//! A child process whose stdout lines are read as they come, on a channel: the CLI's streaming
//! verbs (`topic echo`, `hz`, `service echo`, `graph --watch`) and the Python peers. Killed when
//! dropped, if still running.

use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// A running process and its stdout lines.
pub struct Streaming {
    child: Child,
    lines: mpsc::Receiver<String>,
}

impl Streaming {
    /// Starts `command` with its stdout piped (its stdin and stderr as the command sets them).
    pub fn spawn(command: &mut Command) -> std::io::Result<Self> {
        Ok(Self::from_child(command.stdout(Stdio::piped()).spawn()?))
    }

    /// Reads the stdout of `child`, started with its stdout piped.
    pub fn from_child(mut child: Child) -> Self {
        let stdout = child.stdout.take().expect("piped stdout");
        Self {
            child,
            lines: horus_ros_test_support::line_reader(stdout),
        }
    }

    /// The process.
    pub fn child(&mut self) -> &mut Child {
        &mut self.child
    }

    /// The next line, if one comes within `wait` (`None` also at the end of output).
    pub fn next_line(&self, wait: Duration) -> Option<String> {
        self.lines.recv_timeout(wait).ok()
    }

    /// The next line, within `wait`.
    pub fn line(&self, wait: Duration) -> String {
        self.next_line(wait)
            .unwrap_or_else(|| panic!("no line within {wait:?}"))
    }

    /// The lines up to and including the first `last` accepts, within `wait` in all.
    pub fn until(&self, wait: Duration, last: impl Fn(&str) -> bool) -> String {
        let deadline = Instant::now() + wait;
        let mut out = String::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    out.push_str(&line);
                    out.push('\n');
                    if last(&line) {
                        return out;
                    }
                }
                Err(e) => panic!("the awaited line did not come ({e}):\n{out}"),
            }
        }
    }

    /// Every line up to the end of output, within `wait` in all.
    pub fn rest(&self, wait: Duration) -> String {
        let deadline = Instant::now() + wait;
        let mut out = String::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    out.push_str(&line);
                    out.push('\n');
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => return out,
                Err(mpsc::RecvTimeoutError::Timeout) => panic!("the output did not end:\n{out}"),
            }
        }
    }

    /// Every line up to the end of output, within `wait`, and the exit code.
    pub fn finish(mut self, wait: Duration) -> (String, Option<i32>) {
        let out = self.rest(wait);
        let code = self.child.wait().ok().and_then(|s| s.code());
        (out, code)
    }
}

impl Drop for Streaming {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
        }
        let _ = self.child.wait();
    }
}
