//! An eProsima Fast DDS 2.9 peer (the DDS under `rmw_fastrtps_cpp`, Jazzy's default RMW):
//! `peers/fastdds/ros_participant.cpp`, built with the system C++ compiler against Debian's
//! `libfastrtps-dev` / `libfastcdr-dev` (`scripts/setup` installs them) the first time a test
//! needs it, into `<target dir>/interop-peers/`, and rebuilt only when a source is newer than the
//! binary. Building needs no network, so it also works inside `scripts/isolated`.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
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
    let deadline = Instant::now() + BUILD_LIMIT;
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if Instant::now() >= deadline => {
                let _ = child.kill();
                let _ = child.wait();
                let _ = std::fs::remove_file(&partial);
                return Err(format!(
                    "building the Fast DDS peer took over {BUILD_LIMIT:?}"
                ));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => return Err(format!("waiting for the compiler: {e}")),
        }
    }
    let output = child
        .wait_with_output()
        .map_err(|e| format!("reading the compiler's output: {e}"))?;
    if !output.status.success() {
        let _ = std::fs::remove_file(&partial);
        return Err(format!(
            "building the Fast DDS peer failed ({}): {}{} (scripts/setup installs \
             libfastrtps-dev and libfastcdr-dev)",
            output.status,
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
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
    /// The service server's request reader.
    pub server_request_reader: String,
    /// The service server's reply writer.
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
        Ok(Self {
            participant: field(&["participant"])?,
            vendor: field(&["vendor"])?,
            request_topic: field(&["request_topic"])?,
            reply_topic: field(&["reply_topic"])?,
            server_request_reader: field(&["server", "request_reader"])?,
            server_reply_writer: field(&["server", "reply_writer"])?,
            client_request_writer: field(&["client", "request_writer"])?,
            client_reply_reader: field(&["client", "reply_reader"])?,
            json,
        })
    }
}

/// A running Fast DDS peer; killed when dropped.
#[derive(Debug)]
pub struct FastDdsPeer {
    child: Child,
    lines: Receiver<String>,
}

impl FastDdsPeer {
    /// Builds the peer if needed and starts it: a ROS 2 participant in `domain` with node
    /// `namespace`/`node` owning an AddTwoInts server and client for `service` (fully
    /// qualified), staying up `linger` seconds. Its stderr goes to ours.
    pub fn start(
        domain: u32,
        namespace: &str,
        node: &str,
        service: &str,
        linger: Duration,
    ) -> Result<Self, String> {
        let binary = peer_binary()?;
        let mut child = Command::new(&binary)
            .args([
                domain.to_string().as_str(),
                namespace,
                node,
                service,
                &format!("{:.3}", linger.as_secs_f64()),
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| format!("starting {}: {e}", binary.display()))?;
        let stdout = child.stdout.take().ok_or("no piped stdout")?;
        Ok(Self {
            child,
            lines: spawn_line_reader(stdout),
        })
    }

    /// The peer's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// Waits at most `limit` for the line the peer prints once everything is created.
    pub fn created(&mut self, limit: Duration) -> Result<Created, String> {
        match self.lines.recv_timeout(limit) {
            Ok(line) => Created::parse(&line),
            Err(RecvTimeoutError::Timeout) => Err(format!(
                "the Fast DDS peer printed nothing within {limit:?}"
            )),
            Err(RecvTimeoutError::Disconnected) => Err(format!(
                "the Fast DDS peer exited before printing what it created: {:?}",
                self.child.try_wait()
            )),
        }
    }

    /// Waits at most `limit` for the peer to exit; kills it past that. Returns its exit code
    /// (`None` if it had to be killed or died of a signal).
    pub fn wait(mut self, limit: Duration) -> std::io::Result<Option<i32>> {
        let deadline = Instant::now() + limit;
        loop {
            if let Some(status) = self.child.try_wait()? {
                return Ok(status.code());
            }
            if Instant::now() >= deadline {
                self.child.kill()?;
                self.child.wait()?;
                return Ok(None);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

fn spawn_line_reader(stdout: ChildStdout) -> Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

impl Drop for FastDdsPeer {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}
