//! Starting the daemon process: for `horus-ros daemon start`, and for the first query that may
//! use a daemon when none runs (ros2cli `node/strategy.py`: `NodeStrategy` calls `spawn_daemon`
//! when no daemon answers, unless `--no-daemon`).

use std::io::{self, BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use super::{server, DaemonKey, START_STOP_TIMEOUT};

/// How spawning the daemon went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spawned {
    /// It serves, with this process id.
    Ready(u32),
    /// Another daemon held the socket (started meanwhile by another command).
    AlreadyRunning,
}

/// Why the daemon could not be started.
#[derive(Debug, thiserror::Error)]
pub enum SpawnError {
    /// This program's own path is unknown.
    #[error("could not find the horus-ros binary: {0}")]
    Binary(io::Error),
    /// The process could not be started.
    #[error("could not start the daemon: {0}")]
    Start(io::Error),
    /// Its first line could not be read.
    #[error("could not read the daemon's output: {0}")]
    Output(io::Error),
    /// It did not say it was ready within [`START_STOP_TIMEOUT`] (it was killed).
    #[error("Timed out waiting for daemon to become ready")]
    TimedOut,
    /// It said why it could not start.
    #[error("The daemon could not start: {0}")]
    Failed(String),
    /// It exited without saying why.
    #[error("Daemon process died{}", .0.map(|c| format!(" with returncode {c}")).unwrap_or_default())]
    Died(Option<i32>),
}

/// Starts `horus-ros daemon _run` for the graph of `key`, detached (it makes itself a session
/// leader; stdin, and stderr unless `debug`, on `/dev/null`), and waits for its first line, at
/// most [`START_STOP_TIMEOUT`].
pub fn spawn(key: &DaemonKey, idle_timeout: Duration, debug: bool) -> Result<Spawned, SpawnError> {
    let exe = std::env::current_exe().map_err(SpawnError::Binary)?;
    spawn_program(&exe, key, idle_timeout, debug)
}

/// [`spawn`] with `program` standing for this binary.
fn spawn_program(
    program: &Path,
    key: &DaemonKey,
    idle_timeout: Duration,
    debug: bool,
) -> Result<Spawned, SpawnError> {
    let mut command = Command::new(program);
    command
        .arg("--domain-id")
        .arg(key.domain_id.to_string())
        .arg("--backend")
        .arg(&key.backend)
        .args(["daemon", "_run", "--idle-timeout"])
        .arg(idle_timeout.as_secs().to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped());
    if debug {
        command.stderr(Stdio::inherit());
        if std::env::var_os("RUST_LOG").is_none() {
            command.env("RUST_LOG", "info");
        }
    } else {
        command.stderr(Stdio::null());
    }
    let mut child = command.spawn().map_err(SpawnError::Start)?;
    let Some(stdout) = child.stdout.take() else {
        let _ = child.kill();
        let _ = child.wait();
        return Err(SpawnError::Output(io::Error::other(
            "no pipe from the daemon",
        )));
    };
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let read = BufReader::new(stdout).read_line(&mut line).map(|_| line);
        let _ = tx.send(read);
    });
    let line = match rx.recv_timeout(START_STOP_TIMEOUT) {
        Ok(Ok(line)) => line,
        Ok(Err(e)) => {
            let _ = child.kill();
            let _ = child.wait();
            return Err(SpawnError::Output(e));
        }
        Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => {
            let _ = child.kill();
            let _ = child.wait();
            return Err(SpawnError::TimedOut);
        }
    };
    let line = line.trim_end();
    if line == server::READY {
        // Left running: it is reparented when this process exits.
        return Ok(Spawned::Ready(child.id()));
    }
    let status = child.wait();
    if line == server::ALREADY_RUNNING {
        return Ok(Spawned::AlreadyRunning);
    }
    if let Some(reason) = line.strip_prefix(server::FAILED) {
        return Err(SpawnError::Failed(reason.to_owned()));
    }
    Err(SpawnError::Died(status.ok().and_then(|s| s.code())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> DaemonKey {
        DaemonKey {
            domain_id: 7,
            backend: "rustdds".to_owned(),
            discovery_range: "SUBNET".to_owned(),
            static_peers: Vec::new(),
            backend_environment: Default::default(),
        }
    }

    fn spawn_with(program: &str) -> Result<Spawned, SpawnError> {
        spawn_program(Path::new(program), &key(), Duration::from_secs(1), false)
    }

    #[test]
    fn a_daemon_that_cannot_start_is_an_error_naming_why() {
        // Exits at once, saying nothing.
        let e = spawn_with("false").expect_err("false is no daemon");
        assert!(matches!(e, SpawnError::Died(Some(1))), "{e:?}");
        assert_eq!(e.to_string(), "Daemon process died with returncode 1");
        // Does not exist.
        let e = spawn_with("/nonexistent/horus-ros").expect_err("no such program");
        assert!(matches!(e, SpawnError::Start(_)), "{e:?}");
        assert!(
            e.to_string().starts_with("could not start the daemon: "),
            "{e}"
        );
    }
}
