//! Interop with an independent Cyclone DDS peer (the `cyclonedds` Python binding, as set up by
//! `scripts/setup` in target/interop-venv): it must see our participant's and endpoints'
//! USER_DATA (`enclave=`, `typehash=`) through its built-in topics, and raw CDR must flow both
//! ways. Domain 146; run inside `scripts/isolated`.
mod common;

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::*;
use horus_ros_rmw_cyclone::{BuiltinSample, BuiltinTopic, EndpointQos, Waiter};

const DOMAIN: u32 = 146;

use horus_ros_test_support::jazzy::python;

struct Kill(Child);
impl Drop for Kill {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    // The peer prints flat JSON objects with string/number values; enough for a lookup.
    let pat = format!("\"{key}\": ");
    let rest = &line[line.find(&pat)? + pat.len()..];
    Some(match rest.strip_prefix('"') {
        Some(s) => &s[..s.find('"')?],
        None => rest[..rest.find([',', '}']).unwrap_or(rest.len())].trim(),
    })
}

#[test]
fn python_cyclone_peer_sees_our_user_data_and_exchanges_cdr() {
    let py = python();
    assert!(
        py.exists(),
        "{} missing: run scripts/setup (it creates the venv with cyclonedds)",
        py.display()
    );
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peers/cyclone_blob_peer.py");
    let mut child = Kill(
        Command::new(&py)
            .arg(&script)
            .args([DOMAIN.to_string(), "25".to_owned()])
            .env("CYCLONEDDS_URI", LOOPBACK)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("start the Python peer"),
    );
    let (tx, lines) = mpsc::channel::<String>();
    let stdout = child.0.stdout.take().expect("stdout");
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            eprintln!("peer: {line}");
            if tx.send(line).is_err() {
                break;
            }
        }
    });

    let p = participant(DOMAIN, "enclave=/;");
    let parts = p
        .builtin_reader(BuiltinTopic::Participant)
        .expect("builtin");
    let qos = EndpointQos::default();
    let w = p
        .writer(
            &p.blob_topic("rt/rmwc/to_py", TIME_TYPE).expect("t"),
            &qos,
            TIME_USER_DATA.as_bytes(),
        )
        .expect("w");
    let r = p
        .reader(
            &p.blob_topic("rt/rmwc/from_py", TIME_TYPE).expect("t"),
            &qos,
            TIME_USER_DATA.as_bytes(),
        )
        .expect("r");
    let (me, wguid, rguid) = (
        p.guid().expect("g"),
        w.entity().guid().expect("g"),
        r.entity().guid().expect("g"),
    );

    // Match the Python reader, then send five samples (the interpreter starts first: a wider
    // bound than discovery alone).
    let end = Instant::now() + Duration::from_secs(20);
    wait_matched(&w, end.saturating_duration_since(Instant::now()));
    for i in 0..5 {
        w.write(&time_cdr(1000 + i, 7 * i as u32)).expect("write");
    }

    // Take its three samples, waking on data.
    let waiter = Waiter::new().expect("waiter");
    waiter.attach_reader(&r, 1).expect("attach");
    let mut got = Vec::new();
    let pywriter = loop {
        assert!(
            Instant::now() < end,
            "got only {got:?} from the Python writer"
        );
        waiter.wait(Duration::from_millis(500)).expect("wait");
        while let Some(s) = r.take().expect("take") {
            got.push((parse_time(&s.cdr), s.writer_guid));
        }
        if got.len() >= 3 {
            break got[0].1.expect("writer guid of the Python writer");
        }
    };
    assert_eq!(
        got.iter().map(|g| g.0).collect::<Vec<_>>(),
        vec![(-5, 123456), (-6, 123457), (-7, 123458)]
    );
    assert_ne!(pywriter.participant(), me);

    // What the peer reported.
    let mut report = Vec::new();
    while !report.iter().any(|l: &String| l.contains("\"done\"")) {
        let left = end.saturating_duration_since(Instant::now());
        match lines.recv_timeout(left) {
            Ok(l) => report.push(l),
            Err(e) => panic!("peer did not finish ({e}); it printed {report:#?}"),
        }
    }
    let hex =
        |g: horus_ros_rmw_cyclone::Guid| g.0.iter().map(|b| format!("{b:02x}")).collect::<String>();
    let find = |event: &str, guid: &str| {
        report
            .iter()
            .find(|l| field(l, "event") == Some(event) && field(l, "guid") == Some(guid))
            .unwrap_or_else(|| panic!("peer never reported {event} {guid}: {report:#?}"))
            .clone()
    };
    assert_eq!(
        field(&find("participant", &hex(me)), "user_data"),
        Some("enclave=/;")
    );
    let pw = find("publication", &hex(wguid));
    assert_eq!(field(&pw, "user_data"), Some(TIME_USER_DATA));
    assert_eq!(field(&pw, "type"), Some(TIME_TYPE));
    assert_eq!(field(&pw, "topic"), Some("rt/rmwc/to_py"));
    assert_eq!(
        field(&find("subscription", &hex(rguid)), "user_data"),
        Some(TIME_USER_DATA)
    );
    let samples: Vec<(&str, &str)> = report
        .iter()
        .filter(|l| field(l, "event") == Some("sample"))
        .map(|l| {
            (
                field(l, "sec").unwrap_or(""),
                field(l, "nanosec").unwrap_or(""),
            )
        })
        .collect();
    assert_eq!(
        samples,
        vec![
            ("1000", "0"),
            ("1001", "7"),
            ("1002", "14"),
            ("1003", "21"),
            ("1004", "28")
        ]
    );
    assert!(
        report.iter().any(|l| l.contains("\"done\", \"got\": 5")),
        "{report:#?}"
    );

    // And we see the Python participant's USER_DATA through our built-in reader.
    let waiter = builtin_waiter(&[&parts]);
    let py = until(DISCOVERY, &waiter, || {
        parts
            .take()
            .expect("take")
            .into_iter()
            .find_map(|s| match s {
                BuiltinSample::Participant(info) if info.guid == pywriter.participant() => {
                    Some(info)
                }
                _ => None,
            })
    })
    .expect("Python participant in DCPSParticipant");
    assert_eq!(py.user_data, b"enclave=/py;");
}
