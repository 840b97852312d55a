//! The daemon process (`horus-ros daemon _run`, started by `horus-ros daemon start`): one
//! [`Session`] and its live graph, served on the daemon's socket until it is stopped, is
//! signalled (SIGINT, SIGTERM, SIGHUP) or has had no graph request for its idle timeout (as
//! ros2cli's `serve`, `daemon/__init__.py`).
//!
//! The main thread waits on the socket and on a wake-up pipe with the time left until the idle
//! timeout (`poll`), so it sleeps until a client connects, a stop is asked, or the timeout. Each
//! client gets its own thread with read and write timeouts; at most [`MAX_CLIENTS`] at once.

use std::io::{self, Read, Write};
use std::os::fd::AsFd;
use std::os::unix::net::{UnixListener, UnixStream};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use horus_ros_graph::Graph;
use nix::poll::{PollFd, PollFlags, PollTimeout};
use nix::sys::socket::sockopt;

use super::protocol::{
    self, FrameError, Request, RequestFrame, Response, ResponseFrame, Status, MAX_REQUEST,
};
use super::DaemonKey;
use crate::session::Session;
use crate::settle::{deadline_after, Outstanding, Wait};
use crate::{CliError, Global};

/// What the daemon prints on its stdout (a pipe `daemon start` reads) once it serves.
pub const READY: &str = "ready";
/// What it prints when another daemon already holds its socket.
pub const ALREADY_RUNNING: &str = "already running";
/// What starts the line it prints when it cannot start.
pub const FAILED: &str = "error: ";

/// Most clients served at once (more are closed at once; they fall back to discovery).
const MAX_CLIENTS: usize = 64;
/// How long a client may take to send its request.
const REQUEST_TIMEOUT: Duration = Duration::from_secs(5);
/// How long writing an answer may block.
const WRITE_TIMEOUT: Duration = Duration::from_secs(10);
/// The longest a graph request may make the daemon wait for its graph to be consistent.
const MAX_GRAPH_WAIT: Duration = Duration::from_secs(3600);
/// How long a stopping daemon lets graph requests in progress finish.
const STOP_GRACE: Duration = Duration::from_secs(1);

/// Runs the daemon until it stops. Its first stdout line tells `daemon start` how starting went
/// ([`READY`], [`ALREADY_RUNNING`], or [`FAILED`] and why); stdout then goes to `/dev/null`.
pub fn run(global: &Global, idle_timeout: Duration) -> Result<(), CliError> {
    // Out of the starting shell's session and process group (no terminal signals), and off its
    // working directory. Fails only when already a session leader, which is as good.
    let _ = nix::unistd::setsid();
    let _ = std::env::set_current_dir("/");
    let started = Instant::now();
    let (key, listener) = match bind(global) {
        Ok(Some(bound)) => bound,
        Ok(None) => {
            tell(ALREADY_RUNNING);
            return Ok(());
        }
        Err(e) => {
            tell(&format!("{FAILED}{}", e.message));
            return Err(e);
        }
    };
    let node_name = super::node_name(key.domain_id);
    let session = match Session::join_as(global, &node_name) {
        Ok(session) => session,
        Err(e) => {
            tell(&format!("{FAILED}{}", e.message));
            return Err(e);
        }
    };
    let (wake_reader, wake_writer) = io::pipe().map_err(|e| CliError::new(e.to_string()))?;
    let shared = Arc::new(Shared {
        status: Status {
            pid: std::process::id(),
            node_name,
            key,
            idle_timeout_s: idle_timeout.as_secs(),
            uptime_s: 0.0,
        },
        started,
        joined: session.joined,
        outstanding: session
            .outstanding()
            .cloned()
            .unwrap_or_else(|| Outstanding::watch(&session.graph)),
        graph: Mutex::new(Some(Arc::clone(&session.graph))),
        state: Mutex::new(State {
            last_activity: Instant::now(),
            stopping: false,
            clients: 0,
            graph_requests: 0,
        }),
        graph_requests_done: Condvar::new(),
        wake: wake_writer,
    });
    let on_signal = Arc::clone(&shared);
    if let Err(e) = ctrlc::set_handler(move || {
        tracing::info!("Shutdown on a signal");
        on_signal.stop();
    }) {
        tracing::warn!("signals will end the daemon abruptly: {e}");
    }
    tell(READY);
    quiet_stdout();
    tracing::info!(
        socket = shared.status.key.socket_name(),
        node = shared.status.node_name,
        "serving"
    );
    serve(&shared, &listener, &wake_reader, idle_timeout);

    // The socket's name is free as soon as the listener is closed; then the graph and the
    // participant go, cleanly, once requests in progress are done with them.
    drop(listener);
    let graph = lock(&shared.graph).take();
    let state = lock(&shared.state);
    let (state, _) = shared
        .graph_requests_done
        .wait_timeout_while(state, STOP_GRACE, |s| s.graph_requests > 0)
        .unwrap_or_else(|p| p.into_inner());
    drop(state);
    drop(graph);
    drop(session);
    Ok(())
}

/// Binds the daemon's socket: `None` when another daemon holds it.
fn bind(global: &Global) -> Result<Option<(DaemonKey, UnixListener)>, CliError> {
    let key = DaemonKey::of(global)?;
    let address = key.address()?;
    match UnixListener::bind_addr(&address) {
        Ok(listener) => {
            listener.set_nonblocking(true)?;
            Ok(Some((key, listener)))
        }
        Err(e) if e.kind() == io::ErrorKind::AddrInUse => Ok(None),
        Err(e) => Err(CliError::new(format!(
            "could not bind the daemon's socket {}: {e}",
            key.socket_name()
        ))),
    }
}

/// One line to `daemon start`.
fn tell(line: &str) {
    let mut out = io::stdout().lock();
    let _ = writeln!(out, "{line}").and_then(|()| out.flush());
}

/// Points stdout at `/dev/null`: `daemon start` has read what it waited for and exited.
fn quiet_stdout() {
    match std::fs::OpenOptions::new().write(true).open("/dev/null") {
        Ok(null) => {
            if let Err(e) = nix::unistd::dup2_stdout(null) {
                tracing::warn!("could not detach stdout: {e}");
            }
        }
        Err(e) => tracing::warn!("could not open /dev/null: {e}"),
    }
}

/// What the threads share.
struct Shared {
    /// The daemon's identity (`uptime_s` is filled in per answer).
    status: Status,
    /// When the process started.
    started: Instant,
    /// When its graph started following discovery.
    joined: Instant,
    /// Which participants of the graph have been outstanding since when.
    outstanding: Arc<Outstanding>,
    /// The live graph; `None` once stopping.
    graph: Mutex<Option<Arc<Graph>>>,
    /// What changes.
    state: Mutex<State>,
    /// Signalled when a graph request ends.
    graph_requests_done: Condvar,
    /// Written to wake the main thread.
    wake: io::PipeWriter,
}

struct State {
    /// The last graph request (ros2cli resets its idle timer on every graph call).
    last_activity: Instant,
    /// Asked to stop.
    stopping: bool,
    /// Client threads running.
    clients: usize,
    /// Graph requests in progress.
    graph_requests: usize,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Shared {
    /// Asks the main thread to stop.
    fn stop(&self) {
        lock(&self.state).stopping = true;
        let _ = (&self.wake).write_all(b"x");
    }

    /// The graph for one request, counted in progress (until the [`GraphRequest`] drops) and as
    /// activity; `None` once stopping.
    fn begin_graph_request(&self) -> Option<(Arc<Graph>, GraphRequest<'_>)> {
        let graph = lock(&self.graph).clone()?;
        let mut state = lock(&self.state);
        state.last_activity = Instant::now();
        state.graph_requests += 1;
        Some((graph, GraphRequest(self)))
    }
}

/// Accepts clients until asked to stop or idle for `idle_timeout`.
fn serve(
    shared: &Arc<Shared>,
    listener: &UnixListener,
    wake: &io::PipeReader,
    idle_timeout: Duration,
) {
    loop {
        let idle_until = {
            let state = lock(&shared.state);
            if state.stopping {
                return;
            }
            deadline_after(state.last_activity, idle_timeout)
        };
        let now = Instant::now();
        if now >= idle_until {
            tracing::info!("Shutdown due to timeout");
            return;
        }
        let mut fds = [
            PollFd::new(listener.as_fd(), PollFlags::POLLIN),
            PollFd::new(wake.as_fd(), PollFlags::POLLIN),
        ];
        match nix::poll::poll(&mut fds, poll_timeout(idle_until - now)) {
            Ok(_) => {}
            Err(nix::errno::Errno::EINTR) => continue,
            Err(e) => {
                tracing::error!("waiting on the socket failed: {e}");
                return;
            }
        }
        let ready = |fd: &PollFd| fd.revents().is_some_and(|r| !r.is_empty());
        let (connecting, woken) = (ready(&fds[0]), ready(&fds[1]));
        if woken {
            // One read takes every byte written so far (a few at most).
            let _ = (&*wake).read(&mut [0u8; 64]);
        }
        if connecting && !accept_all(shared, listener) {
            return;
        }
    }
}

/// Hands every waiting connection to a thread of its own; `false` when accepting failed.
fn accept_all(shared: &Arc<Shared>, listener: &UnixListener) -> bool {
    loop {
        match listener.accept() {
            Ok((stream, _)) => admit(shared, stream),
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => return true,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) if e.kind() == io::ErrorKind::ConnectionAborted => {}
            Err(e) => {
                tracing::error!("accepting a client failed: {e}");
                return false;
            }
        }
    }
}

/// Starts serving one client, if it is this user's and there is room.
fn admit(shared: &Arc<Shared>, stream: UnixStream) {
    let own = nix::unistd::getuid().as_raw();
    match nix::sys::socket::getsockopt(&stream, sockopt::PeerCredentials) {
        Ok(peer) if peer.uid() == own => {}
        Ok(peer) => {
            tracing::warn!(uid = peer.uid(), pid = peer.pid(), "refused another user");
            return;
        }
        Err(e) => {
            tracing::warn!("could not read a client's credentials: {e}");
            return;
        }
    }
    {
        let mut state = lock(&shared.state);
        if state.clients >= MAX_CLIENTS {
            tracing::warn!("{MAX_CLIENTS} clients already: one refused");
            return;
        }
        state.clients += 1;
    }
    let slot = ClientSlot(Arc::clone(shared));
    let spawned = std::thread::Builder::new()
        .name("horus-ros-daemon-client".to_owned())
        .spawn(move || serve_client(&slot.0, stream));
    if let Err(e) = spawned {
        // The slot went with the closure.
        tracing::warn!("could not start a client thread: {e}");
    }
}

/// One client counted in [`State::clients`] until dropped (even by a panicking thread).
struct ClientSlot(Arc<Shared>);

impl Drop for ClientSlot {
    fn drop(&mut self) {
        lock(&self.0.state).clients -= 1;
    }
}

/// One graph request counted in [`State::graph_requests`] until dropped.
struct GraphRequest<'a>(&'a Shared);

impl Drop for GraphRequest<'_> {
    fn drop(&mut self) {
        lock(&self.0.state).graph_requests -= 1;
        self.0.graph_requests_done.notify_all();
    }
}

/// Reads one request and answers it.
fn serve_client(shared: &Shared, mut stream: UnixStream) {
    if let Err(e) = stream
        .set_nonblocking(false)
        .and_then(|()| stream.set_write_timeout(Some(WRITE_TIMEOUT)))
    {
        tracing::warn!("client socket: {e}");
        return;
    }
    let deadline = Instant::now() + REQUEST_TIMEOUT;
    let request = match protocol::read_frame::<RequestFrame>(&mut stream, MAX_REQUEST, deadline) {
        Ok(request) => request,
        Err(FrameError::Version(v)) => {
            answer(
                &mut stream,
                Response::Error {
                    message: format!(
                        "this daemon speaks protocol version {}, not {v}: restart it \
                         ('horus-ros daemon stop', then 'horus-ros daemon start')",
                        protocol::VERSION
                    ),
                },
            );
            return;
        }
        Err(e) => {
            tracing::debug!("bad request: {e}");
            return;
        }
    };
    tracing::info!(request = ?request.request, "request");
    if request.key != shared.status.key {
        answer(
            &mut stream,
            Response::WrongGraph {
                daemon: shared.status.key.clone(),
            },
        );
        return;
    }
    match request.request {
        Request::Status => {
            let mut status = shared.status.clone();
            status.uptime_s = shared.started.elapsed().as_secs_f64();
            answer(&mut stream, Response::Status(status));
        }
        Request::Graph { spin_time_ms } => {
            let Some((graph, in_progress)) = shared.begin_graph_request() else {
                answer(
                    &mut stream,
                    Response::Error {
                        message: "the daemon is stopping".to_owned(),
                    },
                );
                return;
            };
            let asked = Instant::now();
            let incomplete = Wait {
                graph: &graph,
                outstanding: &shared.outstanding,
                joined: shared.joined,
                start: asked,
                spin: Duration::from_millis(spin_time_ms).min(MAX_GRAPH_WAIT),
            }
            .run();
            let snapshot = graph.read(|c| c.snapshot());
            drop(graph);
            drop(in_progress);
            tracing::info!(
                waited_ms = asked.elapsed().as_secs_f64() * 1e3,
                complete = incomplete.is_none(),
                endpoints = snapshot.endpoints.len(),
                "graph"
            );
            answer(
                &mut stream,
                Response::Graph {
                    snapshot,
                    incomplete,
                },
            );
        }
        Request::Shutdown => {
            tracing::info!("Remote shutdown requested");
            shared.stop();
            answer(&mut stream, Response::ShuttingDown);
            // Held open: the client sees the end of the stream when this process has exited.
            let _ = stream.set_read_timeout(None);
            let _ = stream.read(&mut [0u8; 1]);
        }
    }
}

fn answer(stream: &mut UnixStream, response: Response) {
    let frame = ResponseFrame {
        version: protocol::VERSION,
        response,
    };
    if let Err(e) = protocol::write_frame(stream, &frame) {
        tracing::debug!("could not answer: {e}");
    }
}

/// `left` for `poll`, rounded up to the next millisecond (so that it never returns early and
/// spins), at most `poll`'s longest.
fn poll_timeout(left: Duration) -> PollTimeout {
    let ms = left.as_micros().div_ceil(1000);
    PollTimeout::try_from(ms).unwrap_or(PollTimeout::MAX)
}
