//! What the CLI and its daemon say to each other: one request and one response per connection,
//! each a frame — a 4-byte big-endian length, then that many bytes of JSON — carrying the
//! protocol [`VERSION`]. Frames are bounded ([`MAX_REQUEST`], [`MAX_RESPONSE`]) and every read
//! has a deadline, so neither side can be made to hang or to allocate without limit.

use std::io::{self, Read, Write};
use std::os::unix::net::UnixStream;
use std::time::{Duration, Instant};

use horus_ros_graph::GraphSnapshot;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::DaemonKey;
use crate::settle::Incomplete;

/// The protocol version; a daemon answers only requests of its own version.
pub const VERSION: u32 = 2;
/// The largest request frame.
pub const MAX_REQUEST: usize = 64 * 1024;
/// The largest response frame (a graph of tens of thousands of endpoints fits).
pub const MAX_RESPONSE: usize = 256 * 1024 * 1024;

/// A request, with the key of the graph it is about.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RequestFrame {
    /// [`VERSION`].
    pub version: u32,
    /// The graph the client wants (the daemon refuses another).
    pub key: DaemonKey,
    /// What it asks.
    pub request: Request,
}

/// What a client asks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Request {
    /// Who the daemon is (does not count as activity, as ros2cli's `system.listMethods`).
    Status,
    /// The graph, once complete: the daemon waits for that as a command does for its own
    /// graph (`crate::settle`), with the client's `--spin-time`.
    Graph {
        /// The client's `--spin-time`, in milliseconds.
        spin_time_ms: u64,
    },
    /// Stop. The daemon answers, then keeps the connection open until it exits, so that the
    /// client sees it gone (end of stream) without polling.
    Shutdown,
}

/// A response.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResponseFrame {
    /// [`VERSION`].
    pub version: u32,
    /// The answer.
    pub response: Response,
}

/// What the daemon answers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Response {
    /// Who it is.
    Status(Status),
    /// Its graph.
    Graph {
        /// Everything its graph holds.
        snapshot: GraphSnapshot,
        /// What was still missing when its wait hit a bound (`None`: complete).
        incomplete: Option<Incomplete>,
    },
    /// It is stopping.
    ShuttingDown,
    /// The request was for another graph: the daemon's own key.
    WrongGraph {
        /// The daemon's key.
        daemon: DaemonKey,
    },
    /// The request could not be served.
    Error {
        /// Why.
        message: String,
    },
}

/// The daemon's identity and settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Status {
    /// Its process id.
    pub pid: u32,
    /// Its hidden node's name.
    pub node_name: String,
    /// The graph it serves.
    pub key: DaemonKey,
    /// Its idle timeout, in seconds.
    pub idle_timeout_s: u64,
    /// How long it has run, in seconds.
    pub uptime_s: f64,
}

/// Why a frame could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    /// The socket failed.
    #[error(transparent)]
    Io(#[from] io::Error),
    /// Nothing (or not all of it) arrived before the deadline.
    #[error("no answer within {:.1} s", .0.as_secs_f64())]
    TimedOut(Duration),
    /// The other side closed the connection before a whole frame.
    #[error("the connection was closed")]
    Closed,
    /// The frame announced more than the limit.
    #[error("a message of {len} bytes is over the limit of {max}")]
    TooLarge {
        /// The announced length.
        len: usize,
        /// The limit.
        max: usize,
    },
    /// The other side speaks another version of the protocol.
    #[error("protocol version {0} (this horus-ros speaks {VERSION})")]
    Version(u32),
    /// The frame is not the JSON expected.
    #[error("malformed message: {0}")]
    Json(serde_json::Error),
}

// The message shows the cause, so it is no `source()` (not `#[from]`).
impl From<serde_json::Error> for FrameError {
    fn from(e: serde_json::Error) -> Self {
        Self::Json(e)
    }
}

/// Writes `value` as one frame.
pub fn write_frame<T: Serialize>(stream: &mut impl Write, value: &T) -> Result<(), FrameError> {
    let body = serde_json::to_vec(value)?;
    let len = u32::try_from(body.len()).map_err(|_| FrameError::TooLarge {
        len: body.len(),
        max: u32::MAX as usize,
    })?;
    let mut frame = Vec::with_capacity(4 + body.len());
    frame.extend_from_slice(&len.to_be_bytes());
    frame.extend_from_slice(&body);
    stream.write_all(&frame)?;
    stream.flush()?;
    Ok(())
}

/// Reads one frame of at most `max` bytes, all of it before `deadline`, and parses it as a `T`
/// of protocol [`VERSION`] (any other version is [`FrameError::Version`]).
pub fn read_frame<T: DeserializeOwned>(
    stream: &mut UnixStream,
    max: usize,
    deadline: Instant,
) -> Result<T, FrameError> {
    let started = Instant::now();
    let mut len = [0u8; 4];
    read_exact_by(stream, &mut len, deadline, started)?;
    let len = u32::from_be_bytes(len) as usize;
    if len > max {
        return Err(FrameError::TooLarge { len, max });
    }
    let mut body = vec![0u8; len];
    read_exact_by(stream, &mut body, deadline, started)?;
    #[derive(Deserialize)]
    struct Versioned {
        version: u32,
    }
    let versioned: Versioned = serde_json::from_slice(&body)?;
    if versioned.version != VERSION {
        return Err(FrameError::Version(versioned.version));
    }
    Ok(serde_json::from_slice(&body)?)
}

/// Fills `buf` from the stream, every read bounded by what is left until `deadline`.
fn read_exact_by(
    stream: &mut UnixStream,
    mut buf: &mut [u8],
    deadline: Instant,
    started: Instant,
) -> Result<(), FrameError> {
    while !buf.is_empty() {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(FrameError::TimedOut(deadline - started));
        }
        stream.set_read_timeout(Some(left))?;
        match stream.read(buf) {
            Ok(0) => return Err(FrameError::Closed),
            Ok(n) => buf = &mut buf[n..],
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) =>
            {
                return Err(FrameError::TimedOut(deadline - started));
            }
            Err(e) => return Err(e.into()),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> DaemonKey {
        DaemonKey {
            domain_id: 3,
            backend: "rustdds".to_owned(),
            discovery_range: "SUBNET".to_owned(),
            static_peers: vec![],
            backend_environment: Default::default(),
        }
    }

    fn soon() -> Instant {
        Instant::now() + Duration::from_secs(5)
    }

    #[test]
    fn frames_round_trip() {
        let (mut a, mut b) = UnixStream::pair().expect("pair");
        let request = RequestFrame {
            version: VERSION,
            key: key(),
            request: Request::Graph { spin_time_ms: 500 },
        };
        write_frame(&mut a, &request).expect("write");
        let got: RequestFrame = read_frame(&mut b, MAX_REQUEST, soon()).expect("read");
        assert_eq!(got, request);
        let response = ResponseFrame {
            version: VERSION,
            response: Response::Graph {
                snapshot: GraphSnapshot::default(),
                incomplete: Some(Incomplete {
                    unsettled: horus_ros_graph::Unsettled {
                        missing_endpoints: 2,
                        ..Default::default()
                    },
                    bound_ms: 4605,
                }),
            },
        };
        write_frame(&mut b, &response).expect("write");
        let got: ResponseFrame = read_frame(&mut a, MAX_RESPONSE, soon()).expect("read");
        assert_eq!(got, response);
    }

    #[test]
    fn oversized_frames_are_refused_before_reading_them() {
        let (mut a, mut b) = UnixStream::pair().expect("pair");
        a.write_all(&(MAX_REQUEST as u32 + 1).to_be_bytes())
            .expect("write");
        let got = read_frame::<RequestFrame>(&mut b, MAX_REQUEST, soon());
        assert!(matches!(got, Err(FrameError::TooLarge { .. })), "{got:?}");
    }

    #[test]
    fn other_versions_are_told_apart() {
        let (mut a, mut b) = UnixStream::pair().expect("pair");
        write_frame(
            &mut a,
            &serde_json::json!({"version": 1, "anything": "else"}),
        )
        .expect("write");
        let got = read_frame::<RequestFrame>(&mut b, MAX_REQUEST, soon());
        assert!(matches!(got, Err(FrameError::Version(1))), "{got:?}");
    }

    #[test]
    fn silence_times_out_and_a_short_frame_is_closed() {
        let (mut a, mut b) = UnixStream::pair().expect("pair");
        let deadline = Instant::now() + Duration::from_millis(50);
        let got = read_frame::<RequestFrame>(&mut b, MAX_REQUEST, deadline);
        assert!(matches!(got, Err(FrameError::TimedOut(_))), "{got:?}");
        a.write_all(&10u32.to_be_bytes()).expect("write");
        a.write_all(b"{\"ver").expect("write");
        drop(a);
        let got = read_frame::<RequestFrame>(&mut b, MAX_REQUEST, soon());
        assert!(matches!(got, Err(FrameError::Closed)), "{got:?}");
    }
}
