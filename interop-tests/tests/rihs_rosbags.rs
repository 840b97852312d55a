//! Every message type horus-ros defines has the RIHS01 hash that an independent implementation
//! computes: rosbags (`peers/rosbags_rihs.py`), from its own ROS 2 Jazzy message definitions and
//! its own REP-2011 hashing. (msgs/tests/hashes.rs checks them against hashes published by ROS 2
//! builds; services are not in rosbags' store and are checked there only.)

use std::collections::BTreeMap;
use std::io::Write;
use std::process::{Command, Stdio};

use horus_ros_msgs::Message;

/// `(type name, our RIHS01 string)` of each listed type.
macro_rules! ours {
    ($($t:ty),* $(,)?) => {
        vec![$((<$t as Message>::TYPE_NAME, <$t as Message>::type_hash().to_string())),*]
    };
}

#[test]
fn every_message_type_hashes_as_rosbags_jazzy_store() {
    let ours: Vec<(&str, String)> = interop_tests::compiled_message_types!(ours);

    let mut child = Command::new(interop_tests::python())
        .arg(interop_tests::peer_script("rosbags_rihs.py"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run the rosbags script");
    {
        let mut stdin = child.stdin.take().expect("stdin");
        for (name, _) in &ours {
            writeln!(stdin, "{name}").expect("write a type name");
        }
    }
    let out = child.wait_with_output().expect("rosbags script output");
    assert!(
        out.status.success(),
        "{}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs: BTreeMap<String, String> = String::from_utf8(out.stdout)
        .expect("UTF-8")
        .lines()
        .filter_map(|l| l.split_once(' '))
        .map(|(name, hash)| (name.to_owned(), hash.to_owned()))
        .collect();
    let differing: Vec<String> = ours
        .iter()
        .filter(|(name, hash)| theirs.get(*name) != Some(hash))
        .map(|(name, hash)| format!("{name}: ours {hash}, rosbags {:?}", theirs.get(*name)))
        .collect();
    assert!(differing.is_empty(), "{differing:#?}");
    assert_eq!(theirs.len(), ours.len(), "{theirs:#?}");
}
