//! A horus-ros AddTwoInts client in a process of its own, driven line by line on its standard
//! input, for tests that run it on another (simulated) host than the server: it prints `ready`
//! once its client exists, then answers each line:
//!
//! - `wait MS`: waits at most MS ms for a server, prints `found` or `not found`;
//! - `call A B MS`: one call with a timeout of MS ms, prints `sum A <sum>` or `failed A <error>`.
//!
//! It ends when its standard input closes. The backend is `HORUS_ROS_BACKEND`'s, the discovery
//! range `ROS_AUTOMATIC_DISCOVERY_RANGE`'s.
//!
//! usage: horus_add_two_ints_caller DOMAIN SERVICE

use std::io::{BufRead, Write};
use std::time::Duration;

use horus_ros_services::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [domain, service] = args.as_slice() else {
        eprintln!("usage: horus_add_two_ints_caller DOMAIN SERVICE");
        std::process::exit(2);
    };
    let context = Context::builder().domain_id(domain.parse()?).build()?;
    let node = context.create_node("caller", "/")?;
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name(service.as_str())
        .build()?;
    let mut out = std::io::stdout();
    writeln!(out, "ready")?;
    out.flush()?;
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        let words: Vec<&str> = line.split_whitespace().collect();
        let answer = match words.as_slice() {
            ["wait", ms] => {
                if client.wait_for_service(Duration::from_millis(ms.parse()?)) {
                    "found".to_owned()
                } else {
                    "not found".to_owned()
                }
            }
            ["call", a, b, ms] => {
                let request = AddTwoIntsRequest {
                    a: a.parse()?,
                    b: b.parse()?,
                };
                match client.call(request, Duration::from_millis(ms.parse()?)) {
                    Ok(reply) => format!("sum {a} {}", reply.sum),
                    Err(error) => format!("failed {a} {error}"),
                }
            }
            _ => format!("unknown command {line:?}"),
        };
        writeln!(out, "{answer}")?;
        out.flush()?;
    }
    Ok(())
}
