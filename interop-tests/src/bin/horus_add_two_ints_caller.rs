//! A horus-ros AddTwoInts client in a process of its own, driven line by line on its standard
//! input, for tests that run it on another (simulated) host than the server: it prints `ready`
//! once its client exists, then answers each line:
//!
//! - `wait MS`: waits at most MS ms for a server, prints `found` or `not found`;
//! - `call A B MS`: one call with a timeout of MS ms, prints `sum A <sum>` or `failed A <error>`;
//! - `node NAME MS`: waits at most MS ms until the graph has a node of full name NAME (as
//!   `/doomed_server`) and a server of SERVICE, prints `node NAME seen` or `node NAME unseen`;
//! - `gone NAME MS`: waits at most MS ms until the graph has neither a node of full name NAME
//!   nor a server of SERVICE (a graph loses them one event at a time), prints `node NAME gone`
//!   or `node NAME still there`.
//!
//! It ends when its standard input closes. The backend is `HORUS_ROS_BACKEND`'s, the discovery
//! range `ROS_AUTOMATIC_DISCOVERY_RANGE`'s.
//!
//! usage: horus_add_two_ints_caller DOMAIN SERVICE

use std::io::{BufRead, Write};
use std::time::Duration;

use horus_ros_graph::{Graph, GraphCache};
use horus_ros_services::prelude::*;

/// Whether `graph` has a node of full name `name` (`/ns/name`).
fn has_node(graph: &GraphCache, name: &str) -> bool {
    graph.node_names().iter().any(|node| {
        let full = if node.namespace.ends_with('/') {
            format!("{}{}", node.namespace, node.name)
        } else {
            format!("{}/{}", node.namespace, node.name)
        };
        full == name
    })
}

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
    let graph = Graph::of(&context)?;
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
            ["node", name, ms] => {
                let limit = Duration::from_millis(ms.parse()?);
                if graph.wait_until(limit, |g| {
                    has_node(g, name) && g.count_services(service) > 0
                }) {
                    format!("node {name} seen")
                } else {
                    format!("node {name} unseen")
                }
            }
            ["gone", name, ms] => {
                let limit = Duration::from_millis(ms.parse()?);
                if graph.wait_until(limit, |g| {
                    !has_node(g, name) && g.count_services(service) == 0
                }) {
                    format!("node {name} gone")
                } else {
                    format!("node {name} still there")
                }
            }
            _ => format!("unknown command {line:?}"),
        };
        writeln!(out, "{answer}")?;
        out.flush()?;
    }
    Ok(())
}
