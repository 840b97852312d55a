//! The verbs' side of the daemon: reaching it, asking it, and the graph it answers with.
//!
//! Nothing here can hang a command: the connection is made without blocking (a daemon whose
//! backlog is full is "busy"), every answer has a deadline, and the daemon must belong to this
//! user (the socket's peer credentials).

use std::io::{self, Read};
use std::os::fd::AsRawFd;
use std::os::unix::net::UnixStream;
use std::time::{Duration, Instant};

use horus_ros_graph::GraphCache;
use nix::errno::Errno;
use nix::sys::socket::{self, sockopt, AddressFamily, SockFlag, SockType, UnixAddr};

use super::protocol::{
    self, FrameError, Request, RequestFrame, Response, ResponseFrame, Status, MAX_RESPONSE,
};
use super::spawn::{spawn, SpawnError, Spawned};
use super::DaemonKey;
use super::DEFAULT_IDLE_TIMEOUT;
use crate::settle::{deadline_after, longest_wait, spin_time, Incomplete};
use crate::Global;

/// How long a daemon may take to answer beyond the wait it was asked for (its discovery wait
/// for a graph request; nothing for the others).
const ANSWER_MARGIN: Duration = Duration::from_secs(2);
/// How long sending a request may block.
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);

/// Why the daemon could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// The socket could not be created or connected.
    #[error("could not reach the daemon's socket: {0}")]
    Connect(io::Error),
    /// The daemon's socket accepts no more connections (its backlog is full: a stopped daemon).
    #[error("the daemon's socket accepts no connection (is the daemon stopped?)")]
    Busy,
    /// Another user's process holds the socket name.
    #[error("the daemon's socket belongs to another user (uid {uid}, pid {pid})")]
    Foreign {
        /// Its owner.
        uid: u32,
        /// Its process.
        pid: u32,
    },
    /// The exchange failed (timeout, closed connection, malformed answer, other version).
    #[error("the daemon (pid {pid}) did not answer: {cause}")]
    Exchange {
        /// The daemon's process id.
        pid: u32,
        /// What went wrong.
        cause: FrameError,
    },
    /// The daemon serves another graph (a digest collision of the keys).
    #[error("the daemon (pid {pid}) serves another graph: {daemon:?}")]
    WrongGraph {
        /// The daemon's process id.
        pid: u32,
        /// Its key.
        daemon: Box<DaemonKey>,
    },
    /// The daemon refused the request.
    #[error("the daemon (pid {pid}) refused the request: {message}")]
    Refused {
        /// The daemon's process id.
        pid: u32,
        /// Its message.
        message: String,
    },
    /// The daemon answered something else than what was asked.
    #[error("the daemon (pid {pid}) answered another request")]
    Unexpected {
        /// The daemon's process id.
        pid: u32,
    },
}

/// A connection to the daemon.
#[derive(Debug)]
pub struct Connection {
    stream: UnixStream,
    /// The daemon's process id (from the socket's peer credentials).
    pub pid: u32,
}

/// Connects to the daemon of `key`; `None` when none runs (nothing listens on its name).
pub fn connect(key: &DaemonKey) -> Result<Option<Connection>, ClientError> {
    let fd = socket::socket(
        AddressFamily::Unix,
        SockType::Stream,
        SockFlag::SOCK_CLOEXEC | SockFlag::SOCK_NONBLOCK,
        None,
    )
    .map_err(|e| ClientError::Connect(e.into()))?;
    let address = UnixAddr::new_abstract(key.socket_name().as_bytes())
        .map_err(|e| ClientError::Connect(e.into()))?;
    match socket::connect(fd.as_raw_fd(), &address) {
        Ok(()) => {}
        Err(Errno::ECONNREFUSED | Errno::ENOENT) => return Ok(None),
        // A Unix socket's non-blocking connect fails at once when the backlog is full.
        Err(Errno::EAGAIN) => return Err(ClientError::Busy),
        Err(e) => return Err(ClientError::Connect(e.into())),
    }
    let stream = UnixStream::from(fd);
    stream
        .set_nonblocking(false)
        .and_then(|()| stream.set_write_timeout(Some(WRITE_TIMEOUT)))
        .map_err(ClientError::Connect)?;
    let peer = socket::getsockopt(&stream, sockopt::PeerCredentials)
        .map_err(|e| ClientError::Connect(e.into()))?;
    let pid = u32::try_from(peer.pid()).unwrap_or(0);
    if peer.uid() != nix::unistd::getuid().as_raw() {
        return Err(ClientError::Foreign {
            uid: peer.uid(),
            pid,
        });
    }
    Ok(Some(Connection { stream, pid }))
}

impl Connection {
    /// Sends `request` about the graph of `key` and reads the answer, all before `deadline`.
    pub fn ask(
        &mut self,
        key: &DaemonKey,
        request: Request,
        deadline: Instant,
    ) -> Result<Response, ClientError> {
        let pid = self.pid;
        let exchange = |source| ClientError::Exchange { pid, cause: source };
        let frame = RequestFrame {
            version: protocol::VERSION,
            key: key.clone(),
            request,
        };
        protocol::write_frame(&mut self.stream, &frame).map_err(exchange)?;
        let answer: ResponseFrame =
            protocol::read_frame(&mut self.stream, MAX_RESPONSE, deadline).map_err(exchange)?;
        match answer.response {
            Response::WrongGraph { daemon } => Err(ClientError::WrongGraph {
                pid,
                daemon: Box::new(daemon),
            }),
            Response::Error { message } => Err(ClientError::Refused { pid, message }),
            other => Ok(other),
        }
    }

    /// Waits until the daemon has exited (its end of the connection closes with it), at most
    /// until `deadline`; returns whether it has.
    pub fn wait_gone(&mut self, deadline: Instant) -> bool {
        let mut buf = [0u8; 64];
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() || self.stream.set_read_timeout(Some(left)).is_err() {
                return false;
            }
            match self.stream.read(&mut buf) {
                Ok(0) => return true,
                Ok(_) => {}
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                // A reset connection is gone too.
                Err(e) if e.kind() == io::ErrorKind::ConnectionReset => return true,
                Err(_) => return false,
            }
        }
    }
}

/// The daemon's status; `None` when none runs.
pub fn status(key: &DaemonKey) -> Result<Option<Status>, ClientError> {
    let Some(mut connection) = connect(key)? else {
        return Ok(None);
    };
    let deadline = Instant::now() + ANSWER_MARGIN;
    match connection.ask(key, Request::Status, deadline)? {
        Response::Status(status) => Ok(Some(status)),
        _ => Err(ClientError::Unexpected {
            pid: connection.pid,
        }),
    }
}

/// The graph a daemon answered with.
#[derive(Debug)]
pub struct DaemonGraph {
    /// Its graph, rebuilt from the snapshot.
    pub cache: GraphCache,
    /// Its domain.
    pub domain_id: u16,
    /// What was missing when the daemon's wait hit a bound (`None`: complete).
    pub incomplete: Option<Incomplete>,
}

/// How asking for the daemon's graph went.
#[derive(Debug)]
pub enum GraphAnswer {
    /// It answered.
    Answered(Box<DaemonGraph>),
    /// No daemon runs for these options (or they name no valid graph: the direct path reports
    /// that).
    NotRunning,
    /// It runs but could not be used; one line on stderr said why.
    Unusable,
}

/// The daemon's graph for these options, as ros2cli's `NodeStrategy` gets it: from the daemon
/// when one runs; when none does, from one started now (as `daemon start` would, with its
/// default idle timeout). `None` after one line on stderr when the daemon could not be started
/// or used: the caller then discovers the graph itself.
pub fn graph_or_spawn(global: &Global) -> Option<DaemonGraph> {
    match graph(global) {
        GraphAnswer::Answered(graph) => return Some(*graph),
        GraphAnswer::Unusable => return None,
        GraphAnswer::NotRunning => {}
    }
    let key = DaemonKey::of(global).ok()?;
    match spawn(&key, DEFAULT_IDLE_TIMEOUT, false) {
        Ok(Spawned::Ready(_) | Spawned::AlreadyRunning) => match graph(global) {
            GraphAnswer::Answered(graph) => Some(*graph),
            GraphAnswer::Unusable => None,
            GraphAnswer::NotRunning => {
                eprintln!(
                    "WARNING: the daemon stopped as it was started; discovering the graph directly"
                );
                None
            }
        },
        Err(e) => {
            spawn_failed(&e);
            None
        }
    }
}

/// The one line for a daemon that could not be started.
fn spawn_failed(e: &SpawnError) {
    eprintln!("WARNING: could not start the daemon ({e}); discovering the graph directly");
}

/// The daemon's graph for these options, if a daemon runs for them (after one line on stderr
/// when it does not answer properly).
pub fn graph(global: &Global) -> GraphAnswer {
    let Ok(key) = DaemonKey::of(global) else {
        return GraphAnswer::NotRunning;
    };
    match ask_graph(&key, spin_time(global)) {
        Ok(Some((cache, incomplete))) => {
            // What the context would have warned about (ROS_LOCALHOST_ONLY's deprecation…).
            if let Ok(environment) =
                horus_ros_rmw::context::env::read_environment(|k| std::env::var(k).ok())
            {
                for w in &environment.warnings {
                    tracing::warn!("{w}");
                }
            }
            GraphAnswer::Answered(Box::new(DaemonGraph {
                cache,
                domain_id: key.domain_id,
                incomplete,
            }))
        }
        Ok(None) => GraphAnswer::NotRunning,
        Err(e) => {
            eprintln!("WARNING: {e}; discovering the graph directly");
            GraphAnswer::Unusable
        }
    }
}

/// Asks the daemon of `key` for its graph, letting it wait for completeness as a command with
/// `--spin-time` `spin` would.
fn ask_graph(
    key: &DaemonKey,
    spin: Duration,
) -> Result<Option<(GraphCache, Option<Incomplete>)>, ClientError> {
    let Some(mut connection) = connect(key)? else {
        return Ok(None);
    };
    let spin_time_ms = u64::try_from(spin.as_millis()).unwrap_or(u64::MAX);
    let deadline = deadline_after(
        Instant::now(),
        longest_wait(spin).saturating_add(ANSWER_MARGIN),
    );
    match connection.ask(key, Request::Graph { spin_time_ms }, deadline)? {
        Response::Graph {
            snapshot,
            incomplete,
        } => Ok(Some((GraphCache::from_snapshot(snapshot), incomplete))),
        _ => Err(ClientError::Unexpected {
            pid: connection.pid,
        }),
    }
}
