//! [`DynamicServiceClient`] with values: a service type known at run time, called with YAML,
//! JSON and dynamic values against a compiled server (run inside the test network namespace).

use std::time::Duration;

use horus_ros_services::prelude::*;
use horus_ros_services::{
    DynamicCallError, DynamicPart, DynamicServiceClient, DynamicServiceType, ServiceError,
    ServiceType,
};

const WAIT: Duration = Duration::from_secs(10);

#[test]
fn a_run_time_type_is_called_with_yaml_json_and_values() {
    let context = Context::builder().domain_id(97).build().expect("context");
    let node = context.create_node("dynamic_calls", "/").expect("node");
    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name("/dyn_add")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()
        .expect("server");
    let ty = ServiceType::compiled("example_interfaces/srv/AddTwoInts").expect("compiled type");
    let mut client = DynamicServiceClient::builder(ty.clone())
        .name("/dyn_add")
        .node(&node)
        .build()
        .expect("client");
    assert!(client.wait_for_service(WAIT));

    let response = client.call_yaml("{a: 2, b: 3}", WAIT).expect("yaml call");
    assert_eq!(
        ty.response_repr(&response),
        "example_interfaces.srv.AddTwoInts_Response(sum=5)"
    );

    let response = client
        .call_json(&serde_json::json!({"a": 40, "b": 2}), WAIT)
        .expect("json call");
    assert_eq!(response, serde_json::json!({"sum": 42}));

    let request = ty.request_from_yaml("{a: -7}").expect("fill");
    let response = client.call_value(&request, WAIT).expect("value call");
    assert_eq!(
        ty.response_to_json(&response),
        serde_json::json!({"sum": -7})
    );

    // Values that do not fit the type never reach the wire.
    let refused = client.call_json(&serde_json::json!({"c": 1}), WAIT);
    assert!(
        matches!(&refused, Err(DynamicCallError::Request { cause, .. }) if cause.to_string().contains("'c'")),
        "{refused:?}"
    );
    let refused = client.call_yaml("{a: x}", WAIT);
    assert!(
        matches!(refused, Err(DynamicCallError::Request { .. })),
        "{refused:?}"
    );
}

#[test]
fn a_client_without_a_schema_says_so_and_a_failed_call_is_its_service_error() {
    let context = Context::builder().domain_id(98).build().expect("context");
    let node = context.create_node("dynamic_raw", "/").expect("node");
    let ty = ServiceType::compiled("std_srvs/srv/Trigger").expect("compiled type");
    let (request_hash, response_hash) = ty.part_hashes();
    let mut raw = DynamicServiceClient::builder(DynamicServiceType::Parts {
        service_type: ty.name().to_owned(),
        request: DynamicPart {
            dds_type_name: "std_srvs::srv::dds_::Trigger_Request_".to_owned(),
            type_hash: request_hash,
        },
        response: DynamicPart {
            dds_type_name: "std_srvs::srv::dds_::Trigger_Response_".to_owned(),
            type_hash: response_hash,
        },
    })
    .name("/nobody_serves")
    .node(&node)
    .build()
    .expect("client");
    assert!(raw.service_type().is_none());
    assert!(matches!(
        raw.call_yaml("{}", Duration::from_millis(10)),
        Err(DynamicCallError::NoSchema)
    ));

    let mut typed = DynamicServiceClient::builder(ty)
        .name("/nobody_serves")
        .node(&node)
        .build()
        .expect("client");
    let e = typed
        .call_json(&serde_json::json!({}), Duration::from_millis(200))
        .expect_err("no server");
    assert!(
        matches!(e, DynamicCallError::Call(ServiceError::NoServer)),
        "{e:?}"
    );
}
