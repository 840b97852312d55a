//! How long horus-ros-codegen takes on every interface package of the ROS 2 Jazzy wheels, and
//! how long the crate it generates takes to compile, to put one beside the other. Prints
//! figures; asserts nothing about time.
//!
//! (a) Generation: [`Builder::generate`] of the packages in [`PACKAGES`] (from the wheels'
//!     `<venv>/share`, as interop-tests' build.rs does: nothing compiled into horus-ros-msgs is
//!     used, every type is generated), each run into a fresh directory; the median of
//!     `HORUS_ROS_BENCH_RUNS` runs (default 10), with interface files and types per second.
//! (b) Compilation: a throwaway crate in a temporary directory (its own `[workspace]`,
//!     depending on horus-ros-msgs by path, the workspace's Cargo.lock) whose lib.rs includes
//!     the generated `interfaces.rs`; built once to compile its dependencies, then rebuilt after
//!     touching lib.rs, so that only the generated crate compiles: the median of
//!     `HORUS_ROS_BENCH_BUILD_RUNS` rebuilds (default 3), debug then release, and the ratio to
//!     the generation time. Its target directory is in the temporary directory.
//!
//! ```text
//! HORUS_ROS_INTEROP_PYTHON=<venv>/bin/python cargo bench --offline -p horus-ros-codegen --bench generate
//! ```
//!
//! The wheels are found as the tests find them
//! ([`horus_ros_test_support::jazzy::share_dir`]).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::{Duration, Instant, SystemTime};

use horus_ros_codegen::{Builder, Generated};

/// The interface packages of the wheels that are generated.
const PACKAGES: [&str; 20] = [
    "std_msgs",
    "builtin_interfaces",
    "geometry_msgs",
    "sensor_msgs",
    "nav_msgs",
    "diagnostic_msgs",
    "shape_msgs",
    "stereo_msgs",
    "trajectory_msgs",
    "visualization_msgs",
    "actionlib_msgs",
    "std_srvs",
    "rcl_interfaces",
    "lifecycle_msgs",
    "action_msgs",
    "service_msgs",
    "type_description_interfaces",
    "unique_identifier_msgs",
    "rosgraph_msgs",
    "test_msgs",
];

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("generate bench: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let share = horus_ros_test_support::jazzy::share_dir()?;
    let prefix = share.parent().ok_or("the wheels' share has no parent")?;
    let runs = env_number("HORUS_ROS_BENCH_RUNS", 10).max(1);
    let build_runs = env_number("HORUS_ROS_BENCH_BUILD_RUNS", 3).max(1);
    let temp = tempfile::Builder::new()
        .prefix("horus-ros-codegen-bench-")
        .tempdir()
        .map_err(|e| format!("a temporary directory: {e}"))?;

    // (a) Generation.
    let mut times = Vec::new();
    let mut last = None;
    for run in 0..runs {
        let out = temp.path().join(format!("generate-{run}"));
        let builder = PACKAGES.iter().fold(
            Builder::new()
                .ament_prefix_path(false)
                .compiled_types(false)
                .prefix(prefix)
                .out_dir(&out),
            |b, p| b.prefix_package(p),
        );
        let start = Instant::now();
        let generated = builder.generate().map_err(|e| format!("generating: {e}"))?;
        times.push(start.elapsed());
        last = Some((out, generated));
    }
    let (out, generated) = last.ok_or("no run")?;
    let generate = median(&mut times);
    let source = Source::of(&generated)?;
    let files = generated.inputs.len();
    println!(
        "generation: {} packages ({} asked for, others they need), {files} interface files, {} \
         interfaces, {} Rust types (structs), {} lines / {} KiB of Rust",
        generated.packages.len(),
        PACKAGES.len(),
        generated.interfaces,
        source.types,
        source.lines,
        source.bytes / 1024,
    );
    println!(
        "  median of {runs}: {} (min {}, max {}); {:.0} files/s, {:.0} interfaces/s, {:.0} types/s",
        ms(generate),
        ms(times[0]),
        ms(times[times.len() - 1]),
        files as f64 / generate.as_secs_f64(),
        generated.interfaces as f64 / generate.as_secs_f64(),
        source.types as f64 / generate.as_secs_f64(),
    );

    // (b) Compilation of the generated crate.
    let krate = temp.path().join("generated-crate");
    write_crate(&krate, &out)?;
    for (profile, args) in [("debug", &[][..]), ("release", &["--release"][..])] {
        let warm = Instant::now();
        cargo_build(&krate, args)?;
        let warm = warm.elapsed();
        let mut builds = Vec::new();
        for _ in 0..build_runs {
            touch(&krate.join("src/lib.rs"))?;
            let start = Instant::now();
            cargo_build(&krate, args)?;
            builds.push(start.elapsed());
        }
        let build = median(&mut builds);
        println!(
            "cargo build ({profile}): first build, dependencies included, {}; the generated \
             crate alone, median of {build_runs}: {} (min {}, max {}); build / generate = {:.0}",
            ms(warm),
            ms(build),
            ms(builds[0]),
            ms(builds[builds.len() - 1]),
            build.as_secs_f64() / generate.as_secs_f64(),
        );
    }
    Ok(())
}

/// What the generated Rust source holds.
struct Source {
    types: usize,
    lines: usize,
    bytes: usize,
}

impl Source {
    fn of(generated: &Generated) -> Result<Self, String> {
        let mut source = Source {
            types: 0,
            lines: 0,
            bytes: 0,
        };
        for file in generated.packages.values() {
            let text = std::fs::read_to_string(file)
                .map_err(|e| format!("reading {}: {e}", file.display()))?;
            source.types += text.matches("pub struct ").count();
            source.lines += text.lines().count();
            source.bytes += text.len();
        }
        Ok(source)
    }
}

/// A crate of its own (`[workspace]`) whose lib.rs includes what was generated in `out`.
fn write_crate(dir: &Path, out: &Path) -> Result<(), String> {
    // codegen/ is a member of the workspace at its parent.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .ok_or("the workspace root")?;
    let msgs = root.join("msgs");
    let write = |path: PathBuf, text: &str| {
        std::fs::write(&path, text).map_err(|e| format!("writing {}: {e}", path.display()))
    };
    let src = dir.join("src");
    std::fs::create_dir_all(&src).map_err(|e| format!("creating {}: {e}", src.display()))?;
    write(
        dir.join("Cargo.toml"),
        &format!(
            "[package]\nname = \"horus-ros-codegen-bench-generated\"\nversion = \"0.0.0\"\n\
             edition = \"2021\"\npublish = false\n\n[dependencies]\n\
             horus-ros-msgs = {{ path = {:?} }}\n\n[workspace]\n",
            msgs.display().to_string()
        ),
    )?;
    // The workspace's versions of the dependencies (cargo drops what the crate does not use).
    std::fs::copy(root.join("Cargo.lock"), dir.join("Cargo.lock"))
        .map_err(|e| format!("copying Cargo.lock: {e}"))?;
    write(
        src.join("lib.rs"),
        &format!(
            "//! The Jazzy wheels' interfaces, generated by horus-ros-codegen.\n\
             #![allow(missing_docs, clippy::all)]\ninclude!({:?});\n",
            out.join("interfaces.rs").display().to_string()
        ),
    )
}

/// `cargo build --offline` of the crate in `dir`, its target directory inside it.
fn cargo_build(dir: &Path, args: &[&str]) -> Result<(), String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .args(["build", "--offline", "--quiet"])
        .args(args)
        .current_dir(dir)
        .env("CARGO_TARGET_DIR", dir.join("target"))
        .output()
        .map_err(|e| format!("running cargo: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "cargo build {args:?} of the generated crate failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Sets the file's modification time to now, so that cargo compiles its crate again.
fn touch(path: &Path) -> Result<(), String> {
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(SystemTime::now()))
        .map_err(|e| format!("touching {}: {e}", path.display()))
}

/// The median, sorting `times`.
fn median(times: &mut [Duration]) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}

/// The number in the environment variable `name`, else `default`.
fn env_number(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}
