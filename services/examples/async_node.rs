//! An async node (feature `tokio`): in one tokio runtime it serves a service whose handler awaits
//! a call of another service, follows the graph's changes, and calls that other service as soon
//! as its server appears.
//!
//! ```text
//! cargo run -p horus-ros-services --example add_two_ints_server &   # the other service
//! cargo run -p horus-ros-services --example async_node
//! ros2 service call /async_node/add_three example_interfaces/srv/AddTwoInts "{a: 2, b: 3}"
//! ```
//!
//! - `/async_node/add_three` (AddTwoInts): answers `a + b + 3`, computing `a + b` by awaiting a
//!   call of `/add_two_ints` inside the handler; many requests are handled at once, each a task of
//!   the runtime.
//! - Every graph change is printed as it happens (`graph: node added /add_two_ints_server`),
//!   from `Graph::events()` — a bounded stream that reports what a slow reader missed.
//! - `wait_for_service_async` resolves when `/add_two_ints` is usable; the node then calls it
//!   once (`2 + 3 = 5 from /add_two_ints`).
//!
//! It runs until SIGINT (Ctrl+C) or SIGTERM shuts its context down, then says how much it served
//! and leaves the graph. The domain comes from `ROS_DOMAIN_ID`.

use std::sync::Arc;

use futures_util::StreamExt;
use horus_ros_graph::{Graph, GraphEvent};
use horus_ros_services::prelude::*;

const CALL_TIMEOUT: Duration = Duration::from_secs(5);

#[tokio::main]
async fn main() -> Result<()> {
    let context = Context::from_env()?;
    // Waited on at the end; made first, so that a signal from now on is left to this program
    // (it says goodbye itself) rather than ending the process at once.
    let shutdown = context.wait_for_shutdown_async();
    let node = context.create_node("async_node", "/")?;

    // Graph changes, as they happen.
    let graph = Graph::of(&context).map_err(horus_ros_services::SetupError::from)?;
    let mut events = graph.events();
    let follower = tokio::spawn(async move {
        while let Some(event) = events.next().await {
            match event {
                Ok(GraphEvent::NodeAdded { name, namespace }) => {
                    println!("graph: node added {}", full_name(&namespace, &name));
                }
                Ok(GraphEvent::NodeRemoved { name, namespace }) => {
                    println!("graph: node removed {}", full_name(&namespace, &name));
                }
                Ok(_) => {}
                Err(lagged) => println!("graph: {lagged}"),
            }
        }
    });

    // The other service, shared by the handler's tasks and this one.
    let adder = Arc::new(
        AsyncServiceClient::<AddTwoInts>::builder()
            .node(&node)
            .name("/add_two_ints")
            .build()?,
    );

    // Our service: its handler awaits a call of the other one.
    let server = {
        let adder = Arc::clone(&adder);
        AsyncServiceServer::<AddTwoInts>::builder()
            .node(&node)
            .name("~/add_three")
            .on_request(move |req| {
                let adder = Arc::clone(&adder);
                async move {
                    let sum = adder
                        .call(AddTwoIntsRequest { a: req.a, b: req.b }, CALL_TIMEOUT)
                        .await
                        .map_err(|e| format!("/add_two_ints: {e}"))?;
                    Ok(AddTwoIntsResponse { sum: sum.sum + 3 })
                }
            })
            .build()?
    };
    println!("serving {}", server.name());

    println!("waiting for /add_two_ints");
    while !adder
        .wait_for_service_async(Duration::from_secs(3600))
        .await
    {}
    let reply = adder
        .call(AddTwoIntsRequest { a: 2, b: 3 }, CALL_TIMEOUT)
        .await?;
    println!("2 + 3 = {} from /add_two_ints", reply.sum);

    shutdown.await;
    println!(
        "served {} requests ({} failed); bye",
        server.served_count(),
        server.failed_count()
    );
    drop(server);
    follower.abort();
    Ok(())
}

fn full_name(namespace: &str, name: &str) -> String {
    if namespace.ends_with('/') {
        format!("{namespace}{name}")
    } else {
        format!("{namespace}/{name}")
    }
}
