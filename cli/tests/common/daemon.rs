//! The daemons a test starts, explicitly (`daemon start`) or by a query that starts one: each
//! becomes a child of the test process (made the reaper of orphans), is found by its command
//! line and guarded: stopped, or killed by its pid and reaped when the guard drops, whatever
//! the test's outcome, so that no daemon outlives its test.

use std::sync::mpsc::{self, Receiver};
use std::sync::Once;
use std::time::Duration;

use nix::sys::signal::{kill, Signal};
use nix::sys::wait::{waitpid, WaitStatus};
use nix::unistd::Pid;

/// How long a daemon may take to exit once it should.
pub const EXIT_LIMIT: Duration = Duration::from_secs(20);

/// Makes this process the reaper of its descendants' orphans, so that a daemon (left by
/// `daemon start` when it exits) becomes its child: it can then be waited for and reaped, and
/// its pid cannot be reused while the guard holds it.
pub fn adopt_orphans() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        nix::sys::prctl::set_child_subreaper(true).expect("PR_SET_CHILD_SUBREAPER");
    });
}

/// A daemon process of this test: killed (SIGKILL, by pid) and reaped when dropped, unless it
/// has exited and been reaped already.
pub struct DaemonGuard {
    pub pid: u32,
    exit: Receiver<WaitStatus>,
    reaped: Option<WaitStatus>,
}

impl DaemonGuard {
    /// The daemon of `domain` among this process's children (there must be exactly one).
    pub fn adopt(domain: u32) -> Self {
        Self::adopt_except(domain, &[])
    }

    /// The daemon of `domain` among this process's children, other than those of `known`
    /// (there must be exactly one).
    pub fn adopt_except(domain: u32, known: &[u32]) -> Self {
        let pids: Vec<u32> = daemon_children(domain)
            .into_iter()
            .filter(|pid| !known.contains(pid))
            .collect();
        assert_eq!(
            pids.len(),
            1,
            "new daemons of domain {domain} among our children: {pids:?}"
        );
        let pid = pids[0];
        let (tx, exit) = mpsc::channel();
        std::thread::spawn(move || loop {
            match waitpid(Pid::from_raw(pid as i32), None) {
                Ok(status @ (WaitStatus::Exited(..) | WaitStatus::Signaled(..))) => {
                    let _ = tx.send(status);
                    return;
                }
                Ok(_) | Err(nix::errno::Errno::EINTR) => {}
                Err(_) => return,
            }
        });
        Self {
            pid,
            exit,
            reaped: None,
        }
    }

    /// Waits at most `limit` for the daemon to exit; its exit status if it did.
    pub fn wait_exit(&mut self, limit: Duration) -> Option<WaitStatus> {
        if self.reaped.is_none() {
            self.reaped = self.exit.recv_timeout(limit).ok();
        }
        self.reaped
    }

    /// Sends `signal` to the daemon (it must not have been reaped).
    pub fn signal(&self, signal: Signal) {
        assert!(self.reaped.is_none(), "the daemon was reaped already");
        kill(Pid::from_raw(self.pid as i32), signal).expect("signal the daemon");
    }
}

impl Drop for DaemonGuard {
    fn drop(&mut self) {
        if self.reaped.is_none() {
            let pid = Pid::from_raw(self.pid as i32);
            // Not reaped, so the pid is still this daemon (a zombie at worst).
            let _ = kill(pid, Signal::SIGKILL);
            let _ = kill(pid, Signal::SIGCONT);
            let _ = self.exit.recv_timeout(EXIT_LIMIT);
        }
    }
}

/// The pids of this process's children that are `horus-ros … daemon _run` of `domain`.
pub fn daemon_children(domain: u32) -> Vec<u32> {
    let me = std::process::id();
    let domain = domain.to_string();
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").expect("/proc").flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
            continue;
        };
        // `pid (comm) state ppid …`: the command may hold spaces and parentheses.
        let Some((_, rest)) = stat.rsplit_once(')') else {
            continue;
        };
        let ppid = rest.split_whitespace().nth(1).and_then(|p| p.parse().ok());
        if ppid != Some(me) {
            continue;
        }
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<String> = cmdline
            .split(|b| *b == 0)
            .map(|a| String::from_utf8_lossy(a).into_owned())
            .collect();
        let is_run = args.windows(2).any(|w| w[0] == "daemon" && w[1] == "_run");
        let in_domain = args
            .windows(2)
            .any(|w| w[0] == "--domain-id" && w[1] == domain);
        if is_run && in_domain {
            found.push(pid);
        }
    }
    found
}
