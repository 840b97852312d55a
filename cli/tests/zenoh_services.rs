//! Services on the zenoh backend against the rmw_zenoh peer (`peers/zenoh_rmw_peer.py`: an
//! AddTwoInts server as a queryable with its SS token, and a client with its SC token calling
//! ours with `get`), through our router: `service call` of the peer's server prints its response
//! as on DDS and the request carries our SC token's GID and a sequence number from 1; the
//! peer's call of our server is answered with an attachment echoing its sequence number and
//! GID; `service list -t` / `service info -v` show both; `param list` reads our node's
//! parameters; the peer killed, our client's call fails with a typed error, not a timeout.
//!
//! One test in this binary: our in-process context reads `ZENOH_CONFIG_OVERRIDE` from the
//! process's environment, set once before anything else. Run inside `scripts/isolated`.

mod common;
mod zenoh_common;

use std::time::Duration;

use horus_ros_msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
use horus_ros_services::{
    EndpointBuilder, NodeServices, ServiceClient, ServiceError, ServiceServer, TransportError,
};
use serde_json::Value;
use zenoh_common::{dotted, field, horus, router, session_override, talker, LIMIT};

const PORT: u16 = 17452;
const DOMAIN: u32 = 7;

#[test]
fn services_with_an_rmw_zenoh_peer() {
    std::env::set_var("ZENOH_CONFIG_OVERRIDE", session_override(PORT));
    let _router = router(PORT);
    let context = horus_ros_rmw::Context::builder()
        .backend(horus_ros_rmw::Backend::Zenoh)
        .domain_id(DOMAIN)
        .signal_handler(horus_ros_rmw::SignalHandlerOptions::None)
        .arguments(Default::default())
        .build()
        .expect("a zenoh context");
    let node = context.create_node("horus_server", "/").expect("node");
    let _node_services = NodeServices::start(&node).expect("node services");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name("/horus_add")
        .on_request(|r: AddTwoIntsRequest| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");

    // The peer's client calls ours: one reply, echoing its sequence number and GID.
    let (mut peer, created) = talker(PORT, DOMAIN, &["/horus_add"]);
    let line = peer.line_where("of a reply from our server", |l| l.contains("\"reply\""));
    let reply: Value = serde_json::from_str(&line).expect("JSON");
    let reply = &reply["reply"];
    assert_eq!(
        field(reply, "key"),
        "7/horus_add/example_interfaces::srv::dds_::AddTwoInts_/RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"
    );
    assert_eq!(field(reply, "payload"), "000100000500000000000000", "sum 5");
    assert_eq!(reply["seq"], Value::from(1), "{reply}");
    assert_eq!(field(reply, "gid"), field(&created, "cli_gid"), "{reply}");
    // Our SS token carries the QoS the server asked for (services_default), as rmw_zenoh's.
    assert!(
        reply["server_tokens"][0]
            .as_str()
            .is_some_and(|t| t.ends_with("/::,10:,:,:,,")),
        "{reply}"
    );

    // Our `service call` calls the peer's server, printing as on DDS; the request carries our
    // SC token's GID and sequence number 1.
    let call = horus(
        PORT,
        DOMAIN,
        &[
            "service",
            "call",
            "/add_two_ints",
            "example_interfaces/srv/AddTwoInts",
            "{a: 2, b: 3}",
        ],
    );
    assert!(
        call.ends_with("response:\nexample_interfaces.srv.AddTwoInts_Response(sum=5)\n\n"),
        "{call}"
    );
    let line = peer.line_where("of a request served", |l| l.contains("\"served\""));
    let served: Value = serde_json::from_str(&line).expect("JSON");
    let served = &served["served"];
    assert_eq!(
        (served["a"].as_i64(), served["b"].as_i64()),
        (Some(2), Some(3))
    );
    assert_eq!(served["seq"], Value::from(1), "{served}");
    assert_eq!(served["gid_is_token_hash"], Value::Bool(true), "{served}");
    // The SC token carries the QoS the client asked for (services_default: RELIABLE, VOLATILE,
    // KEEP_LAST 10), not the deeper local history the services layer keeps.
    let client_token = served["client_tokens"][0].as_str().unwrap_or_default();
    assert!(
        client_token.ends_with("/example_interfaces::srv::dds_::AddTwoInts_/RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a/::,10:,:,:,,"),
        "{served}"
    );

    // Both servers and the peer's client on the graph.
    let services = horus(PORT, DOMAIN, &["service", "list", "-t"]);
    for want in [
        "/add_two_ints [example_interfaces/srv/AddTwoInts]",
        "/horus_add [example_interfaces/srv/AddTwoInts]",
        "/horus_server/get_parameters [rcl_interfaces/srv/GetParameters]",
    ] {
        assert!(services.lines().any(|l| l == want), "{want}: {services}");
    }
    let info = horus(PORT, DOMAIN, &["service", "info", "-v", "/horus_add"]);
    assert!(info.contains("Clients count: 1"), "{info}");
    assert!(info.contains("Services count: 1"), "{info}");
    assert!(info.contains("Node name: horus_server"), "{info}");
    assert!(
        info.contains(&format!(
            " - Request Writer : {}",
            dotted(field(&created, "cli_gid"))
        )),
        "the peer's client has the GID of its SC token: {info}"
    );
    let info = horus(PORT, DOMAIN, &["service", "info", "-v", "/add_two_ints"]);
    assert!(info.contains("Services count: 1"), "{info}");
    assert!(info.contains("Node name: talker"), "{info}");

    // Our node's parameter services answer.
    let params = horus(PORT, DOMAIN, &["param", "list", "/horus_server"]);
    assert!(params.lines().any(|l| l == "  use_sim_time"), "{params}");

    // Our client calls the peer's server; the peer killed, the call fails with a typed error.
    let mut client = ServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("/add_two_ints")
        .build()
        .expect("client");
    assert!(client.wait_for_service(LIMIT), "the peer's server");
    let sum = client
        .call(AddTwoIntsRequest { a: 20, b: 22 }, LIMIT)
        .expect("the peer's answer");
    assert_eq!(sum.sum, 42);
    // {a: 0, b: 0} is held unanswered by the peer, which is then killed: the call in flight ends
    // with ServerGone when the peer's SS token goes, and a call made then finds no server.
    let pending = std::thread::spawn(move || {
        let result = client.call(AddTwoIntsRequest { a: 0, b: 0 }, Duration::from_secs(60));
        (client, result)
    });
    peer.line_where("of the held request", |l| {
        l.contains("\"served\"") && l.contains("\"a\": 0")
    });
    peer.kill();
    let (mut client, result) = pending.join().expect("the calling thread");
    assert!(
        matches!(
            result,
            Err(ServiceError::Transport(TransportError::ServerGone))
        ),
        "{result:?}"
    );
    match client.call(AddTwoIntsRequest { a: 1, b: 1 }, Duration::from_secs(3)) {
        Err(ServiceError::NoServer | ServiceError::Transport(TransportError::ServerGone)) => {}
        other => panic!("expected NoServer or ServerGone, got {other:?}"),
    }
}
