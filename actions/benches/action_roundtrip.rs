//! Action round-trip benchmark (not a test). Opens DDS participants: run it only inside a private
//! network namespace (`scripts/bench`, or `scripts/isolated cargo bench -p horus-ros-actions
//! --bench action_roundtrip`); the backend is `HORUS_ROS_BACKEND`'s (rustdds by default,
//! `cyclone` with the feature `cyclone`).
//!
//! Server and client in two `Context`s of one process (two DDS participants); measures, after a
//! warm-up each, interleaved in rounds:
//! 1. a service round trip (`ServiceClient::call`, AddTwoInts), the floor an action sits on;
//! 2. a goal round trip: `send_goal` → accepted → `get_result` (an execute callback that succeeds
//!    at once): two service round trips plus the goal's thread;
//! 3. 100 goals in flight: 100 `send_goal_pending`, then 100 `get_result_pending`, all waited
//!    on: the time for the batch, and goals per second.
//!
//! Prints p50 / p99 of each and the goal round trip as a ratio to the service round trip.
//! Environment: `HORUS_BENCH_ACTION_CALLS` (measured round trips per variant and round, default
//! 300), `HORUS_BENCH_ACTION_ROUNDS` (default 5), `HORUS_BENCH_ACTION_BATCHES` (100-goal batches
//! per round, default 3).

use std::time::{Duration, Instant};

use horus_ros_actions::interfaces::test_msgs::action::{Fibonacci, FibonacciGoal, FibonacciResult};
use horus_ros_actions::prelude::*;
use horus_ros_services::prelude::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
use horus_ros_services::{ServiceClient, ServiceServer};

const WAIT: Duration = Duration::from_secs(30);
const WARMUP: usize = 50;
const IN_FLIGHT: usize = 100;

fn env(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted.get(i).copied().unwrap_or_default()
}

fn report(name: &str, mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    let (p50, p99) = (percentile(&samples, 0.5), percentile(&samples, 0.99));
    println!(
        "{name:<28} n={:<6} p50 {:>9.1} us  p99 {:>9.1} us",
        samples.len(),
        p50.as_secs_f64() * 1e6,
        p99.as_secs_f64() * 1e6
    );
    p50
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let calls = env("HORUS_BENCH_ACTION_CALLS", 300);
    let rounds = env("HORUS_BENCH_ACTION_ROUNDS", 5);
    let batches = env("HORUS_BENCH_ACTION_BATCHES", 3);
    let server_context = Context::from_env()?;
    let client_context = Context::from_env()?;
    println!(
        "action round trips on {} (two contexts, one process): {rounds} rounds of {calls} calls, {batches} batches of {IN_FLIGHT} goals",
        server_context
            .backend()
            .map_or_else(|| "a custom backend".to_owned(), |b| format!("{b:?}"))
    );
    let server_node = server_context.create_node("bench_action_server", "/")?;
    let client_node = client_context.create_node("bench_action_client", "/")?;

    let _service = ServiceServer::<AddTwoInts>::builder()
        .node(&server_node)
        .name("/bench_add")
        .on_request(|r| Ok(AddTwoIntsResponse { sum: r.a + r.b }))
        .build()?;
    let mut service_client = ServiceClient::<AddTwoInts>::builder()
        .node(&client_node)
        .name("/bench_add")
        .build()?;
    let _server = ActionServer::<Fibonacci>::builder()
        .node(&server_node)
        .name("/bench_fibonacci")
        .max_active_goals(4 * IN_FLIGHT)
        .execute(|handle| {
            let order = handle.goal().order;
            let _ = handle.succeed(FibonacciResult {
                sequence: vec![order],
            });
        })
        .build()?;
    let client = ActionClient::<Fibonacci>::builder()
        .node(&client_node)
        .name("/bench_fibonacci")
        .build()?;
    if !service_client.wait_for_service(WAIT) || !client.wait_for_server(WAIT) {
        return Err("servers never ready".into());
    }
    let service_call =
        |client: &mut ServiceClient<AddTwoInts>| -> Result<Duration, Box<dyn std::error::Error>> {
            let t = Instant::now();
            let r = client.call(AddTwoIntsRequest { a: 1, b: 2 }, WAIT)?;
            assert_eq!(r.sum, 3);
            Ok(t.elapsed())
        };
    let goal_round_trip = |client: &ActionClient<Fibonacci>,
                           i: i32|
     -> Result<Duration, Box<dyn std::error::Error>> {
        let t = Instant::now();
        let goal = client.send_goal(FibonacciGoal { order: i }, WAIT)?;
        let (state, result) = goal.get_result(WAIT)?;
        assert_eq!((state, result.sequence), (GoalState::Succeeded, vec![i]));
        Ok(t.elapsed())
    };
    for i in 0..WARMUP {
        service_call(&mut service_client)?;
        goal_round_trip(&client, i as i32)?;
    }
    let (mut service, mut goals, mut batch_times) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..rounds {
        for i in 0..calls {
            service.push(service_call(&mut service_client)?);
            goals.push(goal_round_trip(&client, i as i32)?);
        }
        for _ in 0..batches {
            let t = Instant::now();
            let pending: Vec<_> = (0..IN_FLIGHT)
                .map(|i| client.send_goal_pending(FibonacciGoal { order: i as i32 }, WAIT))
                .collect();
            let handles = pending
                .into_iter()
                .map(|p| p.wait())
                .collect::<Result<Vec<_>, _>>()?;
            let results: Vec<_> = handles.iter().map(|h| h.get_result_pending(WAIT)).collect();
            for (i, r) in results.into_iter().enumerate() {
                let (_, result) = r.wait()?;
                assert_eq!(result.sequence, vec![i as i32]);
            }
            batch_times.push(t.elapsed());
        }
    }
    let s = report("service round trip", service);
    let g = report("goal round trip", goals);
    let b = report("100 goals in flight (batch)", batch_times);
    println!(
        "goal round trip / service round trip: {:.2}x (a goal is two service round trips)",
        g.as_secs_f64() / s.as_secs_f64().max(1e-9)
    );
    println!(
        "100 goals in flight: {:.0} goals/s at p50",
        IN_FLIGHT as f64 / b.as_secs_f64().max(1e-9)
    );
    Ok(())
}
