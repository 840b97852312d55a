//! Benchmarks that open DDS participants or Zenoh sessions refuse to run where their traffic
//! could reach a real network: only inside a private network namespace (`scripts/bench`,
//! `scripts/isolated`), where `lo` is the only interface up.

/// Names of interfaces other than `lo` that are up (IFF_UP in `flags`, or operstate `up`).
pub fn non_loopback_interfaces_up() -> std::io::Result<Vec<String>> {
    let mut up = Vec::new();
    for entry in std::fs::read_dir("/sys/class/net")? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == "lo" {
            continue;
        }
        let read = |file: &str| {
            std::fs::read_to_string(entry.path().join(file))
                .map(|s| s.trim().to_owned())
                .unwrap_or_default()
        };
        let flags = u32::from_str_radix(read("flags").trim_start_matches("0x"), 16).unwrap_or(0);
        if flags & 0x1 != 0 || read("operstate") == "up" {
            up.push(name);
        }
    }
    Ok(up)
}

/// Exits (status 2) with a message saying why and how to run it — `run`, the isolated
/// command line — when an interface other than `lo` is up (or the interfaces cannot be read).
pub fn refuse_outside_namespace(bench: &str, run: &str) {
    let why = match non_loopback_interfaces_up() {
        Ok(up) if up.is_empty() => return,
        Ok(up) => format!("network interface(s) up besides lo: {}", up.join(", ")),
        Err(e) => format!("cannot read /sys/class/net to check the interfaces: {e}"),
    };
    eprintln!(
        "{bench}: REFUSING TO RUN: {why}.\n\
         This benchmark opens DDS participants or Zenoh sessions, whose traffic must not leave \
         this machine.\nRun it inside a private network namespace:\n    scripts/bench\nor\n    \
         {run}"
    );
    std::process::exit(2);
}
