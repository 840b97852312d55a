//! An eProsima Fast DDS 2.9 peer (the DDS under `rmw_fastrtps_cpp`, Jazzy's default RMW):
//! `peers/fastdds/ros_participant.cpp` (an AddTwoInts server and client, or a demo_nodes talker or
//! listener), built with the system C++ compiler against Debian's
//! `libfastrtps-dev` / `libfastcdr-dev` (`scripts/setup` installs them) the first time a test
//! needs it, into `<target dir>/interop-peers/`, and rebuilt only when a source is newer than the
//! binary. Building needs no network, so it also works inside `scripts/isolated`.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::OnceLock;
use std::time::{Duration, Instant, SystemTime};

use serde_json::Value;

/// How long building the peer may take before it is abandoned.
const BUILD_LIMIT: Duration = Duration::from_secs(180);

/// The directory holding the peer's C++ sources.
pub fn source_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("peers")
        .join("fastdds")
}

/// The workspace's target directory: `CARGO_TARGET_DIR` if set, else the directory three levels
/// above the running test binary (`<target>/<profile>/deps/<test>`), else `<workspace>/target`.
pub fn target_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("CARGO_TARGET_DIR") {
        return PathBuf::from(dir);
    }
    std::env::current_exe()
        .ok()
        .and_then(|exe| {
            let deps = exe.parent()?;
            (deps.file_name()? == "deps").then(|| deps.parent()?.parent().map(Path::to_path_buf))?
        })
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"))
}

/// The path of the built peer (`ros_participant`), building it first if it is missing or older
/// than one of its sources. Built at most once per process; concurrent test processes each
/// build into a private file and rename it into place.
pub fn peer_binary() -> Result<PathBuf, String> {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    BUILT.get_or_init(build).clone()
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

fn build() -> Result<PathBuf, String> {
    let out_dir = target_dir().join("interop-peers");
    let binary = out_dir.join("fastdds_ros_participant");
    let sources: Vec<PathBuf> = std::fs::read_dir(source_dir())
        .map_err(|e| format!("reading {}: {e}", source_dir().display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "cpp" || x == "hpp"))
        .collect();
    let newest_source = sources.iter().filter_map(|p| modified(p)).max();
    if let (Some(built), Some(source)) = (modified(&binary), newest_source) {
        if built >= source {
            return Ok(binary);
        }
    }
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("creating {}: {e}", out_dir.display()))?;
    let partial = out_dir.join(format!(
        "fastdds_ros_participant.{}.partial",
        std::process::id()
    ));
    let compiler = std::env::var_os("CXX").unwrap_or_else(|| "g++".into());
    let mut command = Command::new(&compiler);
    command
        .args(["-std=c++17", "-O1", "-Wall", "-Wextra", "-o"])
        .arg(&partial)
        .args(
            sources
                .iter()
                .filter(|p| p.extension().is_some_and(|x| x == "cpp")),
        )
        .args(["-lfastrtps", "-lfastcdr", "-lpthread"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = command.spawn().map_err(|e| {
        format!(
            "starting {compiler:?} to build the Fast DDS peer: {e} (scripts/setup installs g++, \
             libfastrtps-dev and libfastcdr-dev)"
        )
    })?;
    // Its output is read while it compiles (a long error report must not fill a pipe).
    let output = horus_ros_test_support::wait_with_output(&mut child, BUILD_LIMIT)
        .map_err(|e| format!("waiting for the compiler: {e}"))?;
    let Some(status) = output.status else {
        let _ = std::fs::remove_file(&partial);
        return Err(format!(
            "building the Fast DDS peer took over {BUILD_LIMIT:?}"
        ));
    };
    if !status.success() {
        let _ = std::fs::remove_file(&partial);
        return Err(format!(
            "building the Fast DDS peer failed ({status}): {}{} (scripts/setup installs \
             libfastrtps-dev and libfastcdr-dev)",
            output.stdout, output.stderr
        ));
    }
    std::fs::rename(&partial, &binary)
        .map_err(|e| format!("moving the peer to {}: {e}", binary.display()))?;
    Ok(binary)
}

/// What the peer announced it created (its first stdout line): GIDs in dotted hex.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Created {
    /// The participant's GID.
    pub participant: String,
    /// Its RTPS vendor id as 4 hex digits (`010f`).
    pub vendor: String,
    /// The DDS request topic (`rq/…Request`).
    pub request_topic: String,
    /// The DDS reply topic (`rr/…Reply`).
    pub reply_topic: String,
    /// The service server's request reader (empty when calling: the peer has no server then).
    pub server_request_reader: String,
    /// The service server's reply writer (empty when calling).
    pub server_reply_writer: String,
    /// The client's request writer.
    pub client_request_writer: String,
    /// The client's reply reader.
    pub client_reply_reader: String,
    /// The whole line, parsed (including `qos`, as Fast DDS reports its own endpoints' QoS).
    pub json: Value,
}

impl Created {
    fn parse(line: &str) -> Result<Self, String> {
        let json: Value =
            serde_json::from_str(line.trim()).map_err(|e| format!("{e} in {line:?}"))?;
        let field = |path: &[&str]| -> Result<String, String> {
            let mut v = &json;
            for key in path {
                v = &v[*key];
            }
            v.as_str()
                .map(str::to_owned)
                .ok_or_else(|| format!("no string at {path:?} in {line:?}"))
        };
        let has_server = !json["server"].is_null();
        let server_field = |key: &str| -> Result<String, String> {
            if has_server {
                field(&["server", key])
            } else {
                Ok(String::new())
            }
        };
        Ok(Self {
            participant: field(&["participant"])?,
            vendor: field(&["vendor"])?,
            request_topic: field(&["request_topic"])?,
            reply_topic: field(&["reply_topic"])?,
            server_request_reader: server_field("request_reader")?,
            server_reply_writer: server_field("reply_writer")?,
            client_request_writer: field(&["client", "request_writer"])?,
            client_reply_reader: field(&["client", "reply_reader"])?,
            json,
        })
    }
}

/// A request the serving peer took, as it printed it (`{"served": {...}}`): the request id is
/// what rmw_fastrtps `__rmw_take_request` computes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Served {
    /// The request's `a`.
    pub a: i64,
    /// The request's `b`.
    pub b: i64,
    /// The sum it answered.
    pub sum: i64,
    /// The request id's GUID: the related_sample_identity GUID when given, else the request
    /// writer's (dotted hex).
    pub request_id_guid: String,
    /// The request id's sequence number: the request sample's.
    pub request_id_sequence_number: i64,
    /// The request sample's writer (dotted hex).
    pub sample_writer: String,
    /// The related_sample_identity GUID the request carried (all zeros when none).
    pub related_guid: String,
    /// `YES` (its reply writer matched the client's reply reader in time), `MAYBE` (not in time:
    /// no reply sent, as rmw_fastrtps), or `UNCHECKED` (the id's GUID is not a reader's).
    pub client_present: String,
    /// Whether the reply was written.
    pub sent: bool,
}

impl Served {
    /// Parses a `{"served": {...}}` line; `None` for any other line.
    pub fn parse(line: &str) -> Option<Self> {
        let json: Value = serde_json::from_str(line.trim()).ok()?;
        let s = json.get("served")?;
        let string = |v: &Value| v.as_str().map(str::to_owned);
        Some(Self {
            a: s["a"].as_i64()?,
            b: s["b"].as_i64()?,
            sum: s["sum"].as_i64()?,
            request_id_guid: string(&s["request_id"]["writer_guid"])?,
            request_id_sequence_number: s["request_id"]["sequence_number"].as_i64()?,
            sample_writer: string(&s["sample_identity"]["writer_guid"])?,
            related_guid: string(&s["related_sample_identity"]["writer_guid"])?,
            client_present: string(&s["client_present"])?,
            sent: s["sent"].as_bool()?,
        })
    }
}

/// What a chatter peer (talker or listener) announced it created (its first stdout line).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChatterCreated {
    /// The participant's GID (dotted hex).
    pub participant: String,
    /// Its RTPS vendor id as 4 hex digits (`010f`).
    pub vendor: String,
    /// `talk` or `listen`.
    pub mode: String,
    /// The DDS topic (`rt/chatter`).
    pub topic: String,
    /// The DDS type name (`std_msgs::msg::dds_::String_`).
    pub type_name: String,
    /// The talker's writer or the listener's reader (dotted hex).
    pub endpoint: String,
    /// The whole line, parsed (including `qos`, as Fast DDS reports its endpoint's QoS).
    pub json: Value,
}

impl ChatterCreated {
    fn parse(line: &str) -> Result<Self, String> {
        let json: Value =
            serde_json::from_str(line.trim()).map_err(|e| format!("{e} in {line:?}"))?;
        let field = |key: &str| -> Result<String, String> {
            json[key]
                .as_str()
                .map(str::to_owned)
                .ok_or_else(|| format!("no string at {key:?} in {line:?}"))
        };
        let mode = field("mode")?;
        Ok(Self {
            participant: field("participant")?,
            vendor: field("vendor")?,
            topic: field("topic")?,
            type_name: field("type")?,
            endpoint: field(if mode == "talk" { "writer" } else { "reader" })?,
            mode,
            json,
        })
    }
}

/// A message the listening peer took, as it printed it (`{"heard": ..., "writer": ...}`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Heard {
    /// The message's `data`.
    pub data: String,
    /// The writer it came from (dotted hex GID).
    pub writer: String,
}

impl Heard {
    /// Parses a `{"heard": ...}` line; `None` for any other line.
    pub fn parse(line: &str) -> Option<Self> {
        let json: Value = serde_json::from_str(line.trim()).ok()?;
        Some(Self {
            data: json.get("heard")?.as_str()?.to_owned(),
            writer: json.get("writer")?.as_str()?.to_owned(),
        })
    }
}

/// The message a talking peer published, from its `{"published": ...}` line; `None` for any
/// other line.
pub fn published(line: &str) -> Option<String> {
    let json: Value = serde_json::from_str(line.trim()).ok()?;
    Some(json.get("published")?.as_str()?.to_owned())
}

/// A running Fast DDS peer; killed when dropped.
#[derive(Debug)]
pub struct FastDdsPeer {
    child: Child,
    lines: Receiver<String>,
    /// Every stdout line received so far, for failure messages.
    seen: Vec<String>,
}

impl FastDdsPeer {
    /// Builds the peer if needed and starts it: a ROS 2 participant in `domain` with node
    /// `namespace`/`node` owning an AddTwoInts server and client for `service` (fully
    /// qualified), staying up `linger` seconds. Its server answers as rmw_fastrtps does and
    /// prints a [`Served`] line per request (read them with [`next_line`](Self::next_line)). Its
    /// stderr goes to ours.
    pub fn start(
        domain: u32,
        namespace: &str,
        node: &str,
        service: &str,
        linger: Duration,
    ) -> Result<Self, String> {
        Self::spawn(domain, namespace, node, service, linger, None, None)
    }

    /// Starts the peer as demo_nodes_cpp's talker on rmw_fastrtps_cpp: node
    /// `namespace`/`node` with a `std_msgs/msg/String` writer on `topic` (fully qualified, e.g.
    /// `/chatter`; DDS topic `rt/chatter`) with rclcpp's default QoS, publishing
    /// `Hello World: <n>` every 50 ms until `count` were published (0: no limit), `linger` is
    /// over or [`leave`](Self::leave). It prints `{"published": ...}` per message.
    pub fn start_talker(
        domain: u32,
        namespace: &str,
        node: &str,
        topic: &str,
        linger: Duration,
        count: u32,
    ) -> Result<Self, String> {
        Self::spawn(
            domain,
            namespace,
            node,
            topic,
            linger,
            Some(("talk", count)),
            None,
        )
    }

    /// Starts the peer as demo_nodes_cpp's listener on rmw_fastrtps_cpp: node
    /// `namespace`/`node` with a `std_msgs/msg/String` reader on `topic` with rclcpp's default
    /// QoS, printing a [`Heard`] line per message (read them with
    /// [`next_heard`](Self::next_heard)) until it heard `count` (0: no limit), `linger` is over
    /// or [`leave`](Self::leave). It exits 0 iff it heard `count`.
    pub fn start_listener(
        domain: u32,
        namespace: &str,
        node: &str,
        topic: &str,
        linger: Duration,
        count: u32,
    ) -> Result<Self, String> {
        Self::spawn(
            domain,
            namespace,
            node,
            topic,
            linger,
            Some(("listen", count)),
            None,
        )
    }

    /// Like [`start`](Self::start), with the peer's `ros_discovery_info` writer sending its
    /// periodic heartbeat only every `period` (Fast DDS' default: 3 s): a reader that misses
    /// the heartbeat the writer sends when it matches it then waits that long for the sample.
    pub fn start_with_info_heartbeat(
        domain: u32,
        namespace: &str,
        node: &str,
        service: &str,
        linger: Duration,
        period: Duration,
    ) -> Result<Self, String> {
        Self::spawn(domain, namespace, node, service, linger, None, Some(period))
    }

    /// Like [`start`](Self::start), but calling: the peer's node has only an AddTwoInts client
    /// of `service`, which waits for a server as rmw_fastrtps does, then makes `count` calls one
    /// after the other (a = i, b = 10 i for i = 1..=count), printing a line per reply and a
    /// summary, all within `limit`. It exits 0 iff every reply came with the right sum.
    pub fn start_calling(
        domain: u32,
        namespace: &str,
        node: &str,
        service: &str,
        limit: Duration,
        count: u32,
    ) -> Result<Self, String> {
        Self::spawn(
            domain,
            namespace,
            node,
            service,
            limit,
            Some(("call", count)),
            None,
        )
    }

    fn spawn(
        domain: u32,
        namespace: &str,
        node: &str,
        service: &str,
        linger: Duration,
        mode: Option<(&str, u32)>,
        info_heartbeat: Option<Duration>,
    ) -> Result<Self, String> {
        let binary = peer_binary()?;
        let mut args = vec![
            domain.to_string(),
            namespace.to_owned(),
            node.to_owned(),
            service.to_owned(),
            format!("{:.3}", linger.as_secs_f64()),
        ];
        if let Some((mode, count)) = mode {
            args.extend([mode.to_owned(), count.to_string()]);
        }
        let mut command = Command::new(&binary);
        if let Some(period) = info_heartbeat {
            command.env(
                "PEER_INFO_HEARTBEAT_PERIOD_S",
                period.as_secs().max(1).to_string(),
            );
        }
        let mut child = command
            .args(&args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| format!("starting {}: {e}", binary.display()))?;
        let stdout = child.stdout.take().ok_or("no piped stdout")?;
        Ok(Self {
            child,
            lines: crate::line_reader(stdout),
            seen: Vec::new(),
        })
    }

    /// Asks the peer to leave now (SIGTERM), as it does when LINGER is over: its node is
    /// withdrawn from `ros_discovery_info`, then its endpoints and participant are deleted.
    pub fn leave(&self) -> Result<(), String> {
        let status = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .map_err(|e| format!("running kill: {e}"))?;
        if status.success() {
            Ok(())
        } else {
            Err(format!("kill -TERM {} failed: {status}", self.child.id()))
        }
    }

    /// The peer's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// Waits at most `limit` for the line the peer prints once everything is created.
    pub fn created(&mut self, limit: Duration) -> Result<Created, String> {
        Created::parse(&self.first_line(limit)?)
    }

    /// Waits at most `limit` for the line a talker or listener peer prints once its node and
    /// endpoint are created.
    pub fn chatter_created(&mut self, limit: Duration) -> Result<ChatterCreated, String> {
        ChatterCreated::parse(&self.first_line(limit)?)
    }

    /// The next message a listener peer heard, waiting at most `limit` in all; `None` past that
    /// or once it has exited and everything it printed was read. Other lines are skipped.
    pub fn next_heard(&mut self, limit: Duration) -> Option<Heard> {
        let deadline = Instant::now() + limit;
        loop {
            let line = self.next_line(deadline.saturating_duration_since(Instant::now()))?;
            if let Some(heard) = Heard::parse(&line) {
                return Some(heard);
            }
        }
    }

    fn first_line(&mut self, limit: Duration) -> Result<String, String> {
        match self.lines.recv_timeout(limit) {
            Ok(line) => {
                self.seen.push(line.clone());
                Ok(line)
            }
            Err(RecvTimeoutError::Timeout) => Err(format!(
                "the Fast DDS peer printed nothing within {limit:?}"
            )),
            Err(RecvTimeoutError::Disconnected) => Err(format!(
                "the Fast DDS peer exited before printing what it created: {:?}",
                self.child.try_wait()
            )),
        }
    }

    /// The next line the peer prints, waiting at most `limit`; `None` past that or once it has
    /// exited and everything it printed was read.
    pub fn next_line(&mut self, limit: Duration) -> Option<String> {
        let line = self.lines.recv_timeout(limit).ok()?;
        self.seen.push(line.clone());
        Some(line)
    }

    /// Every stdout line read so far (through [`created`](Self::created),
    /// [`next_line`](Self::next_line) or [`finish`](Self::finish)), one per line.
    pub fn output(&self) -> String {
        self.seen.join("\n")
    }

    /// Waits at most `limit` for the peer to exit (killing it past that), then reads the rest
    /// of its output. Returns its exit code (`None` if killed or died of a signal) and every
    /// stdout line it printed not yet read.
    pub fn finish(&mut self, limit: Duration) -> std::io::Result<(Option<i32>, Vec<String>)> {
        let code = self.wait_exit(limit)?;
        let mut rest = Vec::new();
        // The reader thread ends at EOF, shortly after the exit.
        while let Ok(line) = self.lines.recv_timeout(Duration::from_secs(2)) {
            self.seen.push(line.clone());
            rest.push(line);
        }
        Ok((code, rest))
    }

    fn wait_exit(&mut self, limit: Duration) -> std::io::Result<Option<i32>> {
        let status = horus_ros_test_support::wait_exit(&mut self.child, limit)?;
        Ok(status.and_then(|s| s.code()))
    }

    /// Waits at most `limit` for the peer to exit; kills it past that. Returns its exit code
    /// (`None` if it had to be killed or died of a signal).
    pub fn wait(mut self, limit: Duration) -> std::io::Result<Option<i32>> {
        self.wait_exit(limit)
    }
}

impl Drop for FastDdsPeer {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}
