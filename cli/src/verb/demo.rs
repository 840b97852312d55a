//! `horus-ros demo`: the README's main job — an add_two_ints server node started in this
//! process, what `service info -v` shows for it, and one call, as a newcomer would try by hand.

use std::time::Duration;

use horus_ros_services::prelude::*;

use crate::session::Session;
use crate::verb::service::info;
use crate::{CliError, Global};

/// Arguments of `horus-ros demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// First addend.
    #[arg(default_value_t = 2, allow_negative_numbers = true)]
    pub a: i64,
    /// Second addend.
    #[arg(default_value_t = 3, allow_negative_numbers = true)]
    pub b: i64,
}

/// Starts the server, shows it, calls it.
pub fn run(global: &Global, args: &DemoArgs) -> Result<(), CliError> {
    let session = Session::join(global)?;
    let server_node = session.context.create_node("add_two_ints_server", "/")?;
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&server_node)
        .name("add_two_ints")
        .on_request(|req| Ok(AddTwoIntsResponse { sum: req.a + req.b }))
        .build()?;
    let client_node = session.context.create_node("add_two_ints_client", "/")?;
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&client_node)
        .name("add_two_ints")
        .build()?;
    if !client.wait_for_service(Duration::from_secs(10)) {
        return Err(CliError::new(
            "the demo's add_two_ints server did not come up within 10 s",
        ));
    }
    println!("$ horus-ros service info /add_two_ints -v");
    print!("{}", info::render(&session.graph, "/add_two_ints", true)?);
    println!();
    println!("$ horus-ros service call /add_two_ints example_interfaces/srv/AddTwoInts '{{a: {}, b: {}}}'", args.a, args.b);
    println!(
        "requester: making request: example_interfaces.srv.AddTwoInts_Request(a={}, b={})",
        args.a, args.b
    );
    println!();
    let reply = client
        .call(
            AddTwoIntsRequest {
                a: args.a,
                b: args.b,
            },
            Duration::from_secs(5),
        )
        .map_err(|e| CliError::new(format!("the demo call failed: {e}")))?;
    println!("response:");
    println!(
        "example_interfaces.srv.AddTwoInts_Response(sum={})",
        reply.sum
    );
    Ok(())
}
