//! A 1920×1080 rgb8 `sensor_msgs/Image` (6,220,848 bytes of CDR body) between two Zenoh
//! contexts of this process, both with shared memory on, through a router of the benchmark's own:
//! the copy path (`RawWriter::write` of a `Vec`, copied into the pool; `RawReader::take`, copied
//! out) beside loans (`RawWriter::loan` filled in place and `write_loan`; `RawReader::take_loan`
//! read in place), in the same run. One image in flight at a time: each is published, then
//! taken, and its bytes read (a checksum) on the taking side in both paths. Prints MiB/s and
//! images/s per path and their ratio.
//!
//! Run inside a private network namespace: `scripts/bench`, or
//! `cargo bench -p horus-ros-rmw --features zenoh --bench zenoh_shm_loans --no-run` then
//! `scripts/isolated cargo bench -p horus-ros-rmw --features zenoh --bench zenoh_shm_loans`.
//! Settings: `HORUS_BENCH_LOAN_IMAGES` (images per path and round, default 200),
//! `HORUS_BENCH_LOAN_ROUNDS` (rounds of both paths, alternating; default 3).

use std::time::{Duration, Instant};

use horus_ros_msgs::sensor_msgs::msg::Image;
use horus_ros_msgs::Message;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::zenoh::config::{self, ConfigKind};
use horus_ros_rmw::zenoh::shm::SHM_ENABLED_KEY;
use horus_ros_rmw::{
    Context, DiscoveryEvent, LoanedSample, RawEndpointSpec, RawReader, RawWriter,
    SignalHandlerOptions,
};
use horus_ros_test_support::bench::{env_count, loadavg, refuse_outside_namespace};
use zenoh::Wait;

/// The router's port.
const PORT: u16 = 17590;
/// How long one image may take before the benchmark gives up.
const LIMIT: Duration = Duration::from_secs(30);

/// Shared memory on, without zenoh's own transport optimization (only the publisher's pool can
/// carry an image through shared memory).
fn shm_on() -> String {
    format!("{SHM_ENABLED_KEY}=true;transport/shared_memory/transport_optimization/enabled=false")
}

/// A context on the Zenoh backend joined to the benchmark's router, shared memory on.
fn context() -> Context {
    let get = |k: &str| {
        (k == config::CONFIG_OVERRIDE_ENV).then(|| {
            format!(
                r#"connect/endpoints=["tcp/127.0.0.1:{PORT}"];listen/endpoints=["tcp/127.0.0.1:0"];{}"#,
                shm_on()
            )
        })
    };
    let session = config::config(ConfigKind::Session, get).expect("session config");
    Context::builder()
        .domain_id(93)
        .implementation(horus_ros_rmw::zenoh::implementation(session))
        .signal_handler(SignalHandlerOptions::None)
        .arguments(Default::default())
        .build()
        .expect("a zenoh context")
}

/// The image's CDR body (pixels in a pattern).
fn image_body() -> Vec<u8> {
    let (width, height) = (1920u32, 1080u32);
    let len = (width * height * 3) as usize;
    let image = Image {
        height,
        width,
        encoding: "rgb8".to_owned(),
        step: width * 3,
        data: (0..len).map(|i| (i % 251) as u8).collect(),
        ..Default::default()
    };
    horus_ros_msgs::cdr::to_cdr_body(&image).expect("encode")
}

/// A cheap read of every byte (what a consumer of the image does at least once).
fn checksum(body: &[u8]) -> u64 {
    body.chunks(8).fold(0u64, |sum, chunk| {
        let mut word = [0u8; 8];
        word[..chunk.len()].copy_from_slice(chunk);
        sum.wrapping_add(u64::from_le_bytes(word))
    })
}

/// The next sample of `reader` (as a loan or taken), waiting for it.
fn next(reader: &mut RawReader, loan: bool) -> LoanedSample {
    let deadline = Instant::now() + LIMIT;
    loop {
        let taken = if loan {
            reader.take_loan().expect("take a loan")
        } else {
            reader.take().expect("take").map(LoanedSample::from)
        };
        if let Some(sample) = taken {
            return sample;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "no image within {LIMIT:?}");
        reader.wait(left);
    }
}

/// `images` images through one path; the time taken, and how many were read in place.
fn run(
    writer: &RawWriter,
    reader: &mut RawReader,
    body: &[u8],
    images: usize,
    loan: bool,
) -> (Duration, usize) {
    let expected = checksum(body);
    let mut in_place = 0;
    let start = Instant::now();
    for _ in 0..images {
        if loan {
            let mut buffer = writer.loan(body.len());
            buffer.copy_from_slice(body);
            writer
                .write_loan(buffer, None, None)
                .expect("publish a loan");
        } else {
            writer.write(body.to_vec(), None, None).expect("publish");
        }
        let sample = next(reader, loan);
        assert_eq!(checksum(&sample), expected, "the image arrived changed");
        in_place += usize::from(sample.is_lent());
    }
    (start.elapsed(), in_place)
}

fn main() {
    refuse_outside_namespace(
        "zenoh_shm_loans",
        "scripts/isolated cargo bench -p horus-ros-rmw --features zenoh --bench zenoh_shm_loans \
         (build it outside first: cargo bench -p horus-ros-rmw --features zenoh --bench \
         zenoh_shm_loans --no-run)",
    );
    let images = env_count("HORUS_BENCH_LOAN_IMAGES", 200);
    let rounds = env_count("HORUS_BENCH_LOAN_ROUNDS", 3);
    let get = |k: &str| {
        (k == config::CONFIG_OVERRIDE_ENV)
            .then(|| format!(r#"listen/endpoints=["tcp/127.0.0.1:{PORT}"];{}"#, shm_on()))
    };
    let _router = zenoh::open(config::config(ConfigKind::Router, get).expect("router config"))
        .wait()
        .expect("router");
    let spec = RawEndpointSpec {
        dds_topic_name: "rt/camera/image_raw".to_owned(),
        dds_type_name: Image::dds_type_name(),
        type_hash: Image::type_hash(),
        qos: Qos::default_profile(),
        service_id: None,
    };
    let publisher_context = context();
    let subscriber_context = context();
    let mut feed = publisher_context.discovery_feed().expect("feed");
    let writer = publisher_context
        .create_node("loan_talker", "/")
        .expect("node")
        .create_raw_writer(&spec)
        .expect("writer");
    let mut reader = subscriber_context
        .create_node("loan_listener", "/")
        .expect("node")
        .create_raw_reader(&spec)
        .expect("reader");
    let deadline = Instant::now() + LIMIT;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "the subscription never matched");
        if let Some(DiscoveryEvent::Matched { local, .. }) = feed.next_timeout(left) {
            if local == writer.gid() {
                break;
            }
        }
    }
    let body = image_body();
    let mib = body.len() as f64 / (1024.0 * 1024.0);
    println!(
        "1080p rgb8 Image ({} bytes of CDR body) between two Zenoh contexts of one process, \
         shared memory on, through a router; {rounds} rounds of {images} images per path, one in \
         flight; load {}",
        body.len(),
        loadavg()
    );
    // Warm-up: the pool's first allocations, zenoh's first mappings.
    run(&writer, &mut reader, &body, 10, false);
    run(&writer, &mut reader, &body, 10, true);
    let shm_before = reader.shared_memory_samples();
    let mut totals = [(Duration::ZERO, 0usize); 2];
    for _ in 0..rounds {
        for (path, loan) in [(0, false), (1, true)] {
            let (took, in_place) = run(&writer, &mut reader, &body, images, loan);
            totals[path].0 += took;
            totals[path].1 += in_place;
        }
    }
    let shm = reader.shared_memory_samples() - shm_before;
    let sent = (rounds * images) as f64;
    let rate = |took: Duration| sent * mib / took.as_secs_f64();
    println!("path                                    MiB/s   images/s   read in place");
    for (name, (took, in_place)) in [
        ("copy (write a Vec, take a Vec)", totals[0]),
        ("loans (write_loan, take_loan)", totals[1]),
    ] {
        println!(
            "{name:<38} {:>7.0} {:>10.1} {in_place:>9}/{}",
            rate(took),
            sent / took.as_secs_f64(),
            rounds * images
        );
    }
    println!(
        "loans / copy = {:.2} (MiB/s); through shared memory: {shm} of {} images",
        rate(totals[1].0) / rate(totals[0].0),
        2 * rounds * images
    );
}
