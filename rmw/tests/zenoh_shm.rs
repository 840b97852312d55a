//! Same-host shared memory on the zenoh backend, between two processes: a 1920×1080 rgb8
//! `sensor_msgs/Image` (6,220,800 bytes of pixels) published by one process reaches a
//! subscription of another, joined through a router started by the test, intact, and
//!
//! - with `transport/shared_memory/enabled=true` on both processes and the router, through
//!   shared memory (the subscription's [`RawReader::shared_memory_samples`] counts it);
//! - with shared memory off (the default, as rmw_zenoh's), not through it;
//! - with shared memory on but a pool too small for the image (`ZENOH_SHM_ALLOC_SIZE`), on the
//!   heap (the publisher falls back, as rmw_zenoh's does);
//! - between processes that reach each other only through the router: through shared memory
//!   if the router enabled it too, as bytes if it did not (zenoh negotiates it per link);
//! - with loans ([`LOANS_ENV`]): the publisher fills a buffer its writer lent from the pool
//!   and the subscription reads the image where it lies in that buffer (no copy on either
//!   side: `RawWriter::loan`, `RawReader::take_loan`).
//!
//! Zenoh's own transport optimization (which copies large heap messages into a pool of its
//! own) is turned off in these processes, so that only the publisher's shared-memory buffer can
//! bring the image through shared memory.
//!
//! The test re-runs its own binary for each process: the `child` test does nothing unless
//! [`ROLE_ENV`] names a role. The subscriber prints `ready` once its subscription is declared,
//! then what it received; the publisher waits for the match, publishes once, and stays until
//! its standard input closes (the image's buffer lives in its pool). Run inside
//! `scripts/isolated`.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

use horus_ros_msgs::sensor_msgs::msg::Image;
use horus_ros_msgs::std_msgs::msg::Header;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::zenoh::shm::{SHM_ALLOC_SIZE_ENV, SHM_ENABLED_KEY};
use horus_ros_rmw::{
    Backend, Context, DiscoveryEvent, LoanedSample, RawEndpointSpec, SignalHandlerOptions,
};
use zenoh::Wait;

/// The variable that makes the `child` test a subscriber or publisher:
/// `subscriber:<domain>` or `publisher:<domain>`.
const ROLE_ENV: &str = "HORUS_ROS_SHM_TEST_ROLE";
/// Set (to anything) in both processes: the publisher writes a loan and the subscriber takes
/// one.
const LOANS_ENV: &str = "HORUS_ROS_SHM_TEST_LOANS";
/// CDR little-endian encapsulation, before a body that is decoded.
const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];
/// What marks a child's lines for the test (libtest prints its own lines too).
const MARK: &str = "shm-test:";
/// How long discovery and the image may take (a debug build encodes 6 MB byte by byte).
const LIMIT: Duration = Duration::from_secs(60);

/// `transport/shared_memory/enabled=true`, without zenoh's implicit transport optimization.
fn shm_on() -> String {
    format!("{SHM_ENABLED_KEY}=true;transport/shared_memory/transport_optimization/enabled=false")
}

/// The 1920×1080 rgb8 image, its pixels a pattern that a shifted or truncated copy breaks.
fn image() -> Image {
    let (width, height) = (1920u32, 1080u32);
    let len = (width * height * 3) as usize;
    Image {
        header: Header {
            frame_id: "camera".to_owned(),
            ..Default::default()
        },
        height,
        width,
        encoding: "rgb8".to_owned(),
        is_bigendian: 0,
        step: width * 3,
        data: (0..len).map(|i| (i % 251) as u8).collect(),
    }
}

/// The image topic's endpoints: RELIABLE KEEP_ALL, whose Zenoh publisher blocks rather than
/// drops when its link is congested (rmw_zenoh's congestion control): the image sent as bytes
/// is ~95 batches, which a KEEP_LAST publisher (DROP) may lose.
fn image_spec() -> RawEndpointSpec {
    RawEndpointSpec {
        dds_topic_name: "rt/camera/image_raw".to_owned(),
        dds_type_name: Image::dds_type_name(),
        type_hash: Image::type_hash(),
        qos: Qos::default_profile().keep_all(),
        service_id: None,
    }
}

fn context(domain: u32) -> Context {
    Context::builder()
        .backend(Backend::Zenoh)
        .domain_id(domain)
        .signal_handler(SignalHandlerOptions::None)
        .arguments(Default::default())
        .build()
        .expect("a zenoh context")
}

/// Prints one line for the test process.
fn report(line: &str) {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{MARK} {line}").expect("stdout");
    out.flush().expect("stdout");
}

/// The subscriber process: declares its subscription, says `ready`, then reports the first
/// image it takes (waited for, at most [`LIMIT`]): whether it is intact and how many samples
/// came through shared memory.
fn subscriber(domain: u32) {
    let context = context(domain);
    let node = context.create_node("shm_listener", "/").expect("node");
    let mut reader = node.create_raw_reader(&image_spec()).expect("reader");
    report("ready");
    let loans = std::env::var_os(LOANS_ENV).is_some();
    let deadline = Instant::now() + LIMIT;
    let sample = loop {
        let taken = if loans {
            reader.take_loan().expect("take a loan")
        } else {
            reader.take().expect("take").map(LoanedSample::from)
        };
        if let Some(sample) = taken {
            break sample;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "no image within {LIMIT:?}");
        reader.wait(left);
    };
    assert!(!sample.big_endian, "horus-ros writes CDR_LE");
    let mut payload = CDR_LE_HEADER.to_vec();
    payload.extend_from_slice(&sample);
    let received: Image = horus_ros_msgs::cdr::from_cdr(&payload).expect("an Image");
    let intact = received == image();
    let lent = if loans {
        format!(" lent={}", sample.is_lent())
    } else {
        String::new()
    };
    report(&format!(
        "received intact={intact} len={} shm={}{lent}",
        sample.len(),
        reader.shared_memory_samples()
    ));
}

/// The publisher process: waits until its writer is matched with the subscription, publishes
/// the image once, then stays until its standard input closes.
fn publisher(domain: u32) {
    let context = context(domain);
    let mut feed = context.discovery_feed().expect("feed");
    let node = context.create_node("shm_talker", "/").expect("node");
    let writer = node.create_raw_writer(&image_spec()).expect("writer");
    let deadline = Instant::now() + LIMIT;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "no subscription within {LIMIT:?}");
        if let Some(DiscoveryEvent::Matched { local, .. }) = feed.next_timeout(left) {
            if local == writer.gid() {
                break;
            }
        }
    }
    let body = horus_ros_msgs::cdr::to_cdr_body(&image()).expect("encode");
    if std::env::var_os(LOANS_ENV).is_some() {
        let mut loan = writer.loan(body.len());
        let lent = loan.is_backend_buffer();
        loan.copy_from_slice(&body);
        writer.write_loan(loan, None, None).expect("publish a loan");
        report(&format!("published loaned={lent}"));
    } else {
        writer.write(body, None, None).expect("publish");
        report("published");
    }
    let _ = std::io::stdin().read_to_end(&mut Vec::new());
}

/// Runs as a subscriber or publisher when [`ROLE_ENV`] says so; nothing otherwise.
#[test]
fn child() {
    let Ok(role) = std::env::var(ROLE_ENV) else {
        return;
    };
    let (role, domain) = role.split_once(':').expect("role:domain");
    let domain: u32 = domain.parse().expect("domain");
    match role {
        "subscriber" => subscriber(domain),
        "publisher" => publisher(domain),
        other => panic!("unknown role {other}"),
    }
}

/// This test binary, run as `role` with the zenoh environment `overrides` (joined to the
/// router at `port`) and the extra variables `env`.
fn spawn(role: &str, domain: u32, port: u16, overrides: &str, env: &[(&str, &str)]) -> Child {
    let mut command = Command::new(std::env::current_exe().expect("this test binary"));
    command
        .args(["child", "--exact", "--nocapture", "--test-threads=1"])
        .env(ROLE_ENV, format!("{role}:{domain}"))
        .env(
            config::CONFIG_OVERRIDE_ENV,
            format!(
                r#"connect/endpoints=["tcp/127.0.0.1:{port}"];listen/endpoints=["tcp/127.0.0.1:0"];{overrides}"#
            ),
        )
        .env_remove(config::SESSION_CONFIG_URI_ENV)
        .env_remove(SHM_ALLOC_SIZE_ENV)
        .env_remove("ZENOH_SHM_MESSAGE_SIZE_THRESHOLD")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    for (k, v) in env {
        command.env(k, v);
    }
    command.spawn().expect("start a child process")
}

/// The next line of a child's for the test (blocking until it writes one or exits).
fn next_report(out: &mut BufReader<ChildStdout>, who: &str) -> String {
    let mut line = String::new();
    loop {
        line.clear();
        let n = out.read_line(&mut line).expect("read a child's output");
        assert!(n > 0, "the {who} exited without reporting");
        // libtest may have written `test child ... ` on the same line first.
        if let Some((_, rest)) = line.split_once(MARK) {
            return rest.trim().to_owned();
        }
    }
}

/// What the subscriber reported of the image, with `router_overrides` on the router and
/// `overrides` and `env` on both processes.
fn image_across_processes(
    port: u16,
    domain: u32,
    router_overrides: &str,
    overrides: &str,
    env: &[(&str, &str)],
) -> String {
    let get = |k: &str| {
        (k == config::CONFIG_OVERRIDE_ENV)
            .then(|| format!(r#"listen/endpoints=["tcp/127.0.0.1:{port}"];{router_overrides}"#))
    };
    let router = zenoh::open(config::config(ConfigKind::Router, get).expect("router config"))
        .wait()
        .expect("router");
    let mut subscriber = spawn("subscriber", domain, port, overrides, env);
    let mut sub_out = BufReader::new(subscriber.stdout.take().expect("stdout"));
    assert_eq!(next_report(&mut sub_out, "subscriber"), "ready");
    let mut publisher = spawn("publisher", domain, port, overrides, env);
    let mut pub_out = BufReader::new(publisher.stdout.take().expect("stdout"));
    let received = next_report(&mut sub_out, "subscriber");
    let published = next_report(&mut pub_out, "publisher");
    assert!(published.starts_with("published"), "{published}");
    // Closing its standard input lets the publisher end.
    drop(publisher.stdin.take());
    for (who, mut child) in [("subscriber", subscriber), ("publisher", publisher)] {
        let status = child.wait().expect("wait for a child");
        assert!(status.success(), "the {who} failed: {status}");
    }
    drop(router);
    match published.strip_prefix("published") {
        Some("") | None => received,
        Some(loaned) => format!("{received}{loaned}"),
    }
}

/// The size of the image's CDR body: the header (stamp 8, `camera` 4 + 7), 1 byte of padding,
/// height 4, width 4, `rgb8` 4 + 5, is_bigendian 1, 2 bytes of padding, step 4, and the pixels
/// (4 + 6,220,800).
const BODY_LEN: usize = 6_220_848;

#[test]
fn a_1080p_image_crosses_in_shared_memory_when_enabled() {
    let report = image_across_processes(17580, 87, &shm_on(), &shm_on(), &[]);
    assert_eq!(report, format!("received intact=true len={BODY_LEN} shm=1"));
}

#[test]
fn a_1080p_image_crosses_in_a_lent_buffer_read_in_place() {
    let report = image_across_processes(17585, 92, &shm_on(), &shm_on(), &[(LOANS_ENV, "1")]);
    assert_eq!(
        report,
        format!("received intact=true len={BODY_LEN} shm=1 lent=true loaned=true")
    );
}

#[test]
fn without_shared_memory_the_image_crosses_as_bytes() {
    let report = image_across_processes(17581, 88, "", "", &[]);
    assert_eq!(report, format!("received intact=true len={BODY_LEN} shm=0"));
}

#[test]
fn a_pool_too_small_falls_back_to_the_heap() {
    let one_mib = (1 << 20).to_string();
    let report = image_across_processes(
        17582,
        89,
        &shm_on(),
        &shm_on(),
        &[(SHM_ALLOC_SIZE_ENV, one_mib.as_str())],
    );
    assert_eq!(report, format!("received intact=true len={BODY_LEN} shm=0"));
}

/// The peers' overrides that keep them off each other (gossip autoconnect to routers only), so
/// that the image crosses the router.
fn via_the_router_only() -> String {
    format!(
        r#"{};scouting/gossip/autoconnect={{ router: [], peer: ["router"] }}"#,
        shm_on()
    )
}

#[test]
fn through_the_router_the_image_stays_in_shared_memory_if_the_router_enabled_it() {
    let report = image_across_processes(17583, 90, &shm_on(), &via_the_router_only(), &[]);
    assert_eq!(report, format!("received intact=true len={BODY_LEN} shm=1"));
}

#[test]
fn through_a_router_without_shared_memory_the_image_crosses_as_bytes() {
    let report = image_across_processes(17584, 91, "", &via_the_router_only(), &[]);
    assert_eq!(report, format!("received intact=true len={BODY_LEN} shm=0"));
}
