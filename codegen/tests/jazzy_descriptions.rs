//! Every interface file of every package of the Jazzy wheels (`scripts/setup` installs them),
//! parsed by us: its type description and the RIHS01 hash of every type it defines or uses equal
//! the `.json` rosidl_generator_type_description wrote beside it.

use std::path::{Path, PathBuf};

use horus_ros_codegen::msg::parse_file;
use horus_ros_codegen::TypeRegistry;
use horus_ros_test_support::jazzy::share_dir;
use serde_json::Value;

/// `(package, interface file, its .json)` for every `.msg`/`.srv`/`.action` (or, with `idl`,
/// every `.idl`) under the wheels' share directory, sorted.
fn interface_files(extensions: &[&str]) -> Vec<(String, PathBuf, PathBuf)> {
    let share = share_dir().unwrap_or_else(|e| panic!("{e}"));
    let mut out = Vec::new();
    let mut packages: Vec<PathBuf> = std::fs::read_dir(&share)
        .expect("share dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    packages.sort();
    for package in packages {
        let name = package
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_owned();
        for kind in ["msg", "srv", "action"] {
            let Ok(dir) = std::fs::read_dir(package.join(kind)) else {
                continue;
            };
            let mut files: Vec<PathBuf> = dir.filter_map(|e| e.ok().map(|e| e.path())).collect();
            files.sort();
            for f in files {
                let ext = f.extension().and_then(|e| e.to_str()).unwrap_or_default();
                if extensions.contains(&ext) {
                    out.push((name.clone(), f.clone(), f.with_extension("json")));
                }
            }
        }
    }
    out
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Parses every file, then checks every `.json`: returns (files, type hashes) checked.
fn check(extensions: &[&str]) -> (usize, usize) {
    let files = interface_files(extensions);
    let mut registry = TypeRegistry::new();
    let mut names = Vec::new();
    for (package, file, _) in &files {
        let interface = parse_file(package, file).unwrap_or_else(|e| panic!("{e}"));
        names.push(interface.name().to_string());
        registry.add(&interface);
    }
    let mut hashes = 0;
    let mut failures = Vec::new();
    for ((_, file, json), name) in files.iter().zip(&names) {
        let jazzy = read_json(json);
        match registry.describe(name) {
            Ok(ours) => {
                let ours = serde_json::to_value(&ours).expect("description as JSON");
                if ours != jazzy["type_description_msg"] {
                    failures.push(format!(
                        "{}: description differs\n ours:  {ours}\n jazzy: {}",
                        file.display(),
                        jazzy["type_description_msg"]
                    ));
                }
            }
            Err(e) => failures.push(format!("{}: {e}", file.display())),
        }
        for h in jazzy["type_hashes"].as_array().expect("type_hashes") {
            let type_name = h["type_name"].as_str().expect("type_name");
            let expected = h["hash_string"].as_str().expect("hash_string");
            hashes += 1;
            match registry.hash(type_name) {
                Ok(ours) if ours.to_string() == expected => {}
                Ok(ours) => failures.push(format!("{type_name}: ours {ours}, jazzy {expected}")),
                Err(e) => failures.push(format!("{type_name}: {e}")),
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} files differ from Jazzy:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
    (files.len(), hashes)
}

#[test]
fn every_msg_srv_and_action_file_describes_and_hashes_as_jazzy() {
    let (files, hashes) = check(&["msg", "srv", "action"]);
    println!(
        "{files} .msg/.srv/.action files: descriptions and {hashes} type hashes equal Jazzy's"
    );
    assert!(files >= 190, "only {files} interface files found");
}
