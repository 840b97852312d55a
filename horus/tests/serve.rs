//! `current::serve`: requests are answered from `tick` without the server's thread waiting for
//! the tick, so a request no tick answers does not hold up other clients, and it ends with an
//! error reply at its timeout. Two contexts (the scheduler's and the clients') inside the test
//! network namespace, on a domain of this test's own; every wait is bounded.

use std::sync::mpsc;
use std::time::Duration;

use horus::current::{PendingRequest, ServiceQueue};
use horus::msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
use horus::prelude::*;
use horus::ros::{Context, ServiceClient};
use horus_ros_services::ServiceError;

const WAIT: Duration = Duration::from_secs(30);
const DOMAIN: u32 = 177;
/// How long the node's server lets a request wait for a tick.
const SERVE_TIMEOUT: Duration = Duration::from_secs(6);
/// The answered client's bound: shorter than `SERVE_TIMEOUT`, so a server thread still waiting
/// for the held request (as before the fix) would make it fail.
const ANSWERED_BOUND: Duration = Duration::from_secs(4);

fn context() -> Context {
    Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("context")
}

/// Serves `add_two_ints`: answers requests with `a >= 0`, holds the others unanswered.
struct Adder {
    server: Option<ServiceQueue<AddTwoInts>>,
    held: Vec<PendingRequest<AddTwoInts>>,
    ready: mpsc::Sender<()>,
    holding: mpsc::Sender<i64>,
}

impl Node for Adder {
    fn name(&self) -> &str {
        "adder"
    }
    fn init(&mut self) -> Result<()> {
        self.server = Some(horus::current::serve_with_timeout::<AddTwoInts>(
            "add_two_ints",
            SERVE_TIMEOUT,
        )?);
        let _ = self.ready.send(());
        Ok(())
    }
    fn tick(&mut self) {
        let Some(server) = &self.server else { return };
        while let Some(request) = server.try_recv() {
            let AddTwoIntsRequest { a, b } = *request.request();
            if a >= 0 {
                request.respond(AddTwoIntsResponse { sum: a + b });
            } else {
                let _ = self.holding.send(a);
                self.held.push(request);
            }
        }
    }
}

#[test]
fn an_unanswered_request_neither_delays_another_client_nor_stalls_its_own() {
    let (ready_tx, ready) = mpsc::channel();
    let (holding_tx, holding) = mpsc::channel();
    let mut sched = Scheduler::new()
        .context(context())
        .tick_rate(100_u64.hz())
        .print_report(false);
    sched
        .add(Adder {
            server: None,
            held: Vec::new(),
            ready: ready_tx,
            holding: holding_tx,
        })
        .build()
        .expect("adder");
    let stop = sched.stop_handle();
    let runner = std::thread::spawn(move || sched.run().map_err(|e| e.to_string()));
    ready.recv_timeout(WAIT).expect("the node serves");

    let clients = context();
    let node = clients.create_node("callers", "/").expect("node");
    let client = || {
        let client = ServiceClient::<AddTwoInts>::builder()
            .node(&node)
            .name("/add_two_ints")
            .build()
            .expect("client");
        assert!(client.wait_for_service(WAIT), "service available");
        client
    };
    let mut unanswered = client();
    let mut answered = client();

    // Client 1: a request the node holds and never answers.
    let (held_tx, held) = mpsc::channel();
    let caller = std::thread::spawn(move || {
        let _ = held_tx.send(unanswered.call(AddTwoIntsRequest { a: -1, b: 0 }, WAIT));
    });
    assert_eq!(holding.recv_timeout(WAIT), Ok(-1), "the node holds it");

    // Client 2, meanwhile: answered by the next tick, well before client 1's request times out.
    let reply = answered
        .call(AddTwoIntsRequest { a: 2, b: 3 }, ANSWERED_BOUND)
        .expect("answered while another request waits");
    assert_eq!(reply.sum, 5);
    assert!(
        held.try_recv().is_err(),
        "client 1 is still waiting for its answer"
    );

    // Client 1 gets an error reply at the server's timeout, not a stall.
    let outcome = held.recv_timeout(WAIT).expect("client 1's call ended");
    match outcome {
        Err(ServiceError::ServiceFailed(message)) => {
            assert!(message.contains("did not answer"), "{message}")
        }
        other => panic!("expected an error reply, got {other:?}"),
    }
    caller.join().expect("caller");

    stop.stop();
    assert_eq!(runner.join().expect("scheduler thread"), Ok(()));
}
