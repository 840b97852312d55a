//! An [`AsyncServiceClient`] inside a periodic loop, the way a node calls a service from its
//! scheduler tick without ever blocking it.
//!
//! ```text
//! cargo run -p horus-ros-services --example async_client_loop
//! ```
//!
//! A slow `AddTwoInts` server (each answer takes 150 ms) runs in the same process on
//! `/slow_add`. A control loop ticks every 20 ms (50 Hz); on each tick it does its own work, then
//! `check()`s its outstanding call without waiting:
//!
//! 1. a call with a 1 s timeout: answered after a few ticks;
//! 2. a call with a 70 ms timeout (between two ticks): the loop notices `is_expired()` and moves on;
//! 3. after the loop, two calls awaited in an `async` block run by a tiny std-only `block_on`
//!    (a `PendingResponse` is a `Future`; tokio or any executor can await it too), and one
//!    `wait()`ed on (the blocking way).

use std::future::Future;
use std::sync::{Arc, Mutex};
use std::task::{Context as TaskContext, Poll, Wake, Waker};
use std::time::Instant;

use horus_ros_services::prelude::*;

/// The control loop's period.
const TICK: Duration = Duration::from_millis(20);

/// How long the server takes to answer.
const SERVER_DELAY: Duration = Duration::from_millis(150);

fn main() -> Result<()> {
    let context = Context::from_env()?;
    let node = context.create_node("async_client_loop", "/")?;

    let _server = ServiceServer::<AddTwoInts>::builder()
        .node(&node)
        .name("slow_add")
        .on_request(|req| {
            std::thread::sleep(SERVER_DELAY); // a slow computation
            Ok(AddTwoIntsResponse { sum: req.a + req.b })
        })
        .build()?;

    let client = AsyncServiceClient::<AddTwoInts>::builder()
        .node(&node)
        .name("slow_add")
        .build()?;

    // The calls the loop makes, one at a time: (a, b, timeout).
    let mut calls = vec![
        (1, 2, Duration::from_secs(1)),
        (3, 4, Duration::from_millis(70)),
    ]
    .into_iter();
    let mut pending: Option<(i64, i64, PendingResponse<AddTwoInts>)> = None;
    let mut work_done = 0u64;
    let start = Instant::now();
    let mut next_tick = start;

    for tick in 0..50 {
        // ---- the tick's own work (a controller update, say) --------------------------------
        work_done += 1;

        // ---- start a call when none is outstanding (never blocks) --------------------------
        if pending.is_none() {
            match calls.next() {
                Some((a, b, timeout)) => {
                    println!("tick {tick:2}: call_async({a} + {b}), timeout {timeout:?}");
                    pending = Some((a, b, client.call_async(AddTwoIntsRequest { a, b }, timeout)));
                }
                None => break,
            }
        }

        // ---- look at the outstanding call (never blocks) -----------------------------------
        if let Some((a, b, call)) = &mut pending {
            if call.is_expired() {
                println!(
                    "tick {tick:2}: {a} + {b} expired (at {:.0?}); giving up on it",
                    start.elapsed()
                );
                // check() now reports the timeout; a reply arriving later is dropped.
                println!("         check() -> {:?}", call.check());
                pending = None;
            } else {
                match call.check() {
                    Ok(Some(response)) => {
                        println!(
                            "tick {tick:2}: {a} + {b} = {} (at {:.0?})",
                            response.sum,
                            start.elapsed()
                        );
                        pending = None;
                    }
                    Ok(None) => println!("tick {tick:2}: still waiting..."),
                    Err(e) => {
                        println!("tick {tick:2}: {a} + {b} failed: {e}");
                        pending = None;
                    }
                }
            }
        }

        next_tick += TICK;
        std::thread::sleep(next_tick.saturating_duration_since(Instant::now()));
    }
    println!("loop done: {work_done} ticks of work, none blocked by a call");

    // ---- awaiting: PendingResponse is a Future ----------------------------------------------
    // (The server still works on the abandoned 3 + 4 for a moment: the first call waits for it.)
    let started = Instant::now();
    let sums = block_on(async {
        let first = client
            .call_async(AddTwoIntsRequest { a: 10, b: 20 }, Duration::from_secs(2))
            .await?;
        let second = client
            .call_async(
                AddTwoIntsRequest {
                    a: first.sum,
                    b: 12,
                },
                Duration::from_secs(2),
            )
            .await?;
        Ok::<_, ServiceError>((first.sum, second.sum))
    })?;
    println!(
        "awaited: 10 + 20 = {}, then {} + 12 = {} (in {:.0?})",
        sums.0,
        sums.0,
        sums.1,
        started.elapsed()
    );

    // ---- or block on one --------------------------------------------------------------------
    let pending = client.call_async(AddTwoIntsRequest { a: 5, b: 8 }, Duration::from_secs(2));
    println!("wait(): 5 + 8 = {}", pending.wait()?.sum);
    Ok(())
}

/// Runs a future to completion on this thread: polls it, and parks until its waker is woken.
/// (Enough for these futures, whose wakers the client's reply thread calls.)
fn block_on<F: Future>(future: F) -> F::Output {
    /// Wakes the blocked thread; `woken` covers a wake-up that comes before `park()`.
    struct ThreadWaker {
        thread: std::thread::Thread,
        woken: Mutex<bool>,
    }
    impl Wake for ThreadWaker {
        fn wake(self: Arc<Self>) {
            *self.woken.lock().unwrap_or_else(|p| p.into_inner()) = true;
            self.thread.unpark();
        }
    }

    let mut future = std::pin::pin!(future);
    let waker_state = Arc::new(ThreadWaker {
        thread: std::thread::current(),
        woken: Mutex::new(false),
    });
    let waker = Waker::from(Arc::clone(&waker_state));
    let mut cx = TaskContext::from_waker(&waker);
    loop {
        if let Poll::Ready(output) = future.as_mut().poll(&mut cx) {
            return output;
        }
        // park() may also return spuriously: then we just poll again.
        let woken =
            std::mem::take(&mut *waker_state.woken.lock().unwrap_or_else(|p| p.into_inner()));
        if !woken {
            std::thread::park();
        }
    }
}
