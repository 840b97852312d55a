//! A node that serves `example_interfaces/srv/AddTwoInts` on `add_two_ints` from its `tick`
//! and, in the same ticks, calls the service named by the parameter `target` (default
//! `/add_two_ints`: here, itself) with the async client — neither ever blocks the loop.
//! `ros2 service call /add_two_ints example_interfaces/srv/AddTwoInts "{a: 2, b: 3}"` works on
//! it, and it calls ROS 2's `add_two_ints_server` just as well.
//!
//! `add_two_ints_node [--count N] [--ros-args …]`: stops after N answers (default: Ctrl+C).

use horus::current::{PendingRequest, ServiceQueue};
use horus::msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse};
use horus::prelude::*;
use horus::ros::{AsyncServiceClient, PendingResponse};
use horus::StopHandle;

struct Adder {
    server: Option<ServiceQueue<AddTwoInts>>,
    client: Option<AsyncServiceClient<AddTwoInts>>,
    pending: Option<(i64, i64, PendingResponse<AddTwoInts>)>,
    next: i64,
    answers: u64,
    limit: Option<u64>,
    stop: StopHandle,
}

impl Node for Adder {
    fn name(&self) -> &str {
        "add_two_ints_node"
    }

    fn init(&mut self) -> Result<()> {
        self.server = Some(horus::current::serve::<AddTwoInts>("add_two_ints")?);
        let target = horus::current::parameter_or("target", "/add_two_ints".to_owned());
        self.client = Some(horus::current::client::<AddTwoInts>(&target)?);
        println!("[INFO] [add_two_ints_node]: serving add_two_ints, calling {target}");
        Ok(())
    }

    fn tick(&mut self) {
        // Serve: answer every request that has arrived.
        if let Some(server) = &self.server {
            while let Some(request) = server.try_recv() {
                let r: &AddTwoIntsRequest = request.request();
                let sum = r.a + r.b;
                println!(
                    "[INFO] [add_two_ints_node]: Incoming request\na: {} b: {}",
                    r.a, r.b
                );
                PendingRequest::respond(request, AddTwoIntsResponse { sum });
            }
        }
        // Call: one request in flight, checked each tick.
        if let Some((a, b, pending)) = &mut self.pending {
            match pending.check() {
                Ok(Some(reply)) => {
                    println!(
                        "[INFO] [add_two_ints_node]: Result of add_two_ints: for {a} + {b} = {}",
                        reply.sum
                    );
                    self.answers += 1;
                    self.pending = None;
                    if self.limit.is_some_and(|l| self.answers >= l) {
                        self.stop.stop();
                    }
                }
                Ok(None) => {}
                Err(err) => {
                    hlog!(warn, "call failed: {}", err);
                    self.pending = None;
                }
            }
        } else if let Some(client) = &mut self.client {
            self.next += 1;
            let (a, b) = (self.next, self.next + 1);
            let pending = client.call_async(AddTwoIntsRequest { a, b }, Duration::from_secs(5));
            self.pending = Some((a, b, pending));
        }
    }
}

fn main() -> Result<()> {
    let args = horus::ros::Arguments::from_process()?.non_ros_args();
    let limit = match args.iter().position(|a| a == "--count") {
        Some(i) => Some(
            args.get(i + 1)
                .and_then(|n| n.parse().ok())
                .ok_or_else(|| Error::config("--count needs a number"))?,
        ),
        None => None,
    };
    let mut sched = Scheduler::new().tick_rate(100_u64.hz());
    let stop = sched.stop_handle();
    sched
        .add(Adder {
            server: None,
            client: None,
            pending: None,
            next: 1,
            answers: 0,
            limit,
            stop,
        })
        .build()?;
    sched.run()
}
