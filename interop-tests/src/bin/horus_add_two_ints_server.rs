//! A horus-ros AddTwoInts server in a process of its own, for tests that kill a server: it
//! prints `ready` once serving, then `handling <a>` when its handler starts on a request, which
//! then takes DELAY_MS before answering. The backend is `HORUS_ROS_BACKEND`'s.
//!
//! usage: horus_add_two_ints_server DOMAIN SERVICE DELAY_MS

use std::io::Write;
use std::time::Duration;

use horus_ros_services::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [domain, service, delay] = args.as_slice() else {
        eprintln!("usage: horus_add_two_ints_server DOMAIN SERVICE DELAY_MS");
        std::process::exit(2);
    };
    let delay = Duration::from_millis(delay.parse()?);
    let context = Context::builder().domain_id(domain.parse()?).build()?;
    let node = context.create_node("doomed_server", "/")?;
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name(service.as_str())
        .on_request(move |req| {
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out, "handling {}", req.a);
            let _ = out.flush();
            drop(out);
            std::thread::sleep(delay);
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()?;
    println!("ready");
    std::io::stdout().flush()?;
    // Serves until killed (or until its standard input closes).
    let _ = std::io::Read::read(&mut std::io::stdin(), &mut [0u8; 1]);
    Ok(())
}
