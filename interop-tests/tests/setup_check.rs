//! `scripts/setup --check` against fake machines: directory trees laid out as Debian lays out the
//! packages (`HORUS_ROS_SETUP_ROOT`), with the test environment at `/venv` laid out as pip lays it
//! out (`HORUS_ROS_SETUP_VENV`), each missing one thing, and the exact list of packages the
//! script would install for it. No DDS, no network, nothing installed.

use std::fs;
use std::os::unix::fs::{symlink, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::Command;

use tempfile::TempDir;

/// Debian's multiarch directory of the fake machines.
const MULTIARCH: &str = "x86_64-linux-gnu";
/// Where the fake machines have the Python test environment.
const VENV: &str = "/venv";
/// The pinned packages of the environment, in the order `--check` lists them: Cyclone DDS's
/// Python binding, rosbags, and real ROS 2 Jazzy (rclpy on rmw_fastrtps_cpp / Fast DDS, and the
/// interface packages).
const PIP_PINS: [&str; 17] = [
    "cyclonedds==11.0.1",
    "rosbags==0.11.9",
    "ros-jazzy-rclpy[fastrtps]==7.1.6",
    "ros-rmw-fastrtps-cpp==8.4.3",
    "ros-fastrtps==2.14.5",
    "ros-jazzy-std-msgs==5.3.6",
    "ros-jazzy-std-srvs==5.3.6",
    "ros-jazzy-test-msgs==2.0.3",
    "ros-jazzy-rcl-interfaces==2.0.3",
    "ros-jazzy-service-msgs==2.0.3",
    "ros-jazzy-lifecycle-msgs==2.0.3",
    "ros-jazzy-action-msgs==2.0.3",
    "ros-jazzy-builtin-interfaces==2.0.3",
    "ros-jazzy-type-description-interfaces==2.0.3",
    "ros-jazzy-unique-identifier-msgs==2.5.0",
    "ros-jazzy-rosgraph-msgs==2.0.3",
    "ros-jazzy-common-interfaces==5.3.6",
];

/// The `.dist-info` directory pip makes for a pin: `<name>-<version>.dist-info`, the name's runs
/// of `-_.` as one `_`, extras dropped.
fn dist_info(pin: &str) -> String {
    let (name, version) = pin.split_once("==").expect("a pinned version");
    let name = name.split('[').next().unwrap_or(name);
    let mut normal = String::new();
    for c in name.chars() {
        if matches!(c, '-' | '_' | '.') {
            if !normal.ends_with('_') {
                normal.push('_');
            }
        } else {
            normal.push(c);
        }
    }
    format!("{VENV}/lib/python3.11/site-packages/{normal}-{version}.dist-info")
}

/// The `pip:` lines `--check` prints for `pins`.
fn pip_lines(pins: &[&str]) -> Vec<String> {
    pins.iter().map(|p| format!("pip:{p}")).collect()
}

/// The start of an ELF file of this target's class (what clang-sys checks of a libclang).
fn elf_header() -> Vec<u8> {
    let class = if cfg!(target_pointer_width = "64") {
        2
    } else {
        1
    };
    let mut bytes = vec![0x7f, b'E', b'L', b'F', class];
    bytes.resize(64, 0);
    bytes
}

/// A fake machine: a directory tree.
struct Tree {
    dir: TempDir,
}

impl Tree {
    /// An empty machine.
    fn empty() -> Self {
        Self {
            dir: tempfile::Builder::new()
                .prefix("horus-ros-setup-")
                .tempdir()
                .expect("temporary directory"),
        }
    }

    fn path(&self, path: &str) -> PathBuf {
        self.dir.path().join(path.trim_start_matches('/'))
    }

    fn parent_dirs(&self, path: &str) -> PathBuf {
        let p = self.path(path);
        fs::create_dir_all(p.parent().expect("a parent")).expect("create directories");
        p
    }

    /// A file with these bytes.
    fn file(&self, path: &str, bytes: &[u8]) -> &Self {
        fs::write(self.parent_dirs(path), bytes).expect("write file");
        self
    }

    /// A plain text file.
    fn text(&self, path: &str) -> &Self {
        self.file(path, b"text\n")
    }

    /// An executable.
    fn exe(&self, path: &str) -> &Self {
        let p = self.parent_dirs(path);
        fs::write(&p, b"#!/bin/sh\n").expect("write executable");
        fs::set_permissions(&p, fs::Permissions::from_mode(0o755)).expect("chmod");
        self
    }

    /// A shared library (an ELF header is all the script reads).
    fn elf(&self, path: &str) -> &Self {
        self.file(path, &elf_header())
    }

    /// A symbolic link `path -> target` (target as written: relative, or absolute inside the
    /// machine).
    fn link(&self, path: &str, target: &str) -> &Self {
        let p = self.parent_dirs(path);
        let _ = fs::remove_file(&p);
        symlink(target, p).expect("symlink");
        self
    }

    /// Removes a file or link.
    fn remove(&self, path: &str) -> &Self {
        fs::remove_file(self.path(path)).expect("remove");
        self
    }

    /// A machine with everything scripts/setup looks for, laid out as Debian 12's packages do.
    fn complete() -> Self {
        let t = Self::empty();
        // iproute2, gcc (cc through the alternatives system), make, cmake, g++, valgrind, procps,
        // nftables.
        t.exe("/usr/bin/ip")
            .exe("/usr/bin/gcc-12")
            .link("/usr/bin/gcc", "gcc-12")
            .link("/etc/alternatives/cc", "/usr/bin/gcc")
            .link("/usr/bin/cc", "/etc/alternatives/cc")
            .exe("/usr/bin/g++-12")
            .link("/usr/bin/g++", "g++-12")
            .link("/etc/alternatives/c++", "/usr/bin/g++")
            .link("/usr/bin/c++", "/etc/alternatives/c++")
            .text("/usr/include/stdlib.h")
            .exe("/usr/bin/make")
            .exe("/usr/bin/cmake")
            .exe("/usr/bin/valgrind")
            .exe("/usr/bin/kill")
            .exe("/usr/sbin/nft");
        t.libclang_cpp_14().libclang1_14().clang_headers_14();
        // python3, python3.11-venv, python3-pip-whl, python3-setuptools-whl.
        t.exe("/usr/bin/python3.11")
            .link("/usr/bin/python3", "python3.11")
            .text("/usr/lib/python3.11/venv/__init__.py")
            .text("/usr/lib/python3.11/ensurepip/__init__.py")
            .text("/usr/share/python-wheels/pip-23.0.1-py3-none-any.whl")
            .text("/usr/share/python-wheels/setuptools-66.1.1-py3-none-any.whl");
        // The Python environment with every pinned package.
        t.link(&format!("{VENV}/bin/python"), "/usr/bin/python3.11");
        for pin in PIP_PINS {
            t.text(&format!("{}/METADATA", dist_info(pin)));
        }
        t
    }

    /// Package libclang-cpp14 (on Debian's base images): the C++ library, not what bindgen loads.
    fn libclang_cpp_14(&self) -> &Self {
        self.elf("/usr/lib/llvm-14/lib/libclang-cpp.so.14").link(
            &format!("/usr/lib/{MULTIARCH}/libclang-cpp.so.14"),
            "../llvm-14/lib/libclang-cpp.so.14",
        )
    }

    /// Package libclang1-14, as `dpkg -L libclang1-14` lists it.
    fn libclang1_14(&self) -> &Self {
        let lib = format!("/usr/lib/{MULTIARCH}");
        self.elf(&format!("{lib}/libclang-14.so.14.0.6"))
            .link(&format!("{lib}/libclang-14.so.13"), "libclang-14.so.14.0.6")
            .link(&format!("{lib}/libclang-14.so.1"), "libclang-14.so.13")
            .link(
                "/usr/lib/llvm-14/lib/libclang-14.so.1",
                &format!("../../{MULTIARCH}/libclang-14.so.1"),
            )
            .link("/usr/lib/llvm-14/lib/libclang.so.1", "libclang-14.so.1")
    }

    /// Package libclang1-14's files, less everything but the one at `keep`.
    fn only_libclang(&self, keep: &str) -> &Self {
        let lib = format!("/usr/lib/{MULTIARCH}");
        for path in [
            "/usr/lib/llvm-14/lib/libclang.so.1".to_owned(),
            "/usr/lib/llvm-14/lib/libclang-14.so.1".to_owned(),
            format!("{lib}/libclang-14.so.1"),
            format!("{lib}/libclang-14.so.13"),
            format!("{lib}/libclang-14.so.14.0.6"),
        ] {
            self.remove(&path);
        }
        self.elf(keep)
    }

    /// Package libclang-common-14-dev's builtin headers.
    fn clang_headers_14(&self) -> &Self {
        self.text("/usr/lib/llvm-14/lib/clang/14.0.6/include/stddef.h")
            .text("/usr/lib/llvm-14/lib/clang/14.0.6/include/stdint.h")
            .link(
                "/usr/include/clang/14.0.6/include",
                "../../../lib/llvm-14/lib/clang/14.0.6/include",
            )
    }

    /// `scripts/setup --check` on this machine: (stdout lines, exit status).
    fn check(&self) -> (Vec<String>, Option<i32>) {
        let out = setup(self.dir.path(), &["--check"]);
        let stdout = String::from_utf8(out.stdout).expect("UTF-8 output");
        assert!(
            out.stderr.is_empty(),
            "stderr: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        (
            stdout.lines().map(str::to_owned).collect(),
            out.status.code(),
        )
    }

    /// Asserts `scripts/setup --check` would install exactly `packages` (in that order).
    fn assert_missing(&self, packages: &[&str]) {
        self.assert_missing_for(packages, "");
    }

    /// [`Tree::assert_missing`], naming the case on failure.
    fn assert_missing_for(&self, packages: &[&str], case: &str) {
        let (lines, code) = self.check();
        assert_eq!(lines, packages, "{case}");
        assert_eq!(
            code,
            Some(if packages.is_empty() { 0 } else { 1 }),
            "{case}"
        );
    }
}

/// Runs `bash scripts/setup args…` on the machine `root`, with nothing of this machine's
/// environment that the script reads for the real machine.
fn setup(root: &Path, args: &[&str]) -> std::process::Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/setup");
    Command::new("bash")
        .arg(script)
        .args(args)
        .env("HORUS_ROS_SETUP_ROOT", root)
        .env("HORUS_ROS_SETUP_VENV", VENV)
        .env_remove("LIBCLANG_PATH")
        .env_remove("LLVM_CONFIG_PATH")
        .env_remove("LD_LIBRARY_PATH")
        .env_remove("LIBRARY_PATH")
        .output()
        .expect("run scripts/setup")
}

#[test]
fn a_complete_machine_needs_nothing() {
    Tree::complete().assert_missing(&[]);
}

#[test]
fn an_empty_machine_needs_everything() {
    let mut everything: Vec<String> = [
        "iproute2",
        "gcc",
        "libc6-dev",
        "make",
        "cmake",
        "g++",
        "libclang1-14",
        "libclang-common-14-dev",
        "valgrind",
        "procps",
        "nftables",
        "python3",
        "python3-venv",
    ]
    .map(str::to_owned)
    .to_vec();
    everything.extend(pip_lines(&PIP_PINS));
    let everything: Vec<&str> = everything.iter().map(String::as_str).collect();
    Tree::empty().assert_missing(&everything);
}

#[test]
fn libclang_cpp_is_not_the_libclang_bindgen_loads() {
    // Debian 12's base image: libclang-cpp14 installed, libclang1-14 not.
    let t = Tree::complete();
    let lib = format!("/usr/lib/{MULTIARCH}");
    for path in [
        "/usr/lib/llvm-14/lib/libclang.so.1".to_owned(),
        "/usr/lib/llvm-14/lib/libclang-14.so.1".to_owned(),
        format!("{lib}/libclang-14.so.1"),
        format!("{lib}/libclang-14.so.13"),
        format!("{lib}/libclang-14.so.14.0.6"),
    ] {
        t.remove(&path);
    }
    t.assert_missing(&["libclang1-14"]);
    // A `-cpp.` name is skipped wherever it is, even with a libclang-like version suffix.
    t.elf("/usr/local/lib/libclang-cpp.so.15");
    t.assert_missing(&["libclang1-14"]);
}

#[test]
fn each_name_clang_sys_accepts_is_enough() {
    let lib = format!("/usr/lib/{MULTIARCH}");
    for keep in [
        "/usr/lib/llvm-14/lib/libclang.so.1".to_owned(),
        "/usr/lib/llvm-14/lib/libclang.so".to_owned(),
        "/usr/lib/llvm-14/lib/libclang-14.so".to_owned(),
        format!("{lib}/libclang-14.so.1"),
        format!("{lib}/libclang-14.so.14.0.6"),
    ] {
        let t = Tree::complete();
        t.only_libclang(&keep);
        t.assert_missing_for(&[], &keep);
    }
}

#[test]
fn a_libclang_that_does_not_load_does_not_count() {
    // Not an ELF file, an ELF file of the other class, a dangling link, a name clang-sys does
    // not look for, and a directory it does not search.
    let other_class = {
        let mut h = elf_header();
        h[4] = if h[4] == 2 { 1 } else { 2 };
        h
    };
    let cases: [&dyn Fn(&Tree); 5] = [
        &|t| {
            t.only_libclang("/usr/lib/llvm-14/lib/libclang.so.1")
                .text("/usr/lib/llvm-14/lib/libclang.so.1");
        },
        &|t| {
            t.only_libclang("/usr/lib/llvm-14/lib/libclang.so.1")
                .file("/usr/lib/llvm-14/lib/libclang.so.1", &other_class);
        },
        &|t| {
            t.only_libclang("/usr/lib/llvm-14/lib/libclang.so.1").link(
                "/usr/lib/llvm-14/lib/libclang.so.1",
                "libclang-14.so.14.0.6",
            );
        },
        &|t| {
            t.only_libclang("/usr/lib/llvm-14/lib/libclang.so.1")
                .remove("/usr/lib/llvm-14/lib/libclang.so.1")
                .elf("/usr/lib/llvm-14/lib/libclang14.so");
        },
        &|t| {
            t.only_libclang("/usr/lib/llvm-14/lib/libclang.so.1")
                .remove("/usr/lib/llvm-14/lib/libclang.so.1")
                .elf("/opt/llvm-14/lib/libclang.so.1");
        },
    ];
    for (i, case) in cases.iter().enumerate() {
        let t = Tree::complete();
        case(&t);
        t.assert_missing_for(&["libclang1-14"], &format!("case {i}"));
    }
}

#[test]
fn builtin_headers_must_match_the_libclang_clang_sys_chooses() {
    // Headers are part of libclang-common-14-dev; other headers do not replace stddef.h.
    let t = Tree::complete();
    t.remove("/usr/lib/llvm-14/lib/clang/14.0.6/include/stddef.h");
    t.assert_missing(&["libclang-common-14-dev"]);
    // Headers of another LLVM do not count for libclang 14.
    t.text("/usr/lib/llvm-15/lib/clang/15.0.6/include/stddef.h");
    t.assert_missing(&["libclang-common-14-dev"]);

    // libclang1-15 beside libclang1-14: clang-sys takes the highest version
    // (libclang-15.so.15.0.6), whose headers come from libclang-common-15-dev.
    let t = Tree::complete();
    let lib = format!("/usr/lib/{MULTIARCH}");
    t.elf(&format!("{lib}/libclang-15.so.15.0.6"))
        .link(&format!("{lib}/libclang-15.so.1"), "libclang-15.so.15.0.6")
        .link(
            "/usr/lib/llvm-15/lib/libclang.so.1",
            &format!("../../{MULTIARCH}/libclang-15.so.1"),
        );
    t.assert_missing(&["libclang-common-15-dev"]);
    t.text("/usr/lib/llvm-15/lib/clang/15.0.6/include/stddef.h");
    t.assert_missing(&[]);
}

#[test]
fn a_libclang_of_another_origin_needs_its_own_builtin_headers() {
    // An upstream build in /usr/local: the highest version, so clang-sys takes it; its builtin
    // headers are beside it (lib/clang/<version>/include), not in a Debian package.
    let t = Tree::complete();
    t.elf("/usr/local/lib/libclang.so.18.1.8")
        .text("/usr/local/lib/clang/18/include/stddef.h");
    t.assert_missing(&[]);
    t.remove("/usr/local/lib/clang/18/include/stddef.h");
    let out = setup(t.dir.path(), &["--check"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty(), "no package provides them");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("setup: ")
            && stderr.contains("/usr/local/lib/libclang.so.18.1.8 has no builtin headers"),
        "{stderr}"
    );
}

#[test]
fn the_python_environment_needs_each_pinned_package_in_its_version() {
    // Each package missing is listed alone, with its pin.
    for pin in PIP_PINS {
        let t = Tree::complete();
        t.remove(&format!("{}/METADATA", dist_info(pin)));
        t.assert_missing_for(&[&format!("pip:{pin}")], pin);
    }
    // Another version does not count: rclpy 7.1.5, Fast DDS 2.14.4.
    let t = Tree::complete();
    t.remove(&format!(
        "{}/METADATA",
        dist_info("ros-jazzy-rclpy[fastrtps]==7.1.6")
    ))
    .text(&format!("{}/METADATA", dist_info("ros-jazzy-rclpy==7.1.5")))
    .remove(&format!("{}/METADATA", dist_info("ros-fastrtps==2.14.5")))
    .text(&format!("{}/METADATA", dist_info("ros-fastrtps==2.14.4")));
    t.assert_missing(&[
        "pip:ros-jazzy-rclpy[fastrtps]==7.1.6",
        "pip:ros-fastrtps==2.14.5",
    ]);
    // Without its interpreter the environment is not there at all.
    let t = Tree::complete();
    t.remove(&format!("{VENV}/bin/python"));
    let all = pip_lines(&PIP_PINS);
    t.assert_missing(&all.iter().map(String::as_str).collect::<Vec<_>>());
}

#[test]
fn python3_must_be_cpython_3_11() {
    // Debian 13's python3 is 3.13: no Debian package helps, so it is a note (exit 1), naming
    // the version found and the one the wheels need.
    let t = Tree::complete();
    t.exe("/usr/bin/python3.13")
        .link("/usr/bin/python3", "python3.13")
        .text("/usr/lib/python3.13/venv/__init__.py")
        .text("/usr/lib/python3.13/ensurepip/__init__.py");
    let out = setup(t.dir.path(), &["--check"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        out.stdout.is_empty(),
        "{:?}",
        String::from_utf8_lossy(&out.stdout)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("setup: python3 is 3.13;") && stderr.contains("need CPython 3.11"),
        "{stderr}"
    );
}

#[test]
fn commands_are_executable_files_in_the_bin_directories() {
    let cases: [(&str, &[&str]); 8] = [
        ("/usr/bin/ip", &["iproute2"]),
        ("/usr/bin/cmake", &["cmake"]),
        ("/usr/bin/make", &["make"]),
        ("/usr/bin/valgrind", &["valgrind"]),
        // `kill` is a shell builtin too, but tests run /usr/bin/kill.
        ("/usr/bin/kill", &["procps"]),
        ("/usr/sbin/nft", &["nftables"]),
        // cc and c++ are links through the alternatives system.
        ("/usr/bin/gcc-12", &["gcc"]),
        ("/usr/bin/g++-12", &["g++"]),
    ];
    for (path, packages) in cases {
        let t = Tree::complete();
        t.remove(path);
        t.assert_missing_for(packages, path);
    }
    // A file that is not executable is no command; one in /sbin is.
    let t = Tree::complete();
    t.remove("/usr/bin/ip").text("/usr/bin/ip");
    t.assert_missing(&["iproute2"]);
    t.remove("/usr/bin/ip").exe("/sbin/ip");
    t.assert_missing(&[]);
    // c++ gone but g++ there (the cmake crate's C++ compiler is c++).
    let t = Tree::complete();
    t.remove("/usr/bin/c++");
    t.assert_missing(&["g++"]);
}

#[test]
fn python_needs_venv_ensurepip_and_its_wheels() {
    let t = Tree::complete();
    t.remove("/usr/lib/python3.11/ensurepip/__init__.py");
    t.assert_missing(&["python3-venv"]);
    let t = Tree::complete();
    t.remove("/usr/share/python-wheels/pip-23.0.1-py3-none-any.whl");
    t.assert_missing(&["python3-pip-whl"]);
    t.remove("/usr/share/python-wheels/setuptools-66.1.1-py3-none-any.whl");
    t.assert_missing(&["python3-pip-whl", "python3-setuptools-whl"]);
    let t = Tree::complete();
    t.remove("/usr/bin/python3");
    t.assert_missing(&["python3", "python3-venv"]);
}

#[test]
fn another_root_is_for_check_only_and_arguments_are_checked() {
    let t = Tree::complete();
    let out = setup(t.dir.path(), &[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is for --check only"));
    let out = setup(t.dir.path(), &["--install-everything"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "usage: scripts/setup [--check] [--build-only]\n"
    );
}

#[test]
fn build_only_asks_for_what_building_needs() {
    // Nothing of the tests' own: no valgrind, no Python, no venv.
    let t = Tree::complete();
    t.remove("/usr/bin/valgrind");
    t.remove("/usr/bin/python3");
    let out = setup(t.dir.path(), &["--check", "--build-only"]);
    assert_eq!(String::from_utf8_lossy(&out.stdout), "");
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    // What building needs is still asked for.
    t.remove("/usr/bin/cmake");
    let out = setup(t.dir.path(), &["--check", "--build-only"]);
    assert_eq!(String::from_utf8_lossy(&out.stdout), "cmake\n");
    assert_eq!(out.status.code(), Some(1));
}
