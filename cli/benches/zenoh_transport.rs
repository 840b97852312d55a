//! The Zenoh backend's transports beside Cyclone DDS and raw UDP, in one run: service round
//! trips and 1 MiB / 6 MiB topic throughput. Opens DDS participants and Zenoh sessions: run it
//! only inside a private network namespace (`scripts/bench`, or
//! `scripts/isolated cargo bench -p horus-ros-cli --bench zenoh_transport`); it refuses to run
//! when it can see a network interface other than `lo` up.
//!
//! Every variant is two processes: this bench (the measuring side: service client, subscriber,
//! UDP receiver) and a child of it (this bench re-run with [`CHILD_ENV`] set: service server,
//! publisher, UDP sender), one child per variant, all set up before the first measurement and
//! measured in interleaved rounds (so every variant sees the same machine state):
//!
//! 1. `udp`: raw UDP on 127.0.0.1, the floor. Round trip: a 20-byte ping (the CDR size of an
//!    AddTwoInts request) echoed by the child. Throughput: each message is split into datagrams
//!    of at most [`UDP_CHUNK`] bytes (under 64 KiB) with a 12-byte header (message number,
//!    fragment index, fragment count); the receiver copies each fragment into place and counts a
//!    message **delivered when all its fragments arrived**, **lost** when its last fragment
//!    arrived (or the next message began) with some missing. The receiver acknowledges each
//!    message (a 4-byte datagram) and the sender keeps at most [`UDP_WINDOW`] bytes (at least one
//!    message) unacknowledged, so that the receiver's socket buffer ([`UDP_RCVBUF`], forced as
//!    root) cannot overflow: there is no other flow control in UDP.
//! 2. `cyclone`: horus-ros on the Cyclone DDS backend (`CYCLONEDDS_URI`, else loopback with a
//!    4 MB socket receive buffer as `cli/benches/topic.rs` uses).
//! 3. `p2p`: horus-ros on the Zenoh backend, rmw_zenoh's session configuration (peers that
//!    connect to a router and, told of each other by its gossip, to each other): the data flows
//!    peer to peer. The router is a Zenoh session in this bench, opened with the configuration
//!    `horus-ros router` uses; each variant has its own router and ports.
//! 4. `routed`: as `p2p` but with `scouting/gossip/autoconnect={router:[],peer:["router"]}`:
//!    the peers connect to the router only, which forwards between them (zenoh's
//!    `routing/router/peers_failover_brokering`, on by default).
//! 5. `shm`: as `p2p` with `transport/shared_memory/enabled=true` on both sessions. Shared
//!    memory is used only when the zenoh crate is built with its `shared-memory` feature and the
//!    backend puts samples in shared memory; otherwise this row measures the same TCP path as
//!    `p2p`. The bench prints how many `/dev/shm` files each Zenoh variant's child process has
//!    mapped (from `/proc/<pid>/maps`: Zenoh's shared-memory segments), to tell which.
//!
//! Which TCP links each Zenoh variant actually has after set-up is read from `/proc/net/tcp*`
//! (the namespace holds only this bench's sockets; every session listens on a port of its own)
//! and printed, so that "peer to peer" and "through the router" are observed, not assumed.
//!
//! Service: `ServiceClient::call` of AddTwoInts against a `ServiceServer` in the child,
//! `HORUS_BENCH_ZT_CALLS` sequential calls (default 20000) in `HORUS_BENCH_ZT_ROUNDS` rounds
//! (default 10) after 200 warm-up calls: p50 / p99 / calls per second, and their ratios to UDP.
//!
//! Topics: `sensor_msgs/msg/Image` of 1 MiB (`mono8` 1024×1024, 1 048 576 bytes of data) and of
//! "6 MiB" (`rgb8` 1920×1080, 6 220 800 bytes), RELIABLE, KEEP_ALL, VOLATILE; the child
//! publishes `HORUS_BENCH_ZT_MSGS_1M` (default 200) and `HORUS_BENCH_ZT_MSGS_6M` (default 40)
//! messages back to back per round (`HORUS_BENCH_ZT_TOPIC_ROUNDS`, default 5), each a clone of
//! one prepared image with the round's tag in `header.frame_id`. Timed from the command to the
//! child (a line on its stdin) to the last message of the round taken and decoded by the
//! subscriber; a round ends early when nothing arrived for [`IDLE_LIMIT`], the rest counted as
//! lost. Printed: messages per second, MiB/s of image data, the ratio to UDP's MiB/s, messages
//! delivered of those sent, the CPU time per message delivered of the publishing process (the
//! child) and of the subscribing one (this bench, with the variant's in-process router: all
//! its threads; from `/proc/<pid>/stat`, 10 ms ticks), and the MiB/s of each round; beside
//! them, what one message costs in one process without a transport (clone + CDR encode, CDR
//! decode), the floor of the publisher's and the subscriber's CPU per message.
//!
//! `HORUS_BENCH_ZT_ONLY` (comma-separated subset of `udp,cyclone,p2p,routed,shm`) runs some
//! variants only (the ratios need `udp`). Ports 17600 to 17650 and domains 200 to 203 are used.

use horus_ros_test_support::bench::{env_usize, loadavg, percentile};
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, UdpSocket};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::sensor_msgs::msg::Image;
use horus_ros_msgs::std_msgs::msg::Header;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::{Backend, Context, Node, Publisher, SignalHandlerOptions, Subscription};
use horus_ros_services::prelude::*;
use zenoh::Wait;

/// Set in a child: `<variant key>` (see [`VARIANTS`]).
const CHILD_ENV: &str = "HORUS_BENCH_ZT_CHILD";
const DEFAULT_CALLS: usize = 20_000;
const DEFAULT_ROUNDS: usize = 10;
const DEFAULT_MSGS_1M: usize = 200;
const DEFAULT_MSGS_6M: usize = 40;
const DEFAULT_TOPIC_ROUNDS: usize = 5;
/// Warm-up calls per variant, not measured.
const WARMUP_CALLS: usize = 200;
/// Warm-up messages per variant and size, not measured.
const WARMUP_MSGS: usize = 3;
/// Whole-run limit: a stalled variant aborts the bench instead of hanging it.
const WATCHDOG: Duration = Duration::from_secs(900);
const CALL_TIMEOUT: Duration = Duration::from_secs(5);
const DISCOVERY_TIMEOUT: Duration = Duration::from_secs(20);
/// A throughput round ends when nothing arrived for this long.
const IDLE_LIMIT: Duration = Duration::from_secs(5);
const SERVICE: &str = "/bench_add_two_ints";
const TOPIC_1M: &str = "/bench_image_1m";
const TOPIC_6M: &str = "/bench_image_6m";
/// Cyclone DDS when `CYCLONEDDS_URI` is unset: loopback, multicast, a 4 MB socket receive
/// buffer (as `cli/benches/topic.rs`: without it no 6 MiB image arrives).
const CYCLONE_CONFIG: &str = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>\
    <AllowMulticast>true</AllowMulticast></General><Internal>\
    <SocketReceiveBufferSize min=\"4MB\"/></Internal></Domain></CycloneDDS>";
/// The UDP round trip's payload: CDR encapsulation (4) + two int64 (16), as a request.
const UDP_PING: usize = 20;
/// Image data per UDP datagram (a datagram is this plus [`UDP_HEADER`], under 64 KiB).
const UDP_CHUNK: usize = 65_000;
/// Message number (u32), fragment index (u32), fragment count (u32), little-endian.
const UDP_HEADER: usize = 12;
/// Bytes the UDP sender may have unacknowledged (at least one message).
const UDP_WINDOW: usize = 4 << 20;
/// The UDP receiver's socket buffer (SO_RCVBUFFORCE; SO_RCVBUF, capped by rmem_max, if refused).
const UDP_RCVBUF: usize = 16 << 20;
/// How long the UDP sender waits for an acknowledgement before going on without it.
const UDP_ACK_WAIT: Duration = Duration::from_millis(200);

// ---------------------------------------------------------------------------------------------
// The variants.

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    Udp,
    Cyclone,
    ZenohP2p,
    ZenohRouted,
    ZenohShm,
}

struct Variant {
    key: &'static str,
    name: &'static str,
    kind: Kind,
    /// Domain (DDS and Zenoh) and the first of the variant's ports: router, child, parent.
    domain: u32,
    port: u16,
}

const VARIANTS: [Variant; 5] = [
    Variant {
        key: "udp",
        name: "raw UDP 127.0.0.1",
        kind: Kind::Udp,
        domain: 0,
        port: 0,
    },
    Variant {
        key: "cyclone",
        name: "Cyclone DDS",
        kind: Kind::Cyclone,
        domain: 200,
        port: 0,
    },
    Variant {
        key: "p2p",
        name: "Zenoh peer to peer",
        kind: Kind::ZenohP2p,
        domain: 201,
        port: 17600,
    },
    Variant {
        key: "routed",
        name: "Zenoh through the router",
        kind: Kind::ZenohRouted,
        domain: 202,
        port: 17620,
    },
    Variant {
        key: "shm",
        name: "Zenoh p2p + shared_memory",
        kind: Kind::ZenohShm,
        domain: 203,
        port: 17640,
    },
];

impl Variant {
    fn backend(&self) -> Option<Backend> {
        match self.kind {
            Kind::Udp => None,
            Kind::Cyclone => Some(Backend::Cyclone),
            Kind::ZenohP2p | Kind::ZenohRouted | Kind::ZenohShm => Some(Backend::Zenoh),
        }
    }

    fn is_zenoh(&self) -> bool {
        self.backend() == Some(Backend::Zenoh)
    }

    fn router_port(&self) -> u16 {
        self.port
    }

    fn child_port(&self) -> u16 {
        self.port + 1
    }

    fn parent_port(&self) -> u16 {
        self.port + 2
    }

    /// `ZENOH_CONFIG_OVERRIDE` of a session listening on `listen`.
    fn zenoh_override(&self, listen: u16) -> String {
        let mut o = format!(
            r#"connect/endpoints=["tcp/127.0.0.1:{}"];listen/endpoints=["tcp/127.0.0.1:{listen}"]"#,
            self.router_port()
        );
        match self.kind {
            Kind::ZenohRouted => {
                o.push_str(r#";scouting/gossip/autoconnect={router:[],peer:["router"]}"#)
            }
            Kind::ZenohShm => o.push_str(";transport/shared_memory/enabled=true"),
            _ => {}
        }
        o
    }
}

// ---------------------------------------------------------------------------------------------
// Refuse to run where DDS could reach a real network (as services/benches/service_roundtrip.rs).

fn refuse_outside_namespace() {
    horus_ros_test_support::bench::refuse_outside_namespace(
        "zenoh_transport",
        "scripts/isolated cargo bench -p horus-ros-cli --bench zenoh_transport (build it outside first: cargo bench -p horus-ros-cli --bench zenoh_transport --no-run)",
    );
}

// ---------------------------------------------------------------------------------------------
// Messages.

/// The two message sizes: (label, topic, width, height, encoding, bytes per pixel).
#[derive(Clone, Copy)]
struct Size {
    label: &'static str,
    topic: &'static str,
    width: u32,
    height: u32,
    encoding: &'static str,
    channels: u32,
}

const SIZES: [Size; 2] = [
    Size {
        label: "1 MiB (mono8 1024×1024)",
        topic: TOPIC_1M,
        width: 1024,
        height: 1024,
        encoding: "mono8",
        channels: 1,
    },
    Size {
        label: "6 MiB (rgb8 1920×1080)",
        topic: TOPIC_6M,
        width: 1920,
        height: 1080,
        encoding: "rgb8",
        channels: 3,
    },
];

impl Size {
    fn bytes(&self) -> usize {
        (self.width * self.height * self.channels) as usize
    }

    fn image(&self) -> Image {
        Image {
            header: Header {
                stamp: Time::default(),
                frame_id: String::new(),
            },
            height: self.height,
            width: self.width,
            encoding: self.encoding.to_owned(),
            is_bigendian: 0,
            step: self.width * self.channels,
            data: (0..self.bytes()).map(|i| (i % 251) as u8).collect(),
        }
    }
}

/// Reliable, keep all, volatile: nothing may be dropped for want of room.
fn topic_qos() -> Qos {
    Qos::default_profile().keep_all().reliable().volatile()
}

// ---------------------------------------------------------------------------------------------
// The child: server, publishers, UDP echo and sender; commands on stdin, answers on stdout.

struct ChildEndpoints {
    publishers: Vec<Publisher<Image>>,
    _server: ServiceServer<AddTwoInts>,
    _node: Node,
}

fn child_endpoints(variant: &Variant, backend: Backend) -> Result<ChildEndpoints, String> {
    let node = context(backend, variant.domain)?
        .create_node("bench_server", "/")
        .map_err(|e| format!("node: {e}"))?;
    let server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name(SERVICE)
        .on_request(|req| {
            Ok(AddTwoIntsResponse {
                sum: req.a.wrapping_add(req.b),
            })
        })
        .build()
        .map_err(|e| format!("server: {e}"))?;
    let publishers = SIZES
        .iter()
        .map(|s| {
            node.create_publisher::<Image>(s.topic, &topic_qos())
                .map_err(|e| format!("publisher: {e}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(ChildEndpoints {
        publishers,
        _server: server,
        _node: node,
    })
}

/// Publishes `count` messages tagged `tag`; each failed publish is retried (up to 100 times)
/// and counted.
fn publish(publisher: &Publisher<Image>, image: &Image, tag: &str, count: usize) -> usize {
    let mut errors = 0;
    for _ in 0..count {
        for _ in 0..100 {
            let mut message = image.clone();
            message.header.frame_id = tag.to_owned();
            match publisher.publish(message) {
                Ok(()) => break,
                Err(_) => errors += 1,
            }
        }
    }
    errors
}

/// Sends `count` messages of `size` bytes numbered from `first` to `to`, windowed by the
/// receiver's acknowledgements; returns how often an acknowledgement did not come in time.
fn udp_send(
    socket: &UdpSocket,
    to: SocketAddr,
    payload: &[u8],
    first: u32,
    count: u32,
) -> Result<usize, String> {
    socket.connect(to).map_err(|e| format!("connect: {e}"))?;
    socket
        .set_read_timeout(Some(UDP_ACK_WAIT))
        .map_err(|e| e.to_string())?;
    let window = (UDP_WINDOW / payload.len().max(1)).max(1) as u32;
    let fragments = payload.len().div_ceil(UDP_CHUNK) as u32;
    let mut datagram = vec![0u8; UDP_HEADER + UDP_CHUNK];
    let mut acked = first;
    let mut stalls = 0;
    let mut ack = [0u8; 16];
    for seq in first..first + count {
        while seq - acked >= window {
            match socket.recv(&mut ack) {
                Ok(4) => {
                    let n = u32::from_le_bytes([ack[0], ack[1], ack[2], ack[3]]);
                    acked = acked.max(n + 1);
                }
                Ok(_) => {}
                Err(_) => {
                    stalls += 1;
                    acked = seq;
                }
            }
        }
        for (index, chunk) in payload.chunks(UDP_CHUNK).enumerate() {
            datagram[..4].copy_from_slice(&seq.to_le_bytes());
            datagram[4..8].copy_from_slice(&(index as u32).to_le_bytes());
            datagram[8..12].copy_from_slice(&fragments.to_le_bytes());
            datagram[UDP_HEADER..UDP_HEADER + chunk.len()].copy_from_slice(chunk);
            socket
                .send(&datagram[..UDP_HEADER + chunk.len()])
                .map_err(|e| format!("send: {e}"))?;
        }
    }
    // Drain what is still due (the receiver's socket is left empty for the next round).
    while acked < first + count {
        match socket.recv(&mut ack) {
            Ok(4) => {
                let n = u32::from_le_bytes([ack[0], ack[1], ack[2], ack[3]]);
                acked = acked.max(n + 1);
            }
            Ok(_) => {}
            Err(_) => {
                stalls += 1;
                break;
            }
        }
    }
    Ok(stalls)
}

/// The child's command loop. Commands: `ping <size index>` (one message tagged `ping`),
/// `pub <size index> <tag> <count>`, `udp <port> <size index> <first> <count>`; each answered
/// by `sent <publish errors or late acknowledgements> <seconds spent sending>`. Ends when stdin
/// closes.
fn child(key: &str) -> Result<(), String> {
    let variant = VARIANTS
        .iter()
        .find(|v| v.key == key)
        .ok_or_else(|| format!("unknown variant {key}"))?;
    let images: Vec<Image> = SIZES.iter().map(Size::image).collect();
    let mut out = std::io::stdout().lock();
    let mut say = |line: String| -> Result<(), String> {
        writeln!(out, "{line}")
            .and_then(|()| out.flush())
            .map_err(|e| e.to_string())
    };
    let endpoints = match variant.backend() {
        Some(backend) => Some(child_endpoints(variant, backend)?),
        None => None,
    };
    // UDP: an echo socket (round trips) on a thread, a sender socket (throughput).
    let echo_port = if endpoints.is_none() {
        let echo = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
        let port = echo.local_addr().map_err(|e| e.to_string())?.port();
        thread::spawn(move || {
            let mut buf = [0u8; 64];
            while let Ok((n, from)) = echo.recv_from(&mut buf) {
                if echo.send_to(&buf[..n], from).is_err() {
                    break;
                }
            }
        });
        port
    } else {
        0
    };
    let sender = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    say(format!("ready {echo_port}"))?;
    for line in std::io::stdin().lock().lines() {
        let line = line.map_err(|e| e.to_string())?;
        let words: Vec<&str> = line.split_whitespace().collect();
        let number = |i: usize| -> Result<usize, String> {
            words
                .get(i)
                .and_then(|w| w.parse().ok())
                .ok_or_else(|| format!("bad command '{line}'"))
        };
        let answer = match words.first().copied() {
            Some("ping") | Some("pub") => {
                let endpoints = endpoints.as_ref().ok_or("no publishers for UDP")?;
                let size = number(1)?;
                let (publisher, image) = endpoints
                    .publishers
                    .get(size)
                    .zip(images.get(size))
                    .ok_or_else(|| format!("bad size in '{line}'"))?;
                let started = Instant::now();
                let errors = if words[0] == "ping" {
                    publish(publisher, image, "ping", 1)
                } else {
                    let tag = words
                        .get(2)
                        .ok_or_else(|| format!("bad command '{line}'"))?;
                    publish(publisher, image, tag, number(3)?)
                };
                format!("sent {errors} {}", started.elapsed().as_secs_f64())
            }
            Some("udp") => {
                let to = SocketAddr::from(([127, 0, 0, 1], number(1)? as u16));
                let image = images
                    .get(number(2)?)
                    .ok_or_else(|| format!("bad size in '{line}'"))?;
                let started = Instant::now();
                let stalls = udp_send(
                    &sender,
                    to,
                    &image.data,
                    number(3)? as u32,
                    number(4)? as u32,
                )?;
                format!("sent {stalls} {}", started.elapsed().as_secs_f64())
            }
            _ => return Err(format!("unknown command '{line}'")),
        };
        say(answer)?;
    }
    drop(endpoints);
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The measuring side.

fn context(backend: Backend, domain: u32) -> Result<Context, String> {
    Context::builder()
        .domain_id(domain)
        .backend(backend)
        .signal_handler(SignalHandlerOptions::None)
        .build()
        .map_err(|e| format!("context: {e}"))
}

/// The UDP receiver of one variant: reassembles messages, acknowledges each.
struct UdpReceiver {
    socket: UdpSocket,
    buf: Vec<u8>,
    message: Vec<u8>,
}

impl UdpReceiver {
    fn new() -> Result<Self, String> {
        use nix::sys::socket::{setsockopt, sockopt};
        let socket = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
        if setsockopt(&socket, sockopt::RcvBufForce, &UDP_RCVBUF).is_err() {
            setsockopt(&socket, sockopt::RcvBuf, &UDP_RCVBUF)
                .map_err(|e| format!("SO_RCVBUF: {e}"))?;
        }
        socket
            .set_read_timeout(Some(Duration::from_millis(100)))
            .map_err(|e| e.to_string())?;
        Ok(Self {
            socket,
            buf: vec![0u8; 65_536],
            message: Vec::new(),
        })
    }

    fn port(&self) -> u16 {
        self.socket.local_addr().map_or(0, |a| a.port())
    }

    /// Receives messages `first..first + count` of `bytes` bytes: (delivered, time of the last
    /// one delivered); ends early after [`IDLE_LIMIT`] without a datagram.
    fn receive(&mut self, first: u32, count: u32, bytes: usize) -> (usize, Option<Instant>) {
        self.message.resize(bytes, 0);
        let end = first + count;
        let (mut delivered, mut last) = (0, None);
        let (mut current, mut fragments_seen) = (u32::MAX, 0u32);
        let mut heard = Instant::now();
        loop {
            let (n, from) = match self.socket.recv_from(&mut self.buf) {
                Ok(r) => r,
                Err(_) if heard.elapsed() < IDLE_LIMIT => continue,
                Err(_) => return (delivered, last),
            };
            heard = Instant::now();
            if n < UDP_HEADER {
                continue;
            }
            let word = |i: usize| {
                u32::from_le_bytes([
                    self.buf[i],
                    self.buf[i + 1],
                    self.buf[i + 2],
                    self.buf[i + 3],
                ])
            };
            let (seq, index, fragments) = (word(0), word(4), word(8));
            if seq < first || seq >= end {
                continue;
            }
            if seq != current {
                if current != u32::MAX && current < seq {
                    // The last fragment of `current` was lost: acknowledge it as ended.
                    let _ = self.socket.send_to(&current.to_le_bytes(), from);
                }
                current = seq;
                fragments_seen = 0;
            }
            let at = index as usize * UDP_CHUNK;
            let len = n - UDP_HEADER;
            if let Some(place) = self.message.get_mut(at..at + len) {
                place.copy_from_slice(&self.buf[UDP_HEADER..n]);
                fragments_seen += 1;
            }
            if index + 1 == fragments {
                if fragments_seen == fragments {
                    delivered += 1;
                    last = Some(heard);
                }
                let _ = self.socket.send_to(&seq.to_le_bytes(), from);
                current = u32::MAX;
                if seq + 1 == end {
                    return (delivered, last);
                }
            }
        }
    }
}

/// One variant's measuring side and its child.
struct Running {
    child: Child,
    /// `None` once closed (the child ends).
    stdin: Option<ChildStdin>,
    stdout: BufReader<ChildStdout>,
    echo_port: u16,
    client: Option<ServiceClient<AddTwoInts>>,
    subscriptions: Vec<Subscription<Image>>,
    udp: Option<(UdpSocket, UdpReceiver)>,
    udp_seq: u32,
    _node: Option<Node>,
    _router: Option<zenoh::Session>,
}

impl Drop for Running {
    fn drop(&mut self) {
        // Closing its stdin ends the child (its command loop returns).
        drop(self.stdin.take());
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            match self.child.try_wait() {
                Ok(Some(_)) | Err(_) => break,
                Ok(None) if Instant::now() < deadline => {
                    thread::sleep(Duration::from_millis(20));
                }
                Ok(None) => {
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    break;
                }
            }
        }
    }
}

impl Running {
    /// Sends one command line to the child.
    fn send(&mut self, line: &str) -> Result<(), String> {
        let stdin = self.stdin.as_mut().ok_or("the child's stdin is closed")?;
        writeln!(stdin, "{line}")
            .and_then(|()| stdin.flush())
            .map_err(|e| format!("to the child: {e}"))
    }

    /// Sends one command line to the child and reads its answer.
    fn command(&mut self, line: &str) -> Result<String, String> {
        self.send(line)?;
        self.answer()
    }

    fn answer(&mut self) -> Result<String, String> {
        let mut answer = String::new();
        self.stdout
            .read_line(&mut answer)
            .map_err(|e| format!("from the child: {e}"))?;
        if answer.is_empty() {
            return Err("the child ended".to_owned());
        }
        Ok(answer.trim().to_owned())
    }

    fn start(variant: &Variant) -> Result<Self, String> {
        let router = if variant.is_zenoh() {
            let port = variant.router_port();
            let get = |k: &str| {
                (k == config::CONFIG_OVERRIDE_ENV)
                    .then(|| format!(r#"listen/endpoints=["tcp/127.0.0.1:{port}"]"#))
            };
            let router_config = config::config(ConfigKind::Router, get)
                .map_err(|e| format!("router configuration: {e}"))?;
            Some(
                zenoh::open(router_config)
                    .wait()
                    .map_err(|e| format!("router: {e}"))?,
            )
        } else {
            None
        };
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let mut command = Command::new(exe);
        command
            .env(CHILD_ENV, variant.key)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped());
        if variant.is_zenoh() {
            command.env(
                config::CONFIG_OVERRIDE_ENV,
                variant.zenoh_override(variant.child_port()),
            );
        }
        let mut child = command.spawn().map_err(|e| format!("child process: {e}"))?;
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            let _ = child.kill();
            let _ = child.wait();
            return Err("child without pipes".to_owned());
        };
        let mut running = Self {
            child,
            stdin: Some(stdin),
            stdout: BufReader::new(stdout),
            echo_port: 0,
            client: None,
            subscriptions: Vec::new(),
            udp: None,
            udp_seq: 0,
            _node: None,
            _router: router,
        };
        let ready = running.answer()?;
        running.echo_port = ready
            .strip_prefix("ready ")
            .and_then(|p| p.parse().ok())
            .ok_or_else(|| format!("the child said '{ready}'"))?;
        match variant.backend() {
            None => {
                let ping = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
                ping.connect(("127.0.0.1", running.echo_port))
                    .map_err(|e| e.to_string())?;
                ping.set_read_timeout(Some(CALL_TIMEOUT))
                    .map_err(|e| e.to_string())?;
                running.udp = Some((ping, UdpReceiver::new()?));
            }
            Some(backend) => {
                // The context reads ZENOH_CONFIG_OVERRIDE when it is built (through std::env,
                // which set_var locks against); set for this context only.
                if variant.is_zenoh() {
                    std::env::set_var(
                        config::CONFIG_OVERRIDE_ENV,
                        variant.zenoh_override(variant.parent_port()),
                    );
                }
                let node = context(backend, variant.domain).and_then(|c| {
                    c.create_node("bench_client", "/")
                        .map_err(|e| format!("node: {e}"))
                });
                std::env::remove_var(config::CONFIG_OVERRIDE_ENV);
                let node = node?;
                let client = ServiceClient::<AddTwoInts>::builder()
                    .node(&node)
                    .name(SERVICE)
                    .build()
                    .map_err(|e| format!("client: {e}"))?;
                running.subscriptions = SIZES
                    .iter()
                    .map(|s| {
                        node.create_subscription::<Image>(s.topic, &topic_qos())
                            .map_err(|e| format!("subscription: {e}"))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                if !client.wait_for_service(DISCOVERY_TIMEOUT) {
                    return Err(format!("no server within {DISCOVERY_TIMEOUT:?}"));
                }
                running.client = Some(client);
                running._node = Some(node);
            }
        }
        for i in 0..WARMUP_CALLS {
            running.call(i as i64)?;
        }
        for size in 0..SIZES.len() {
            running.discover(size)?;
            running.throughput(size, "warm", WARMUP_MSGS)?;
        }
        Ok(running)
    }

    /// Until a subscription gets its publisher's message: one `ping` message every 200 ms.
    fn discover(&mut self, size: usize) -> Result<(), String> {
        if self.udp.is_some() {
            return Ok(());
        }
        let deadline = Instant::now() + DISCOVERY_TIMEOUT;
        while Instant::now() < deadline {
            self.command(&format!("ping {size}"))?;
            let subscription = &mut self.subscriptions[size];
            let until = Instant::now() + Duration::from_millis(200);
            loop {
                let left = until.saturating_duration_since(Instant::now());
                while let Some(image) = subscription.try_take().map_err(|e| e.to_string())? {
                    if image.header.frame_id == "ping" {
                        return Ok(());
                    }
                }
                if left.is_zero() {
                    break;
                }
                subscription.wait(left);
            }
        }
        Err(format!(
            "no {} message within {DISCOVERY_TIMEOUT:?}",
            SIZES[size].label
        ))
    }

    fn call(&mut self, i: i64) -> Result<(), String> {
        if let Some((ping, _)) = &self.udp {
            let mut payload = [0u8; UDP_PING];
            payload[..4].copy_from_slice(&[0, 1, 0, 0]);
            payload[4..12].copy_from_slice(&i.to_le_bytes());
            ping.send(&payload).map_err(|e| format!("udp send: {e}"))?;
            let mut buf = [0u8; 64];
            let n = ping.recv(&mut buf).map_err(|e| format!("udp recv: {e}"))?;
            return (n == UDP_PING && buf[..n] == payload)
                .then_some(())
                .ok_or_else(|| "udp: wrong echo".to_owned());
        }
        let client = self.client.as_mut().ok_or("no client")?;
        let reply = client
            .call(AddTwoIntsRequest { a: i, b: 1 }, CALL_TIMEOUT)
            .map_err(|e| format!("call: {e}"))?;
        (reply.sum == i.wrapping_add(1))
            .then_some(())
            .ok_or_else(|| format!("wrong sum {}", reply.sum))
    }

    /// Reads the child's answer to a `pub` or `udp` command, reporting its errors (`what`) if
    /// there were any.
    fn sent(&mut self, what: &str) -> Result<(), String> {
        let answer = self.answer()?;
        match answer.split_whitespace().nth(1) {
            Some("0") => Ok(()),
            Some(errors) => {
                eprintln!("zenoh_transport: {what}: {errors}");
                Ok(())
            }
            None => Err(format!("the child answered '{answer}'")),
        }
    }

    /// One throughput round: `count` messages of `SIZES[size]`.
    fn throughput(&mut self, size: usize, tag: &str, count: usize) -> Result<Round, String> {
        let cpu_before = (
            cpu_seconds("self"),
            cpu_seconds(&self.child.id().to_string()),
        );
        let (delivered, secs) = self.transfer(size, tag, count)?;
        Ok(Round {
            delivered,
            secs,
            receiver_cpu: cpu_seconds("self") - cpu_before.0,
            sender_cpu: cpu_seconds(&self.child.id().to_string()) - cpu_before.1,
        })
    }

    /// `count` messages of `SIZES[size]`: (delivered, seconds to the last one delivered).
    fn transfer(&mut self, size: usize, tag: &str, count: usize) -> Result<(usize, f64), String> {
        let bytes = SIZES[size].bytes();
        if let Some((_, receiver)) = self.udp.as_mut() {
            let (port, first) = (receiver.port(), self.udp_seq);
            self.udp_seq += count as u32;
            self.send(&format!("udp {port} {size} {first} {count}"))?;
            let start = Instant::now();
            let Some((_, receiver)) = self.udp.as_mut() else {
                return Err("no UDP receiver".to_owned());
            };
            let (delivered, last) = receiver.receive(first, count as u32, bytes);
            self.sent("UDP sender: acknowledgements late")?;
            let secs = last.map_or(0.0, |l| l.duration_since(start).as_secs_f64());
            return Ok((delivered, secs));
        }
        self.send(&format!("pub {size} {tag} {count}"))?;
        let start = Instant::now();
        let subscription = &mut self.subscriptions[size];
        let (mut delivered, mut last) = (0, None);
        let mut heard = Instant::now();
        while delivered < count && heard.elapsed() < IDLE_LIMIT {
            match subscription.try_take().map_err(|e| e.to_string())? {
                Some(image) => {
                    heard = Instant::now();
                    if image.header.frame_id == tag && image.data.len() == bytes {
                        delivered += 1;
                        last = Some(heard);
                    }
                }
                None => {
                    subscription.wait(Duration::from_millis(100));
                }
            }
        }
        self.sent("publish errors (retried)")?;
        let secs = last.map_or(0.0, |l| l.duration_since(start).as_secs_f64());
        Ok((delivered, secs))
    }
}

// ---------------------------------------------------------------------------------------------
// Statistics and output.

fn micros(d: Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

fn times(value: f64, baseline: f64) -> String {
    if value > 0.0 && baseline > 0.0 {
        format!("{:.2}×", value / baseline)
    } else {
        "n/a".to_owned()
    }
}

/// Established TCP connections as (local port, remote port), from `/proc/net/tcp` and `tcp6`.
fn tcp_connections() -> Vec<(u16, u16)> {
    let mut found = Vec::new();
    for file in ["/proc/net/tcp", "/proc/net/tcp6"] {
        let Ok(table) = std::fs::read_to_string(file) else {
            continue;
        };
        for line in table.lines().skip(1) {
            let fields: Vec<&str> = line.split_whitespace().collect();
            let port = |f: Option<&&str>| {
                f.and_then(|a| a.rsplit(':').next())
                    .and_then(|p| u16::from_str_radix(p, 16).ok())
            };
            // State 01: ESTABLISHED.
            if fields.get(3) != Some(&"01") {
                continue;
            }
            if let (Some(local), Some(remote)) = (port(fields.get(1)), port(fields.get(2))) {
                found.push((local, remote));
            }
        }
    }
    found
}

/// The TCP links of a Zenoh variant: to the router, and between the two sessions (each counted
/// on its connecting side: the remote port is a listening one).
fn zenoh_links(variant: &Variant) -> (usize, usize) {
    let connections = tcp_connections();
    let to = |port: u16| connections.iter().filter(|(_, r)| *r == port).count();
    (
        to(variant.router_port()),
        to(variant.child_port()) + to(variant.parent_port()),
    )
}

/// How many distinct `/dev/shm` files (POSIX shared memory) process `pid` has mapped.
fn dev_shm_mappings(pid: u32) -> usize {
    let maps = std::fs::read_to_string(format!("/proc/{pid}/maps")).unwrap_or_default();
    maps.lines()
        .filter_map(|l| l.split_whitespace().nth(5))
        .filter(|path| path.starts_with("/dev/shm/"))
        .collect::<std::collections::BTreeSet<_>>()
        .len()
}

struct Rtt {
    samples: Vec<Duration>,
    failed: Option<String>,
}

impl Rtt {
    fn per_second(&self) -> f64 {
        let total: Duration = self.samples.iter().sum();
        self.samples.len() as f64 / total.as_secs_f64().max(1e-9)
    }
}

/// The in-process cost of one message of `size`, without any transport (what the publisher and
/// the subscriber pay at least): (clone + CDR encode, CDR decode) in ms, the median of 9.
fn cdr_cost(size: &Size) -> Result<(f64, f64), String> {
    use horus_ros_msgs::cdr::{from_cdr_body, to_cdr_body};
    let image = size.image();
    let (mut encode, mut decode) = (Vec::new(), Vec::new());
    for _ in 0..9 {
        let start = Instant::now();
        let body = to_cdr_body(&image.clone()).map_err(|e| e.to_string())?;
        encode.push(start.elapsed());
        let start = Instant::now();
        let back: Image =
            from_cdr_body::<Image, byteorder::LittleEndian>(&body).map_err(|e| e.to_string())?;
        decode.push(start.elapsed());
        if back.data.len() != image.data.len() {
            return Err("the decoded image differs".to_owned());
        }
    }
    encode.sort_unstable();
    decode.sort_unstable();
    Ok((encode[4].as_secs_f64() * 1e3, decode[4].as_secs_f64() * 1e3))
}

/// One throughput round of one variant.
struct Round {
    delivered: usize,
    /// From the command to the last message delivered.
    secs: f64,
    /// CPU seconds of the child (publisher, UDP sender) and of this process in the round.
    sender_cpu: f64,
    receiver_cpu: f64,
}

/// CPU seconds (user + system) of process `pid` (a number or `self`) so far, from
/// `/proc/<pid>/stat` in USER_HZ = 100 ticks per second (as on every Linux); 0 if unreadable.
fn cpu_seconds(pid: &str) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    // Fields after the command name (which may hold spaces) in parentheses: state is the 3rd
    // field, utime and stime the 14th and 15th.
    let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<u64>().ok())
            .unwrap_or(0)
    };
    (ticks(11) + ticks(12)) as f64 / 100.0
}

/// A variant's throughput figures for one message size, over the rounds.
#[derive(Default)]
struct Throughput {
    sent: usize,
    delivered: usize,
    secs: f64,
    /// CPU seconds of the child (publisher, UDP sender) and of this process (subscriber, UDP
    /// receiver, and the variant's router) over the rounds.
    sender_cpu: f64,
    receiver_cpu: f64,
    round_mib_s: Vec<f64>,
    failed: Option<String>,
}

fn main() {
    refuse_outside_namespace();
    // Before any thread starts (Cyclone DDS reads it when a context creates its domain).
    let cyclone_uri_set = std::env::var_os("CYCLONEDDS_URI").is_some();
    if !cyclone_uri_set {
        std::env::set_var("CYCLONEDDS_URI", CYCLONE_CONFIG);
    }
    if let Ok(key) = std::env::var(CHILD_ENV) {
        if let Err(e) = child(&key) {
            eprintln!("zenoh_transport child {key}: {e}");
            std::process::exit(1);
        }
        return;
    }
    thread::spawn(|| {
        thread::sleep(WATCHDOG);
        eprintln!("zenoh_transport: stalled for {WATCHDOG:?}; aborting");
        std::process::exit(3);
    });
    let calls = env_usize("HORUS_BENCH_ZT_CALLS", DEFAULT_CALLS);
    let rounds = env_usize("HORUS_BENCH_ZT_ROUNDS", DEFAULT_ROUNDS).min(calls);
    let per_round = calls / rounds;
    let counts = [
        env_usize("HORUS_BENCH_ZT_MSGS_1M", DEFAULT_MSGS_1M),
        env_usize("HORUS_BENCH_ZT_MSGS_6M", DEFAULT_MSGS_6M),
    ];
    let topic_rounds = env_usize("HORUS_BENCH_ZT_TOPIC_ROUNDS", DEFAULT_TOPIC_ROUNDS);
    let only = std::env::var("HORUS_BENCH_ZT_ONLY").unwrap_or_default();
    let wanted = |v: &str| only.is_empty() || only.split(',').any(|o| o.trim() == v);
    let cpus = thread::available_parallelism().map_or(0, |n| n.get());

    println!(
        "zenoh_transport: service round trips and image throughput, two processes per variant"
    );
    println!(
        "  CPUs: {cpus}; load average at start: {}; other processes may share these CPUs",
        loadavg()
    );
    println!(
        "  Cyclone DDS configuration: {}",
        if cyclone_uri_set {
            "CYCLONEDDS_URI from the environment"
        } else {
            "loopback, 4 MB receive buffer (CYCLONEDDS_URI was unset)"
        }
    );
    let setup_start = Instant::now();
    let mut running: Vec<(&Variant, Option<Running>, Option<String>)> = VARIANTS
        .iter()
        .map(|v| {
            if !wanted(v.key) {
                return (
                    v,
                    None,
                    Some("not asked for (HORUS_BENCH_ZT_ONLY)".to_owned()),
                );
            }
            if v.backend().is_some_and(|b| !b.is_available()) {
                return (v, None, Some("backend not built in".to_owned()));
            }
            match Running::start(v) {
                Ok(r) => (v, Some(r), None),
                Err(e) => {
                    println!("  {} could not be set up: {e}", v.name);
                    (v, None, Some(format!("setup failed: {e}")))
                }
            }
        })
        .collect();
    println!(
        "  setup (processes, discovery, warm-up of all variants): {:.2} s",
        setup_start.elapsed().as_secs_f64()
    );
    for (v, r, _) in &running {
        if v.is_zenoh() && r.is_some() {
            let (router, direct) = zenoh_links(v);
            println!(
                "  {}: TCP links to its router {router}, between the two sessions {direct}{}",
                v.name,
                if direct == 0 {
                    " (data goes through the router)"
                } else {
                    " (data goes peer to peer)"
                }
            );
        }
    }

    // Service round trips, interleaved rounds.
    let mut rtt: Vec<Rtt> = running
        .iter()
        .map(|(_, _, why)| Rtt {
            samples: Vec::new(),
            failed: why.clone(),
        })
        .collect();
    let run_start = Instant::now();
    for _ in 0..rounds {
        for ((_, r, _), stats) in running.iter_mut().zip(&mut rtt) {
            let Some(r) = r.as_mut() else { continue };
            if stats.failed.is_some() {
                continue;
            }
            for i in 0..per_round {
                let start = Instant::now();
                match r.call(i as i64) {
                    Ok(()) => stats.samples.push(start.elapsed()),
                    Err(e) => {
                        stats.failed = Some(format!("failed during the run: {e}"));
                        break;
                    }
                }
            }
        }
    }
    let rtt_time = run_start.elapsed();

    // Throughput, interleaved rounds per size.
    let mut tput: Vec<Vec<Throughput>> = SIZES
        .iter()
        .map(|_| {
            running
                .iter()
                .map(|(_, _, why)| Throughput {
                    failed: why.clone(),
                    ..Throughput::default()
                })
                .collect()
        })
        .collect();
    let tput_start = Instant::now();
    for (size, stats) in tput.iter_mut().enumerate() {
        for round in 0..topic_rounds {
            for ((_, r, _), s) in running.iter_mut().zip(stats.iter_mut()) {
                let Some(r) = r.as_mut() else { continue };
                if s.failed.is_some() {
                    continue;
                }
                let count = counts[size];
                match r.throughput(size, &format!("round{round}"), count) {
                    Ok(Round {
                        delivered,
                        secs,
                        sender_cpu,
                        receiver_cpu,
                    }) => {
                        s.sent += count;
                        s.sender_cpu += sender_cpu;
                        s.receiver_cpu += receiver_cpu;
                        s.delivered += delivered;
                        s.secs += secs;
                        let mib = (delivered * SIZES[size].bytes()) as f64 / f64::from(1 << 20);
                        s.round_mib_s.push(mib / secs.max(1e-9));
                    }
                    Err(e) => s.failed = Some(format!("failed during the run: {e}")),
                }
            }
        }
    }
    let tput_time = tput_start.elapsed();
    for (v, r, _) in &running {
        if let (true, Some(r)) = (v.is_zenoh(), r) {
            println!(
                "  {}: /dev/shm files mapped by its publisher/server process: {}",
                v.name,
                dev_shm_mappings(r.child.id())
            );
        }
    }
    println!(
        "  measured: round trips {:.2} s, throughput {:.2} s; load average at end: {}",
        rtt_time.as_secs_f64(),
        tput_time.as_secs_f64(),
        loadavg()
    );

    println!();
    println!(
        "service round trip (AddTwoInts; raw UDP: a 20-byte ping echoed), client and server in \
         two processes, {} sequential calls per variant in {rounds} interleaved rounds",
        per_round * rounds
    );
    println!(
        "  {:<28} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11}",
        "variant", "p50 µs", "p99 µs", "calls/s", "p50/UDP", "p99/UDP", "calls/s/UDP"
    );
    let summary = |s: &Rtt| {
        let mut sorted = s.samples.clone();
        sorted.sort_unstable();
        (
            micros(percentile(&sorted, 50.0)),
            micros(percentile(&sorted, 99.0)),
            s.per_second(),
        )
    };
    let udp_rtt = summary(&rtt[0]);
    for ((v, _, _), s) in running.iter().zip(&rtt) {
        if let Some(why) = &s.failed {
            println!("  {:<28} {:>9}   {why}", v.name, "n/a");
            continue;
        }
        let (p50, p99, rate) = summary(s);
        println!(
            "  {:<28} {p50:>9.1} {p99:>9.1} {rate:>9.0} {:>9} {:>9} {:>11}",
            v.name,
            times(p50, udp_rtt.0),
            times(p99, udp_rtt.1),
            times(rate, udp_rtt.2),
        );
    }
    for (size, stats) in tput.iter().enumerate() {
        println!();
        println!(
            "topic throughput, sensor_msgs/Image {} (RELIABLE KEEP_ALL VOLATILE; raw UDP: \
             datagrams of ≤ {UDP_CHUNK} bytes), publisher and subscriber in two processes, \
             {} messages back to back per round, {topic_rounds} interleaved rounds",
            SIZES[size].label, counts[size]
        );
        println!(
            "  {:<28} {:>9} {:>9} {:>9} {:>11} {:>10} {:>10}   MiB/s per round",
            "variant", "msgs/s", "MiB/s", "MiB/s/UDP", "delivered", "pub CPU", "sub CPU"
        );
        match cdr_cost(&SIZES[size]) {
            Ok((encode, decode)) => println!(
                "  in-process, no transport: clone + CDR encode {encode:.2} ms, CDR decode \
                 {decode:.2} ms per message (median of 9)"
            ),
            Err(e) => println!("  in-process CDR cost: {e}"),
        }
        let rate = |s: &Throughput| {
            let msgs = s.delivered as f64 / s.secs.max(1e-9);
            (msgs, msgs * SIZES[size].bytes() as f64 / f64::from(1 << 20))
        };
        let udp = rate(&stats[0]);
        for ((v, _, _), s) in running.iter().zip(stats) {
            if let Some(why) = &s.failed {
                println!("  {:<28} {:>9}   {why}", v.name, "n/a");
                continue;
            }
            let (msgs, mib) = rate(s);
            let rounds: Vec<String> = s.round_mib_s.iter().map(|r| format!("{r:.0}")).collect();
            let per_message = |cpu: f64| format!("{:.2} ms", cpu * 1e3 / s.delivered.max(1) as f64);
            println!(
                "  {:<28} {msgs:>9.1} {mib:>9.1} {:>9} {:>11} {:>10} {:>10}   {}",
                v.name,
                times(mib, udp.1),
                format!("{}/{}", s.delivered, s.sent),
                per_message(s.sender_cpu),
                per_message(s.receiver_cpu),
                rounds.join(" ")
            );
        }
    }
    // Children end as their stdin closes; routers after them.
    for (_, r, _) in running.iter_mut().rev() {
        drop(r.take());
    }
}
